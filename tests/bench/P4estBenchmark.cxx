// What describing a p4est forest for Canopy costs, against one p4est_balance
// of the same forest, in one run: bricks refined at a front to 1e5 .. 1e6+
// quadrants (2D) and octants (3D), then balanced (timed), then described
// (P4estForest/P8estForest with a user-data field, timed) and built into a
// vtkHyperTreeGrid (timed). The best of R repetitions of describe and build.
//
// Usage: mpirun -np N canopy_bench_p4est [--repetitions R] [--2d]
// Prints a Markdown table (rank 0); times are the slowest rank's.
#include "ForestFingerprint.h"
#include <canopy/HtgBuilder.h>
#include <canopy/P4estForest.h>

#include <mpi.h>
#include <p4est_extended.h>
#include <p8est_extended.h>
#include <vtkHyperTreeGrid.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace
{

using Clock = std::chrono::steady_clock;

struct Data
{
  double density;
};

/// Maximum over ranks of a local duration, in milliseconds.
double slowest(Clock::time_point start)
{
  double local = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  double global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return global;
}

int targetLevel = 0;

/// Refine within a thin shell around a circle/sphere (unbalanced on purpose:
/// neighbours of the shell stay coarse until balance).
template <typename Forest, typename Quadrant, int D, int MaxLevel>
int nearShell(Forest* forest, p4est_topidx_t tree, Quadrant* q)
{
  if (q->level >= targetLevel)
  {
    return 0;
  }
  const double* lo =
      forest->connectivity->vertices + 3 * forest->connectivity->tree_to_vertex[tree * (1 << D)];
  const double root = static_cast<double>(1 << MaxLevel);
  const double size = static_cast<double>(1 << (MaxLevel - q->level)) / root;
  std::int32_t xyz[3] = {q->x, q->y, 0};
  if constexpr (D == 3)
  {
    xyz[2] = q->z;
  }
  double squared = 0;
  for (int a = 0; a < D; ++a)
  {
    const double c = lo[a] + (xyz[a] / root) + 0.5 * size - 2.0;
    squared += c * c;
  }
  return std::abs(std::sqrt(squared) - 1.3) < 0.75 * size * std::sqrt(D);
}

template <int D>
struct Run;

template <>
struct Run<2>
{
  static void row(int level, int repetitions, int rank)
  {
    targetLevel = level;
    p4est_connectivity_t* brick = p4est_connectivity_new_brick(4, 4, 0, 0);
    p4est_t* forest = p4est_new_ext(MPI_COMM_WORLD, brick, 0, 2, 1, sizeof(Data), nullptr, nullptr);
    p4est_refine(forest, 1, nearShell<p4est_t, p4est_quadrant_t, 2, P4EST_MAXLEVEL>, nullptr);
    p4est_partition(forest, 0, nullptr);
    const auto before = static_cast<long long>(forest->global_num_quadrants);
    MPI_Barrier(MPI_COMM_WORLD);
    auto start = Clock::now();
    p4est_balance(forest, P4EST_CONNECT_FULL, nullptr);
    const double balance = slowest(start);
    p4est_partition(forest, 0, nullptr);
    report<canopy::P4estForest>(forest, "2D", before, balance, repetitions, rank);
    p4est_destroy(forest);
    p4est_connectivity_destroy(brick);
  }

  template <typename Described, typename Forest>
  static void report(Forest* forest, const char* dimension, long long before, double balance,
                     int repetitions, int rank)
  {
    double describe = 1e300;
    double build = 1e300;
    for (int r = 0; r < repetitions; ++r)
    {
      MPI_Barrier(MPI_COMM_WORLD);
      auto start = Clock::now();
      Described described(forest);
      described.template addUserDataField<double>("density", 0);
      describe = std::min(describe, slowest(start));
      start = Clock::now();
      vtkSmartPointer<vtkHyperTreeGrid> htg = canopy::buildHyperTreeGrid(described.description());
      build = std::min(build, slowest(start));
    }
    if (rank == 0)
    {
      Described described(forest);
      described.template addUserDataField<double>("density", 0);
      std::cout << canopy::tools::describeInput(std::string(dimension) + ", rank 0's part",
                                                described.description())
                << std::endl;
      std::printf("| %s | %lld | %lld | %.1f | %.1f | %.1f | %.1fx | %.1fx |\n", dimension, before,
                  static_cast<long long>(forest->global_num_quadrants), balance, describe, build,
                  balance / describe, balance / (describe + build));
      std::fflush(stdout);
    }
  }
};

template <>
struct Run<3>
{
  static void row(int level, int repetitions, int rank)
  {
    targetLevel = level;
    p8est_connectivity_t* brick = p8est_connectivity_new_brick(4, 4, 4, 0, 0, 0);
    p8est_t* forest = p8est_new_ext(MPI_COMM_WORLD, brick, 0, 1, 1, sizeof(Data), nullptr, nullptr);
    p8est_refine(forest, 1, nearShell<p8est_t, p8est_quadrant_t, 3, P8EST_MAXLEVEL>, nullptr);
    p8est_partition(forest, 0, nullptr);
    const auto before = static_cast<long long>(forest->global_num_quadrants);
    MPI_Barrier(MPI_COMM_WORLD);
    auto start = Clock::now();
    p8est_balance(forest, P8EST_CONNECT_FULL, nullptr);
    const double balance = slowest(start);
    p8est_partition(forest, 0, nullptr);
    Run<2>::report<canopy::P8estForest>(forest, "3D", before, balance, repetitions, rank);
    p8est_destroy(forest);
    p8est_connectivity_destroy(brick);
  }
};

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  int repetitions = 3;
  bool only2D = false;
  for (int i = 1; i < argc; ++i)
  {
    if (std::strcmp(argv[i], "--repetitions") == 0 && i + 1 < argc)
    {
      repetitions = std::max(1, std::atoi(argv[i + 1]));
    }
    only2D = only2D || std::strcmp(argv[i], "--2d") == 0;
  }
  int rank = 0;
  int size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  sc_init(MPI_COMM_WORLD, 1, 1, nullptr, SC_LP_ERROR);
  p4est_init(nullptr, SC_LP_ERROR);
  if (rank == 0)
  {
    std::printf("%d rank(s); ms, slowest rank; describe = P4estForest + one user-data field\n\n",
                size);
    std::printf("| dim | quadrants before balance | after | p4est_balance ms | describe ms | "
                "build ms | balance / describe | balance / (describe + build) |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
  }
  for (int level : {10, 12, 14})
  {
    Run<2>::row(level, repetitions, rank);
  }
  for (int level : {6, 7})
  {
    if (only2D)
    {
      break;
    }
    Run<3>::row(level, repetitions, rank);
  }
  sc_finalize();
  MPI_Finalize();
  return 0;
}
