// CollectiveAgreement (adaptor/insitu/CollectiveAgreement.h), through its own
// header, on real MPI ranks (ctest: 2): every rank's failures gathered in rank
// order on every rank; texts gathered on rank 0; per-script states agreed as
// their minimum and maximum over ranks, against an independent all-gather of
// the states; allOf and reduce against closed forms. Then the bounded wait after
// a script call: a rank that comes late but within the limit costs nothing; one
// that comes past the limit is waited for and reported by the ranks that wait,
// and not by itself; one that never comes ends the job (exit code 124) at the limit plus twice the
// grace, in a job of its own (StuckJob.cxx).
#include "CollectiveAgreement.h"
#include "CapturedStderr.h"
#include "JobOutput.h"
#include "SeparateJob.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <random>
#include <regex>
#include <string>
#include <thread>
#include <vector>

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

int ranks()
{
  int value = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &value);
  return value;
}

/// An agreement without a time limit, writing on a JobOutput of its own.
class CollectiveAgreementTest : public ::testing::Test
{
protected:
  JobOutput Output;
  CollectiveAgreement Agreement{MPI_COMM_WORLD, Output, 0.0, 0.0};
};

TEST_F(CollectiveAgreementTest, FailuresOfEveryRankInRankOrderOnEveryRank)
{
  EXPECT_EQ(Agreement.rank(), rank());
  EXPECT_TRUE(Agreement.gatherFailures("").empty());
  // The last rank fails.
  const int last = ranks() - 1;
  const auto one = Agreement.gatherFailures(rank() == last ? "disk full" : "");
  EXPECT_EQ(one, std::vector<std::string>{"rank " + std::to_string(last) + ", disk full"});
  // Every rank, with messages of different lengths and any bytes (a NUL, not UTF-8).
  std::vector<std::string> expected;
  for (int r = 0; r < ranks(); ++r)
  {
    expected.push_back("rank " + std::to_string(r) + ", " + std::string(r + 1, 'x') +
                       std::string("\0\xff", 2) + std::to_string(r));
  }
  const std::string mine = expected[rank()].substr(expected[rank()].find(", ") + 2);
  EXPECT_EQ(Agreement.gatherFailures(mine), expected);
  // Every rank but the first.
  const auto others = Agreement.gatherFailures(rank() == 0 ? "" : "step 3: late");
  EXPECT_EQ(others.size(), static_cast<std::size_t>(ranks() - 1));
  for (std::size_t k = 0; k < others.size(); ++k)
  {
    EXPECT_EQ(others[k], "rank " + std::to_string(k + 1) + ", step 3: late");
  }
}

TEST_F(CollectiveAgreementTest, TextsGatheredOnRankZeroOnly)
{
  const auto texts = Agreement.gatherOnRoot("text of rank " + std::to_string(rank()));
  if (rank() == 0)
  {
    ASSERT_EQ(texts.size(), static_cast<std::size_t>(ranks()));
    for (int r = 0; r < ranks(); ++r)
    {
      EXPECT_EQ(texts[r], "text of rank " + std::to_string(r));
    }
  }
  else
  {
    EXPECT_TRUE(texts.empty());
  }
}

TEST_F(CollectiveAgreementTest, StatesAgreedAsTheirMinimumAndMaximumOverRanks)
{
  // Random states per rank and script, many rounds; the reference gathers every
  // rank's states (MPI_Allgather) and takes the minimum and maximum itself.
  std::mt19937 random(static_cast<unsigned>(17 + rank()));
  std::uniform_int_distribution<int> state(0, 2);
  for (int round = 0; round < 40; ++round)
  {
    const std::size_t scripts = static_cast<std::size_t>(round % 6);
    std::vector<ScriptState> local(scripts);
    std::vector<int> localInts(scripts);
    for (std::size_t i = 0; i < scripts; ++i)
    {
      localInts[i] = state(random);
      local[i] = static_cast<ScriptState>(localInts[i]);
    }
    std::vector<int> all(scripts * static_cast<std::size_t>(ranks()));
    MPI_Allgather(localInts.data(), static_cast<int>(scripts), MPI_INT, all.data(),
                  static_cast<int>(scripts), MPI_INT, MPI_COMM_WORLD);
    const CollectiveAgreement::States agreed = Agreement.agree(local);
    ASSERT_EQ(agreed.minimum.size(), scripts);
    ASSERT_EQ(agreed.maximum.size(), scripts);
    for (std::size_t i = 0; i < scripts; ++i)
    {
      int lo = 2;
      int hi = 0;
      for (int r = 0; r < ranks(); ++r)
      {
        lo = std::min(lo, all[static_cast<std::size_t>(r) * scripts + i]);
        hi = std::max(hi, all[static_cast<std::size_t>(r) * scripts + i]);
      }
      EXPECT_EQ(agreed.minimum[i], static_cast<ScriptState>(lo)) << "round " << round;
      EXPECT_EQ(agreed.maximum[i], static_cast<ScriptState>(hi)) << "round " << round;
    }
  }
}

TEST_F(CollectiveAgreementTest, AllOfAndReductions)
{
  EXPECT_TRUE(Agreement.allOf(true));
  EXPECT_FALSE(Agreement.allOf(rank() != ranks() - 1));
  EXPECT_FALSE(Agreement.allOf(false));
  const int n = ranks();
  const double r = rank();
  const double triangle = n * (n - 1) / 2.0;
  EXPECT_EQ(Agreement.reduce({r, 1.5, -r}, MPI_SUM),
            (std::vector<double>{triangle, 1.5 * n, -triangle}));
  EXPECT_EQ(Agreement.reduce({r, 1.5, -r}, MPI_MIN), (std::vector<double>{0, 1.5, 1.0 - n}));
  EXPECT_EQ(Agreement.reduce({r, 1.5, -r}, MPI_MAX), (std::vector<double>{n - 1.0, 1.5, 0}));
  EXPECT_TRUE(Agreement.reduce({}, MPI_SUM).empty());
}

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Both ranks start a script call together; the last rank comes to the
/// agreement after it `lateSeconds` later than the others. Returns what each
/// rank wrote on its job output; `result` and `waited` are this rank's.
std::string agreeWithALateRank(double limit, double grace, double lateSeconds,
                               const std::string& localFailure, std::vector<std::string>& result,
                               double& waited)
{
  CapturedStderr captured;
  std::string text;
  {
    const JobOutput output; // writes into the capture
    const CollectiveAgreement agreement(MPI_COMM_WORLD, output, limit, grace);
    MPI_Barrier(MPI_COMM_WORLD);
    const CollectiveAgreement::After after{
        "the script '/scripts/a.py' (catalyst_execute) at step 4", Clock::now(), 0.0};
    if (rank() == ranks() - 1)
    {
      std::this_thread::sleep_for(std::chrono::duration<double>(lateSeconds));
    }
    const auto arrived = Clock::now();
    result = agreement.gatherFailures(localFailure, &after, localFailure.empty() ? "" : "detail");
    waited = secondsSince(arrived);
  }
  captured.restore();
  return captured.text();
}

TEST(CollectiveAgreementAfterAScriptCall, ALateRankWithinTheLimitCostsNothing)
{
  std::vector<std::string> result;
  double waited = 0;
  const std::string said = agreeWithALateRank(2.0, 1.0, 0.3, "", result, waited);
  EXPECT_TRUE(result.empty());
  EXPECT_EQ(said, "");
  if (rank() != ranks() - 1)
  {
    EXPECT_GE(waited, 0.25) << "it waited for the late rank";
  }
}

TEST(CollectiveAgreementAfterAScriptCall, ARankPastTheLimitIsWaitedForAndReported)
{
  // Limit 0.2 s, grace 1 s: the ranks that wait say so at 0.7 s, and would end
  // the job at 2.2 s; the last rank comes at 1.2 s. Rank 0's script failed.
  std::vector<std::string> result;
  double waited = 0;
  const std::string failure = "raised an error: ValueError: bad";
  const std::string said =
      agreeWithALateRank(0.2, 1.0, 1.2, rank() == 0 ? failure : "", result, waited);
  EXPECT_EQ(result, std::vector<std::string>{"rank 0, " + failure});
  if (rank() != ranks() - 1)
  {
    EXPECT_GE(waited, 1.1);
    EXPECT_LT(waited, 2.2) << "the job would have been ended";
    std::string expected = "canopy: rank " + std::to_string(rank()) +
                           ", waiting for other ranks to finish the script '/scripts/a.py' "
                           "(catalyst_execute) at step 4: the step time limit (0.2 s) has passed";
    if (rank() == 0)
    {
      expected += "; on this rank: " + failure + "\ndetail";
    }
    EXPECT_EQ(said, expected + "\n");
  }
  else
  {
    // It came when the others were all there: it waited for nobody.
    EXPECT_EQ(said, "");
  }
}

TEST(CollectiveAgreementAfterAScriptCall, ARankThatNeverComesEndsTheJob)
{
  if (rank() != 0)
  {
    return; // one job of its own is enough: rank 0 runs it, the others wait
  }
  const JobResult job = runSeparateJob(
      {CANOPY_MPIEXEC, "--oversubscribe", "-np", "2", CANOPY_STUCK_JOB, "agreement"}, 60);
  ASSERT_TRUE(job.started);
  EXPECT_FALSE(job.timedOut) << job.output;
  EXPECT_EQ(job.exitCode, stuckJobExitCode) << job.output;
  EXPECT_NE(job.output.find("canopy: rank 0, waiting for other ranks to finish the script "
                            "'/scripts/a.py' (catalyst_execute) at step 7: the step time limit "
                            "(0.2 s) has passed\n"),
            std::string::npos)
      << job.output;
  EXPECT_NE(job.output.find("canopy: rank 0, other ranks did not finish the script "
                            "'/scripts/a.py' (catalyst_execute) at step 7 within the step time "
                            "limit (0.2 s) and the grace after it. Ending the job (MPI_Abort).\n"),
            std::string::npos)
      << job.output;
  EXPECT_EQ(job.output.find("nothing ended the job"), std::string::npos) << job.output;
}

} // namespace
} // namespace canopy::testing
