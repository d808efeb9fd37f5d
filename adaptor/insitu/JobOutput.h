// Messages that must reach the job's output from any rank. ParaView turns off
// vtkLogger's stderr on ranks above 0 (and Canopy's failure reports are logged
// by rank 0 only), so what a rank must say on its own (it is stuck, it waits
// for others, the job ends) goes straight to the process's standard error,
// duplicated at open in case something redirects descriptor 2 afterwards.
#pragma once

#include <mpi.h>

#include <string>

namespace canopy
{

/// Exit code of a job that Canopy ends because a rank is stuck (as timeout(1)).
constexpr int stuckJobExitCode = 124;

class JobOutput
{
public:
  JobOutput();
  ~JobOutput();
  JobOutput(const JobOutput&) = delete;
  JobOutput& operator=(const JobOutput&) = delete;

  /// Writes "canopy: <line>\n" in one write (lines of different ranks do not mix).
  void write(const std::string& line) const;

  /// Writes the message, then ends every rank's process: MPI_Abort on `communicator`
  /// with stuckJobExitCode. Safe from any thread.
  [[noreturn]] void endJob(MPI_Comm communicator, const std::string& message) const;

private:
  int Descriptor = -1;
};

} // namespace canopy
