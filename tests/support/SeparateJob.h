// A program run as a job of its own from a test that is itself a rank of an
// MPI job: for what must end a whole job (MPI_Abort), which a test cannot do to
// its own. The child gets the test's environment without the variables through
// which mpirun tells a process it is one of its ranks (OMPI_*, PMIX_*, ...), so
// it starts as a singleton or under an mpirun of its own; it runs in a process
// group of its own, which is killed if it outlives its time.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <string>
#include <vector>

extern char** environ;

namespace canopy::testing
{

struct JobResult
{
  bool started = false;
  bool timedOut = false;
  int exitCode = -1;  ///< -1 when it did not exit (killed by a signal, or not started)
  std::string output; ///< its standard output and error, interleaved
  double seconds = 0;
};

/// Whether `variable` ("NAME=value") tells a process it is a rank of mpirun's job.
inline bool launcherVariable(const char* variable)
{
  for (const char* prefix : {"OMPI_", "PMIX_", "OPAL_", "ORTE_", "PRTE_", "HYDRA_", "PMI_"})
  {
    if (std::strncmp(variable, prefix, std::strlen(prefix)) == 0)
    {
      // Running as root is allowed by these, not a sign of being a rank.
      return std::strncmp(variable, "OMPI_ALLOW_RUN_AS_ROOT", 22) != 0;
    }
  }
  return false;
}

/// Runs `command` (the program's path first), waits up to `timeoutSeconds`.
inline JobResult runSeparateJob(const std::vector<std::string>& command, double timeoutSeconds)
{
  JobResult result;
  std::vector<char*> arguments;
  for (const std::string& word : command)
  {
    arguments.push_back(const_cast<char*>(word.c_str()));
  }
  arguments.push_back(nullptr);
  std::vector<char*> environment;
  for (char** variable = environ; *variable != nullptr; ++variable)
  {
    if (!launcherVariable(*variable))
    {
      environment.push_back(*variable);
    }
  }
  environment.push_back(nullptr);
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0)
  {
    return result;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDERR_FILENO);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attributes, 0);
  const auto start = std::chrono::steady_clock::now();
  pid_t child = -1;
  result.started = posix_spawn(&child, arguments[0], &actions, &attributes, arguments.data(),
                               environment.data()) == 0;
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  close(fds[1]);
  if (!result.started)
  {
    close(fds[0]);
    return result;
  }
  const auto deadline = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                    std::chrono::duration<double>(timeoutSeconds));
  char buffer[4096];
  while (true)
  {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0)
    {
      result.timedOut = true;
      kill(-child, SIGKILL);
      break;
    }
    pollfd readable{fds[0], POLLIN, 0};
    if (poll(&readable, 1, static_cast<int>(left.count())) <= 0)
    {
      continue;
    }
    const ssize_t n = read(fds[0], buffer, sizeof buffer);
    if (n <= 0)
    {
      break; // every writer closed: the job is over
    }
    result.output.append(buffer, static_cast<std::size_t>(n));
  }
  close(fds[0]);
  int status = 0;
  waitpid(child, &status, 0);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

} // namespace canopy::testing
