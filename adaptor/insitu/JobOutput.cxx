#include "JobOutput.h"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>

namespace canopy
{

JobOutput::JobOutput() : Descriptor(dup(STDERR_FILENO)) {}

JobOutput::~JobOutput()
{
  if (this->Descriptor >= 0)
  {
    close(this->Descriptor);
  }
}

void JobOutput::write(const std::string& line) const
{
  const std::string text = "canopy: " + line + "\n";
  const int descriptor = this->Descriptor >= 0 ? this->Descriptor : STDERR_FILENO;
  std::size_t written = 0;
  while (written < text.size())
  {
    const ssize_t n = ::write(descriptor, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR)
    {
      continue;
    }
    if (n <= 0)
    {
      return; // nowhere left to say it
    }
    written += static_cast<std::size_t>(n);
  }
}

void JobOutput::endJob(MPI_Comm communicator, const std::string& message) const
{
  this->write(message);
  MPI_Abort(communicator, stuckJobExitCode);
  std::_Exit(stuckJobExitCode); // MPI_Abort does not return; if it did, do not hang
}

} // namespace canopy
