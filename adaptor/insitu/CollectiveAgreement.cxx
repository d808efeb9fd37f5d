#include "CollectiveAgreement.h"

#include "GatherText.h"

#include <algorithm>
#include <sstream>
#include <thread>

namespace canopy
{

CollectiveAgreement::CollectiveAgreement(MPI_Comm communicator, const JobOutput& output,
                                         double limitSeconds, double graceSeconds)
    : Communicator(communicator), Output(output), LimitSeconds(limitSeconds),
      GraceSeconds(graceSeconds)
{
  MPI_Comm_rank(communicator, &this->Rank);
}

void CollectiveAgreement::maxReduce(std::vector<int>& values, const After* after,
                                    const std::string& localFailure) const
{
  std::vector<int> local = values;
  const int count = static_cast<int>(values.size());
  if (after == nullptr || this->LimitSeconds <= 0.0)
  {
    MPI_Allreduce(local.data(), values.data(), count, MPI_INT, MPI_MAX, this->Communicator);
    return;
  }
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](double s)
  { return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s)); };
  // The watchdog of a rank stuck in the script ends the job at limit + grace
  // with the better message (it knows where it is stuck); this rank says what
  // it knows before that, and ends the job itself only if nobody did.
  const double allowed = this->LimitSeconds + after->extraSeconds;
  // Said only by a rank that has waited itself: one that comes late, when the
  // others are all there, finishes the reduction within a few polls and must
  // not claim to be waiting for them.
  const auto noticeAt = std::max(after->since + seconds(allowed + 0.5 * this->GraceSeconds),
                                 Clock::now() + seconds(0.5 * this->GraceSeconds));
  const auto endAt = after->since + seconds(allowed + 2.0 * this->GraceSeconds);
  MPI_Request request;
  MPI_Iallreduce(local.data(), values.data(), count, MPI_INT, MPI_MAX, this->Communicator,
                 &request);
  bool noticed = false;
  std::ostringstream limit;
  limit << "the step time limit (" << this->LimitSeconds << " s)";
  const std::string rankText = "rank " + std::to_string(this->Rank) + ", ";
  for (int polls = 0;; ++polls)
  {
    int done = 0;
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done)
    {
      return;
    }
    const auto now = Clock::now();
    if (!noticed && now >= noticeAt)
    {
      noticed = true;
      this->Output.write(rankText + "waiting for other ranks to finish " + after->what + ": " +
                         limit.str() + " has passed" +
                         (localFailure.empty() ? "" : "; on this rank: " + localFailure));
    }
    if (now >= endAt)
    {
      this->Output.endJob(this->Communicator,
                          rankText + "other ranks did not finish " + after->what + " within " +
                              limit.str() + " and the grace after it. Ending the job (MPI_Abort).");
    }
    if (polls > 1000)
    {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  }
}

std::vector<std::string> CollectiveAgreement::gatherFailures(const std::string& localFailure,
                                                             const After* after,
                                                             const std::string& localDetail) const
{
  std::vector<int> anyFailed{localFailure.empty() ? 0 : 1};
  this->maxReduce(anyFailed, after,
                  localDetail.empty() ? localFailure : localFailure + "\n" + localDetail);
  if (!anyFailed[0])
  {
    return {};
  }
  const std::vector<std::string> texts = gatherTextsToAll(this->Communicator, localFailure);
  std::vector<std::string> failures;
  for (std::size_t rank = 0; rank < texts.size(); ++rank)
  {
    if (!texts[rank].empty())
    {
      failures.push_back("rank " + std::to_string(rank) + ", " + texts[rank]);
    }
  }
  return failures;
}

bool CollectiveAgreement::allOf(bool local) const
{
  int value = local ? 1 : 0;
  int every = 0;
  MPI_Allreduce(&value, &every, 1, MPI_INT, MPI_MIN, this->Communicator);
  return every == 1;
}

std::vector<double> CollectiveAgreement::reduce(std::vector<double> values, MPI_Op operation) const
{
  std::vector<double> reduced(values.size());
  MPI_Allreduce(values.data(), reduced.data(), static_cast<int>(values.size()), MPI_DOUBLE,
                operation, this->Communicator);
  return reduced;
}

std::vector<std::string> CollectiveAgreement::gatherOnRoot(const std::string& local) const
{
  return gatherTextsToRoot(this->Communicator, local, 0);
}

CollectiveAgreement::States CollectiveAgreement::agree(const std::vector<ScriptState>& local,
                                                       const After* after) const
{
  // One reduction for both: the minimum is the negated maximum of the negations.
  const std::size_t count = local.size();
  std::vector<int> both(2 * count);
  for (std::size_t i = 0; i < count; ++i)
  {
    both[i] = static_cast<int>(local[i]);
    both[count + i] = -static_cast<int>(local[i]);
  }
  this->maxReduce(both, after, {});
  States agreed{std::vector<ScriptState>(count), std::vector<ScriptState>(count)};
  for (std::size_t i = 0; i < count; ++i)
  {
    agreed.maximum[i] = static_cast<ScriptState>(both[i]);
    agreed.minimum[i] = static_cast<ScriptState>(-both[count + i]);
  }
  return agreed;
}

} // namespace canopy
