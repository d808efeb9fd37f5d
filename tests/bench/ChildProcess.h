// A measurement run in a child process: VTK 9.2's hypertree filters may abort on an
// assertion (Debian builds VTK with them on), and a benchmark reports that route as
// failed instead of dying with it. Used by the slice and block forest benchmarks.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <functional>
#include <string>

namespace canopy::bench
{

/// Runs `run` in a child process and returns what it printed on its pipe, or ""
/// when it died.
inline std::string inChild(const std::function<std::string()>& run)
{
  int fds[2];
  if (pipe(fds) != 0)
    return "";
  const pid_t child = fork();
  if (child == 0)
  {
    close(fds[0]);
    const std::string text = run();
    const ssize_t written = write(fds[1], text.data(), text.size());
    _exit(written == static_cast<ssize_t>(text.size()) ? 0 : 1);
  }
  close(fds[1]);
  std::string text;
  char buffer[256];
  ssize_t n = 0;
  while ((n = read(fds[0], buffer, sizeof buffer)) > 0)
    text.append(buffer, static_cast<std::size_t>(n));
  close(fds[0]);
  int status = 0;
  waitpid(child, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? text : "";
}

} // namespace canopy::bench
