// StepWatchdog (adaptor/insitu/StepWatchdog.h), through its own header, on each
// MPI rank (it is not collective; the rank it names is the one it is given): a
// fast call raises no alarm; a call that overruns a short limit is marked
// exceeded no earlier than the limit, is interrupted on the thread that made it
// (the interrupt signal, here handled by the test instead of Python), and the
// interrupt message is taken once and only for that call; a rank done with the
// script and waiting past the limit says so on the job's output, naming rank,
// step, script and call; a script's extra seconds move the limit; no limit, no
// thread; the grace in closed form; a call stuck past the grace ends its job
// with exit code 124 and a message naming where it is stuck (a job of its own,
// StuckJob.cxx).
#include "StepWatchdog.h"
#include "CapturedStderr.h"
#include "JobOutput.h"
#include "SeparateJob.h"

#include <gtest/gtest.h>
#include <mpi.h>
#include <pthread.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <string>
#include <thread>
#include <tuple>

namespace canopy::testing
{
namespace
{

int rank()
{
  int value = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &value);
  return value;
}

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void sleepSeconds(double seconds)
{
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
}

/// The interrupt signal caught by the test while it lives: how many arrived,
/// and whether each arrived on the thread that made this (the calling thread).
class InterruptCounter
{
public:
  InterruptCounter()
  {
    Count = 0;
    Elsewhere = 0;
    Caller = pthread_self();
    struct sigaction action = {};
    action.sa_handler = [](int)
    {
      Count.fetch_add(1);
      if (!pthread_equal(pthread_self(), Caller))
      {
        Elsewhere.fetch_add(1);
      }
    };
    sigemptyset(&action.sa_mask);
    sigaction(StepWatchdog::interruptSignal, &action, &Previous);
  }
  ~InterruptCounter() { sigaction(StepWatchdog::interruptSignal, &Previous, nullptr); }
  InterruptCounter(const InterruptCounter&) = delete;
  InterruptCounter& operator=(const InterruptCounter&) = delete;

  int count() const { return Count.load(); }
  int elsewhere() const { return Elsewhere.load(); }

private:
  static std::atomic<int> Count;
  static std::atomic<int> Elsewhere;
  static pthread_t Caller;
  struct sigaction Previous = {};
};

std::atomic<int> InterruptCounter::Count{0};
std::atomic<int> InterruptCounter::Elsewhere{0};
pthread_t InterruptCounter::Caller{};

/// Waits up to `seconds` for `condition`.
template <typename Condition>
bool within(double seconds, Condition&& condition)
{
  const auto start = Clock::now();
  while (!condition())
  {
    if (secondsSince(start) > seconds)
    {
      return false;
    }
    sleepSeconds(0.01);
  }
  return true;
}

TEST(StepWatchdog, AFastCallRaisesNoAlarm)
{
  CapturedStderr captured;
  const InterruptCounter interrupts;
  {
    const JobOutput output;
    StepWatchdog watchdog(0.3, rank(), MPI_COMM_WORLD, output);
    watchdog.useSignal(true);
    for (int step = 0; step < 20; ++step)
    {
      const auto watch =
          watchdog.watch("/scripts/fast.py", "catalyst_execute", "step " + std::to_string(step));
      watchdog.noteWaiting("succeeded");
      EXPECT_FALSE(watch.exceeded());
    }
    sleepSeconds(0.5); // past the limit of the last call, which has ended
    EXPECT_EQ(StepWatchdog::takeInterrupt(), "");
  }
  EXPECT_EQ(interrupts.count(), 0);
  EXPECT_EQ(captured.text(), "");
}

TEST(StepWatchdog, AnOverrunningCallIsInterruptedOnItsThreadAndReported)
{
  CapturedStderr captured;
  const InterruptCounter interrupts;
  const JobOutput output;
  StepWatchdog watchdog(0.2, rank(), MPI_COMM_WORLD, output);
  watchdog.useSignal(true);
  {
    const auto start = Clock::now();
    const auto watch = watchdog.watch("/scripts/slow.py", "catalyst_execute", "step 4");
    ASSERT_TRUE(within(5, [&] { return watch.exceeded(); }));
    EXPECT_GE(secondsSince(start), 0.2) << "exceeded before the limit";
    ASSERT_TRUE(within(5, [&] { return interrupts.count() > 0; }));
    EXPECT_EQ(interrupts.elsewhere(), 0) << "interrupted another thread";
    // What Python raises in the script: once.
    EXPECT_EQ(StepWatchdog::takeInterrupt(),
              "exceeded the step time limit (0.2 s) and was interrupted");
    EXPECT_EQ(StepWatchdog::takeInterrupt(), "");
    // Done with the script here, now waiting for the other ranks: said at once.
    watchdog.noteWaiting("raised an error: StepTimeLimitExceeded");
    const std::string expected = "canopy: rank " + std::to_string(rank()) +
                                 ", step 4: waiting for the other ranks to finish the script "
                                 "'/scripts/slow.py' (catalyst_execute); on this rank it raised "
                                 "an error: StepTimeLimitExceeded; the step time limit (0.2 s) "
                                 "has passed\n";
    EXPECT_TRUE(within(2, [&] { return captured.text() == expected; })) << captured.text();
    EXPECT_LT(secondsSince(start), 2.2) << "too slow to tell: the job would end now";
  }
  // The call has ended: nothing more is said, nothing more interrupted.
  const int interrupted = interrupts.count();
  sleepSeconds(0.3);
  EXPECT_EQ(interrupts.count(), interrupted);
  captured.restore();
  EXPECT_EQ(captured.text().find("canopy:", 1), std::string::npos) << captured.text();
}

TEST(StepWatchdog, AnInterruptIsForTheCallItWasMeantFor)
{
  CapturedStderr captured;
  const InterruptCounter interrupts;
  const JobOutput output;
  StepWatchdog watchdog(0.2, rank(), MPI_COMM_WORLD, output);
  watchdog.useSignal(true);
  {
    const auto watch = watchdog.watch("/scripts/slow.py", "catalyst_execute", "step 5");
    ASSERT_TRUE(within(5, [&] { return interrupts.count() > 0; }));
  }
  // The call that was to be interrupted ended before Python took the interrupt:
  // neither after it nor in the next call does it raise.
  EXPECT_EQ(StepWatchdog::takeInterrupt(), "");
  {
    const auto watch = watchdog.watch("/scripts/slow.py", "catalyst_execute", "step 6");
    EXPECT_EQ(StepWatchdog::takeInterrupt(), "");
    EXPECT_FALSE(watch.exceeded());
  }
}

TEST(StepWatchdog, ExtraSecondsMoveTheLimit)
{
  const JobOutput output;
  StepWatchdog watchdog(0.2, rank(), MPI_COMM_WORLD, output);
  const InterruptCounter interrupts;
  watchdog.useSignal(true);
  {
    const auto watch = watchdog.watch("/scripts/first.py", "import", "step 0", 0.6);
    sleepSeconds(0.5);
    EXPECT_FALSE(watch.exceeded()) << "0.5 s of 0.2 + 0.6 s allowed";
    ASSERT_TRUE(within(5, [&] { return watch.exceeded(); }));
  }
  EXPECT_EQ(StepWatchdog::takeInterrupt(), "") << "the call has ended";
  EXPECT_EQ(StepWatchdog::firstStepExtraSeconds, 60.0);
}

TEST(StepWatchdog, WithoutALimitNothingIsWatched)
{
  CapturedStderr captured;
  {
    const JobOutput output;
    StepWatchdog watchdog(0.0, rank(), MPI_COMM_WORLD, output);
    EXPECT_EQ(watchdog.limitSeconds(), 0.0);
    const auto watch = watchdog.watch("/scripts/slow.py", "catalyst_execute", "step 1");
    watchdog.noteWaiting("succeeded");
    sleepSeconds(0.3);
    EXPECT_FALSE(watch.exceeded());
    EXPECT_EQ(StepWatchdog::takeInterrupt(), "");
  }
  EXPECT_EQ(captured.text(), "");
}

TEST(StepWatchdog, TheGraceIsHalfTheLimitWithinOneToTenSeconds)
{
  const JobOutput output;
  for (const auto& [limit, grace, text] :
       {std::tuple<double, double, const char*>{0.2, 1.0, "the step time limit (0.2 s)"},
        {4.0, 2.0, "the step time limit (4 s)"},
        {30.0, 10.0, "the step time limit (30 s)"}})
  {
    const StepWatchdog watchdog(limit, rank(), MPI_COMM_WORLD, output);
    EXPECT_EQ(watchdog.limitSeconds(), limit);
    EXPECT_EQ(watchdog.graceSeconds(), grace);
    EXPECT_EQ(watchdog.limitText(), text);
  }
}

TEST(StepWatchdog, ACallStuckPastTheGraceEndsTheJob)
{
  if (rank() != 0)
  {
    return; // one job of its own is enough: rank 0 runs it
  }
  // Limit 0.2 s, grace 1 s: the job ends about 1.2 s after the call began.
  const JobResult job = runSeparateJob({CANOPY_STUCK_JOB, "watched-call"}, 60);
  ASSERT_TRUE(job.started);
  EXPECT_FALSE(job.timedOut) << job.output;
  EXPECT_EQ(job.exitCode, stuckJobExitCode) << job.output;
  EXPECT_NE(job.output.find("canopy: rank 0, step 4: the script '/scripts/stuck.py' is still in "
                            "catalyst_execute 1 s after the step time limit (0.2 s) and cannot "
                            "be interrupted: it is in C code or waits in an MPI collective (for "
                            "example for a rank whose script failed). Ending the job "
                            "(MPI_Abort).\n"),
            std::string::npos)
      << job.output;
  EXPECT_EQ(job.output.find("nothing ended the job"), std::string::npos) << job.output;
}

} // namespace
} // namespace canopy::testing
