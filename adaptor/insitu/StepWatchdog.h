// The time limit on calls into pipeline scripts (InSituOptions::stepTimeLimitSeconds).
// A thread watches the call the main thread is in. When the limit passes, it
// interrupts the script's Python: a signal to the calling thread, whose Python
// handler raises StepTimeLimitExceeded where the script is, and the call fails
// like any Python error. If the call is still
// running a grace period later, Python cannot get control back there: the rank
// is in C code or waits in an MPI collective inside ParaView (typically for a
// rank whose script failed). Then the watchdog says which rank, script and step
// are stuck on the job's output and ends the job (MPI_Abort) instead of letting
// it hang forever.
#pragma once

#include "JobOutput.h"

#include <mpi.h>
#include <pthread.h>

#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace canopy
{

class StepWatchdog
{
public:
  /// limitSeconds 0: no limit, no thread.
  StepWatchdog(double limitSeconds, int rank, MPI_Comm abortCommunicator, const JobOutput& output);
  ~StepWatchdog();
  StepWatchdog(const StepWatchdog&) = delete;
  StepWatchdog& operator=(const StepWatchdog&) = delete;

  double limitSeconds() const { return LimitSeconds; }
  /// How long after the limit a call that could not be interrupted ends the job.
  double graceSeconds() const { return GraceSeconds; }

  /// One watched call, from construction to destruction (main thread only).
  class Watch
  {
  public:
    ~Watch();
    Watch(const Watch&) = delete;
    Watch& operator=(const Watch&) = delete;
    /// Whether the limit passed during the call (so far).
    bool exceeded() const;

  private:
    friend class StepWatchdog;
    explicit Watch(StepWatchdog* watchdog) : Watchdog(watchdog) {}
    StepWatchdog* Watchdog;
  };

  /// Starts watching: `script` is in `call` ("catalyst_execute") at `when` ("step 4"),
  /// allowed the limit plus `extraSeconds`.
  [[nodiscard]] Watch watch(const std::string& script, const std::string& call,
                            const std::string& when, double extraSeconds = 0.0);

  /// What a script's first step (its import and first run) is allowed beyond the
  /// limit: ParaView loads its Python modules and creates render windows then.
  static constexpr double firstStepExtraSeconds = 60.0;

  /// The signal that interrupts the watched call on the main thread, where
  /// Python handles it (PythonSide::installInterrupt).
  static constexpr int interruptSignal = SIGURG;

  /// Whether Python handles interruptSignal. Without it (the simulation handles
  /// SIGURG itself) interrupting is best effort: a pending call, which Python
  /// runs only once something else wakes its evaluation loop up.
  void useSignal(bool handled);

  /// The message to raise in the script when an interrupt of the running call is
  /// due, else "" (asked from Python on the main thread: _canopy.interrupt_wanted).
  /// An interrupt raises only in the call it was meant for, once.
  static std::string takeInterrupt();

  /// The watched call is done with the script's code on this rank and now
  /// waits for the other ranks; `outcome` says how the script ended here
  /// ("succeeded", "raised an error: ..."). Past the limit this is written on
  /// the job's output at once (the rank stuck elsewhere may end the job first).
  void noteWaiting(const std::string& outcome);

  /// "the step time limit (2 s)"
  std::string limitText() const;

private:
  void run();
  void end();

  double LimitSeconds;
  double GraceSeconds;
  int Rank;
  MPI_Comm AbortCommunicator;
  const JobOutput& Output;

  mutable std::mutex Mutex;
  std::condition_variable Changed;
  bool Stopping = false;
  bool Active = false;
  bool Exceeded = false;
  std::uint64_t Serial = 0;
  std::chrono::steady_clock::time_point Start;
  std::chrono::steady_clock::duration Extra{};
  std::string Script;
  std::string Call;
  std::string When;
  std::string WaitingNote;
  pthread_t Caller{};
  bool UseSignal = false;
  std::thread Thread;
};

} // namespace canopy
