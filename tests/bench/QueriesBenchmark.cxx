// Queries on a simulation's arrays (canopy::runQueries): time per leaf per query on
// one core, the shares of the forest's validation and of the one collective, against
// the goal (< 2 ns per leaf per query on 1e6 leaves, docs/benchmarks.md).
//
//   mpirun -np 1 build/tests/bench/canopy_bench_queries [--roots N] [--levels L] [--runs R]
//
// A 3D synthetic forest refined around a spherical front (tools/SyntheticForest.h),
// stored breadth-first (no slot map) and depth-first (a slot map); fields "density"
// (every node, strided in an array of records) and "pressure" (leaves only, a plain
// array). Prints one markdown row per storage, field and set of queries: the median
// of R runs.
#include "SyntheticForest.h"

#include <canopy/Queries.h>

#include <mpi.h>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

namespace
{

/// This thread's CPU time: on a shared machine, wall time counts the other jobs' turns.
double cpuSeconds()
{
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

/// Median CPU time of `runs` calls (and their median wall time in `wall`).
double medianSeconds(int runs, const std::function<void()>& work, double* wall = nullptr)
{
  std::vector<double> times;
  std::vector<double> walls;
  for (int r = 0; r < runs; ++r)
  {
    const auto start = std::chrono::steady_clock::now();
    const double cpu = cpuSeconds();
    work();
    times.push_back(cpuSeconds() - cpu);
    walls.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(times.begin(), times.end());
  std::sort(walls.begin(), walls.end());
  if (wall != nullptr)
  {
    *wall = walls[walls.size() / 2];
  }
  return times[times.size() / 2];
}

std::vector<canopy::Query> allKinds(const std::string& field)
{
  using canopy::Query;
  return {Query::minimum(field),        Query::maximum(field), Query::count(field, 0.5, 2),
          Query::volume(field, 0.5, 2), Query::sum(field),     Query::mean(field),
          Query::integral(field),       Query::l2Norm(field),  Query::histogram(field, 0, 4, 32),
          Query::nonFinite(field),      Query::cells(field),   Query::count(field, 1, 1.5)};
}

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  int roots = 4;
  int levels = 7;
  int runs = 15;
  for (int i = 1; i + 1 < argc; i += 2)
  {
    if (std::strcmp(argv[i], "--roots") == 0)
      roots = std::atoi(argv[i + 1]);
    else if (std::strcmp(argv[i], "--levels") == 0)
      levels = std::atoi(argv[i + 1]);
    else if (std::strcmp(argv[i], "--runs") == 0)
      runs = std::atoi(argv[i + 1]);
  }
  std::printf("| storage | leaves | field | queries | CPU time (wall) | per leaf | per leaf per "
              "query |\n");
  std::printf("|---|---:|---|---:|---:|---:|---:|\n");
  for (const bool depthFirst : {false, true})
  {
    canopy::tools::SyntheticForestOptions options;
    options.dimension = 3;
    options.rootsPerAxis = roots;
    options.maxLevels = levels;
    options.cutaway = true;
    options.depthFirstStorage = depthFirst;
    const canopy::tools::SyntheticForest forest(options);
    const auto& description = forest.description();
    const double leaves = static_cast<double>(forest.numberOfLeaves());
    const char* storage = depthFirst ? "depth-first (slot map)" : "breadth-first";
    auto row = [&](const char* field, const std::vector<canopy::Query>& queries)
    {
      double wall = 0;
      const double seconds = medianSeconds(
          runs, [&] { canopy::runQueries(MPI_COMM_WORLD, description, queries); }, &wall);
      const double perLeaf = seconds / leaves * 1e9;
      std::printf(
          "| %s | %.3g | %s | %zu | %.2f ms (%.2f ms) | %.2f ns | %s |\n", storage, leaves, field,
          queries.size(), seconds * 1e3, wall * 1e3, perLeaf,
          queries.empty()
              ? "(validation + collective)"
              : (std::to_string(perLeaf / static_cast<double>(queries.size())).substr(0, 4) + " ns")
                    .c_str());
      std::fflush(stdout);
    };
    row("-", {});
    // The floor: a plain sum over the leaves-only array, as a simulation's own loop.
    {
      const auto& pressure = description.fields.back();
      const auto* values = static_cast<const double*>(pressure.data);
      volatile double sink = 0;
      const double seconds =
          medianSeconds(runs,
                        [&]
                        {
                          double sum = 0;
                          for (std::size_t i = 0; i < pressure.numberOfTuples; ++i)
                          {
                            sum += values[i];
                          }
                          sink = sum;
                        });
      (void)sink;
      std::printf("| %s | %.3g | pressure | a plain sum loop | %.2f ms | %.2f ns | |\n", storage,
                  leaves, seconds * 1e3, seconds / leaves * 1e9);
    }
    for (const char* field : {"density", "pressure"})
    {
      row(field, {canopy::Query::maximum(field)});
      row(field, {canopy::Query::maximum(field), canopy::Query::volume(field, 0.5, 2),
                  canopy::Query::mean(field), canopy::Query::histogram(field, 0, 4, 32)});
      row(field, allKinds(field));
    }
  }
  MPI_Finalize();
  return 0;
}
