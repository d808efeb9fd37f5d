#include "StepWatchdog.h"

#include "CanopyModule.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>

namespace canopy
{
namespace
{

// Read on the main thread when Python handles the interrupt, possibly after
// the watched call ended (or the watchdog is gone): static storage. An
// interrupt raises only in the call it was meant for, once.
std::atomic<std::uint64_t> interruptibleCall{0};  // the watched call (0: none)
std::atomic<std::uint64_t> requestedInterrupt{0}; // the call the watchdog wants interrupted
std::string interruptMessage;

std::string seconds(double value)
{
  std::ostringstream text;
  text << value << " s";
  return text.str();
}

} // namespace

StepWatchdog::StepWatchdog(double limitSeconds, int rank, MPI_Comm abortCommunicator,
                           const JobOutput& output)
    : LimitSeconds(limitSeconds), GraceSeconds(std::clamp(0.5 * limitSeconds, 1.0, 10.0)),
      Rank(rank), AbortCommunicator(abortCommunicator), Output(output)
{
  if (this->LimitSeconds > 0.0)
  {
    interruptMessage = "exceeded " + this->limitText() + " and was interrupted";
    this->Thread = std::thread([this] { this->run(); });
  }
}

void StepWatchdog::useSignal(bool handled)
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  this->UseSignal = handled;
}

std::string StepWatchdog::takeInterrupt()
{
  const auto requested = requestedInterrupt.exchange(0);
  return requested != 0 && requested == interruptibleCall.load() ? interruptMessage : std::string();
}

StepWatchdog::~StepWatchdog()
{
  if (this->Thread.joinable())
  {
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
      this->Stopping = true;
    }
    this->Changed.notify_all();
    this->Thread.join();
  }
}

std::string StepWatchdog::limitText() const
{
  return "the step time limit (" + seconds(this->LimitSeconds) + ")";
}

StepWatchdog::Watch StepWatchdog::watch(const std::string& script, const std::string& call,
                                        const std::string& when, double extraSeconds)
{
  if (!this->Thread.joinable())
  {
    return Watch(nullptr);
  }
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    this->Active = true;
    this->Exceeded = false;
    this->Serial += 1;
    this->Start = std::chrono::steady_clock::now();
    this->Caller = pthread_self();
    this->Extra = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(extraSeconds));
    this->Script = script;
    this->Call = call;
    this->When = when;
    this->WaitingNote.clear();
    interruptibleCall.store(this->Serial);
  }
  return Watch(this); // no notification: the watchdog polls (calls start on idle steps too)
}

void StepWatchdog::noteWaiting(const std::string& outcome)
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  if (this->Active)
  {
    this->WaitingNote = "waiting for the other ranks to finish the script '" + this->Script +
                        "' (" + this->Call + "); on this rank it " + outcome;
  }
}

void StepWatchdog::end()
{
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    this->Active = false;
    interruptibleCall.store(0);
  }
}

StepWatchdog::Watch::~Watch()
{
  if (this->Watchdog != nullptr)
  {
    this->Watchdog->end();
  }
}

bool StepWatchdog::Watch::exceeded() const
{
  if (this->Watchdog == nullptr)
  {
    return false;
  }
  std::lock_guard<std::mutex> lock(this->Watchdog->Mutex);
  return this->Watchdog->Exceeded;
}

void StepWatchdog::run()
{
  using Clock = std::chrono::steady_clock;
  const auto limit = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(this->LimitSeconds));
  const auto grace = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(this->GraceSeconds));
  std::unique_lock<std::mutex> lock(this->Mutex);
  while (!this->Stopping)
  {
    // Polled: watched calls start and end on every step, and telling this
    // thread each time would cost the idle steps a context switch.
    const auto poll = std::chrono::milliseconds(50);
    const auto limitAt = this->Start + this->Extra + limit;
    if (!this->Active || Clock::now() < limitAt)
    {
      this->Changed.wait_for(lock, poll);
      continue;
    }
    const std::uint64_t serial = this->Serial;
    auto callEnded = [this, serial]
    { return this->Stopping || !this->Active || this->Serial != serial; };
    this->Exceeded = true;
    const std::string where = "rank " + std::to_string(this->Rank) + ", " + this->When + ": ";
    bool noted = false;
    auto nextInterrupt = Clock::now();
    while (!callEnded())
    {
      const auto now = Clock::now();
      if (this->WaitingNote.empty())
      {
        // In the script: interrupt it, and again every second while it goes on
        // (it may have swallowed the exception); past the grace it is stuck
        // where Python cannot get control back.
        if (now >= limitAt + grace)
        {
          this->Output.endJob(this->AbortCommunicator,
                              where + "the script '" + this->Script + "' is still in " +
                                  this->Call + " " + seconds(this->GraceSeconds) + " after " +
                                  this->limitText() +
                                  " and cannot be interrupted: it is in C code or waits in an MPI "
                                  "collective (for example for a rank whose script failed). "
                                  "Ending the job (MPI_Abort).");
        }
        if (now >= nextInterrupt)
        {
          requestedInterrupt.store(serial);
          if (this->UseSignal)
          {
            // Python's handler runs on the main thread when the signal arrives
            // there: it wakes Python's evaluation loop up (and interrupts a
            // sleep), and raises.
            pthread_kill(this->Caller, interruptSignal);
          }
          else
          {
            interruptScriptByPendingCall();
          }
          nextInterrupt = now + std::chrono::seconds(1);
        }
      }
      else
      {
        // Done with the script here, waiting for the others: say so at once
        // (the rank stuck in the script may end the job first), and leave
        // ending the job to that rank, which says where it is stuck, unless it
        // does not.
        if (!noted)
        {
          this->Output.write(where + this->WaitingNote + "; " + this->limitText() + " has passed");
          noted = true;
        }
        if (now >= limitAt + 2 * grace)
        {
          this->Output.endJob(this->AbortCommunicator,
                              where + "the other ranks have not finished the script '" +
                                  this->Script + "' " + seconds(2 * this->GraceSeconds) +
                                  " after " + this->limitText() + ". Ending the job (MPI_Abort).");
        }
      }
      this->Changed.wait_until(lock, now + std::chrono::milliseconds(100), callEnded);
    }
  }
}

} // namespace canopy
