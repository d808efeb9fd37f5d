// GoogleTest on real MPI ranks for the in-situ driver's components, which use
// MPI's C API on a communicator they are given: every rank runs every test;
// rank 0 reports as usual, the other ranks print only their failures (with
// their rank); a failure on any rank fails the run. With
// CANOPY_TESTS_NEED_CATALYST, ParaView Catalyst runs around all tests, started
// as the driver starts it (CatalystSession): it cannot be started twice in one
// process, and its proxy manager and Python are what those components use.
#include <gtest/gtest.h>
#include <mpi.h>

#ifdef CANOPY_TESTS_NEED_CATALYST
#include "CatalystSession.h"
#endif

#include <cstdio>

namespace
{

class FailuresOfThisRank : public ::testing::EmptyTestEventListener
{
public:
  explicit FailuresOfThisRank(int rank) : Rank(rank) {}
  void OnTestPartResult(const ::testing::TestPartResult& result) override
  {
    if (result.failed())
    {
      std::printf("[rank %d] %s:%d: Failure\n%s\n", Rank,
                  result.file_name() ? result.file_name() : "?", result.line_number(),
                  result.message());
      std::fflush(stdout);
    }
  }

private:
  int Rank;
};

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0)
  {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
    listeners.Append(new FailuresOfThisRank(rank));
  }
  int failed = 0;
  {
#ifdef CANOPY_TESTS_NEED_CATALYST
    const canopy::CatalystSession catalyst(MPI_COMM_WORLD);
    if (!catalyst.started())
    {
      std::printf("[rank %d] ParaView Catalyst did not start\n", rank);
      failed = 1;
    }
    else
#endif
    {
      failed = RUN_ALL_TESTS();
    }
  }
  int anyFailed = failed;
  MPI_Allreduce(&failed, &anyFailed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return anyFailed;
}
