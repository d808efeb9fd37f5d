// The in-situ driver's collective agreement: every decision that leads into a
// collective (building, running a pipeline) is taken by all ranks together,
// so a problem on one rank makes every rank skip instead of leaving the
// others waiting. The agreement has its own communicator, apart from
// ParaView's, so it can never be matched against a collective inside ParaView.
#pragma once

#include "JobOutput.h"

#include <mpi.h>

#include <chrono>
#include <string>
#include <vector>

namespace canopy
{

/// What a script is at a step on one rank. Ordered: the maximum over ranks is
/// the worst (one rank failed: Failed), the minimum tells whether all agree.
enum class ScriptState : int
{
  NotDue = 0,
  Due = 1,
  Failed = 2
};

class CollectiveAgreement
{
public:
  /// With a time limit (> 0), an agreement that follows a script call
  /// (`After`) does not wait forever for a rank that never arrives.
  CollectiveAgreement(MPI_Comm communicator, const JobOutput& output, double limitSeconds,
                      double graceSeconds);

  /// The script call the ranks agree after, and when this rank started it.
  struct After
  {
    std::string what; ///< "the script '...' (catalyst_execute) at step 4"
    std::chrono::steady_clock::time_point since;
    double extraSeconds = 0.0; ///< allowed beyond the limit (a script's first step)
  };

  /// Every rank's failure message (empty on ranks that succeeded), as
  /// "rank R, message", in rank order; empty when all succeeded. Collective.
  /// Cost when nothing failed: one MPI_Allreduce of an int.
  /// With `after`, a rank that waits past the limit writes its own failure and
  /// `localDetail` (its traceback) on the job's output.
  std::vector<std::string> gatherFailures(const std::string& localFailure,
                                          const After* after = nullptr,
                                          const std::string& localDetail = {}) const;

  /// Every rank's text on rank 0 (index: rank; empty elsewhere). Collective.
  std::vector<std::string> gatherOnRoot(const std::string& local) const;

  /// Per-script states agreed across ranks (minimum and maximum). Collective.
  struct States
  {
    std::vector<ScriptState> minimum;
    std::vector<ScriptState> maximum;
  };
  States agree(const std::vector<ScriptState>& local, const After* after = nullptr) const;

  /// Whether `local` holds on every rank. Collective.
  bool allOf(bool local) const;

  /// MPI_Allreduce of doubles with `operation`. Collective; blocking (it is
  /// used inside a script call, which the watchdog bounds).
  std::vector<double> reduce(std::vector<double> values, MPI_Op operation) const;

  int rank() const { return Rank; }

private:
  /// MPI_Allreduce(MPI_MAX) of ints; with `after` and a limit, bounded in time:
  /// half the grace past the limit, once it has itself waited half the grace,
  /// this rank says it is waiting (and its own failure), and it ends the job if
  /// the others still have not come at twice the grace past the limit.
  void maxReduce(std::vector<int>& values, const After* after,
                 const std::string& localFailure) const;

  MPI_Comm Communicator;
  const JobOutput& Output;
  double LimitSeconds;
  double GraceSeconds;
  int Rank = 0;
};

} // namespace canopy
