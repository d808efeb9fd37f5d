// Standard error (descriptor 2) redirected into a temporary file while this
// lives, so that a test can read what a component wrote there. Canopy's
// JobOutput duplicates descriptor 2 when it is made: make it inside the capture,
// and it keeps writing into the file after the capture ends.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <stdexcept>
#include <string>

namespace canopy::testing
{

class CapturedStderr
{
public:
  CapturedStderr()
  {
    std::fflush(stderr);
    File = std::tmpfile();
    Saved = dup(STDERR_FILENO);
    if (File == nullptr || Saved < 0 || dup2(fileno(File), STDERR_FILENO) < 0)
    {
      throw std::runtime_error("cannot redirect standard error");
    }
  }
  ~CapturedStderr()
  {
    restore();
    std::fclose(File);
  }
  CapturedStderr(const CapturedStderr&) = delete;
  CapturedStderr& operator=(const CapturedStderr&) = delete;

  /// Standard error back where it was (what was written stays readable).
  void restore()
  {
    if (Saved >= 0)
    {
      std::fflush(stderr);
      dup2(Saved, STDERR_FILENO);
      close(Saved);
      Saved = -1;
    }
  }

  /// Everything written so far.
  std::string text() const
  {
    std::fflush(stderr);
    std::string all;
    char buffer[4096];
    off_t offset = 0;
    ssize_t n = 0;
    while ((n = pread(fileno(File), buffer, sizeof buffer, offset)) > 0)
    {
      all.append(buffer, static_cast<std::size_t>(n));
      offset += n;
    }
    return all;
  }

private:
  std::FILE* File = nullptr;
  int Saved = -1;
};

} // namespace canopy::testing
