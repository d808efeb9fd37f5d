// What canopy::InSitu costs a simulation on steps where no pipeline runs, next
// to what it saves there (building the grid) and what a step that runs costs.
//
// Opens the given pipeline scripts with --frequency=F (they run at steps 0, F,
// 2F, ...), then for every step calls willExecute() and execute() on a
// synthetic forest, as a simulation would, and reports per kind of step:
// mean, median and maximum wall time of the two calls (the maximum over ranks
// for each step). For comparison it times buildHyperTreeGrid() on the same
// forest: the work an idle step skips.
//
// Usage: mpirun -np N canopy_bench_insitu --script PATH [--script PATH]...
//          [--frequency F] [--steps S] [--max-levels L] [--output DIR]
//          [--time-limit SECONDS]   (InSituOptions::stepTimeLimitSeconds)
//          [--live HOST:PORT]       (InSituOptions::liveUrl; with no viewer there,
//                                    reports what Catalyst Live costs a step)
#include "ForestFingerprint.h"
#include "SyntheticForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/InSitu.h>

#include <mpi.h>
#include <vtkHyperTreeGrid.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <numeric>
#include <string>
#include <vector>

namespace
{

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point since)
{
  return std::chrono::duration<double>(Clock::now() - since).count();
}

struct Summary
{
  double mean = 0;
  double median = 0;
  double maximum = 0;
  std::size_t count = 0;
};

Summary summarize(std::vector<double> values)
{
  Summary s;
  s.count = values.size();
  if (values.empty())
  {
    return s;
  }
  std::sort(values.begin(), values.end());
  s.mean = std::accumulate(values.begin(), values.end(), 0.0) / values.size();
  s.median = values[values.size() / 2];
  s.maximum = values.back();
  return s;
}

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  int rank = 0;
  int size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  std::vector<std::string> scripts;
  int frequency = 50;
  int steps = 201;
  int maxLevels = 7;
  std::string output = "canopy-bench-insitu";
  double timeLimit = 0.0;
  std::string live;
  for (int i = 1; i + 1 < argc; i += 2)
  {
    const std::string key = argv[i];
    if (key == "--script")
      scripts.push_back(argv[i + 1]);
    else if (key == "--frequency")
      frequency = std::stoi(argv[i + 1]);
    else if (key == "--steps")
      steps = std::stoi(argv[i + 1]);
    else if (key == "--max-levels")
      maxLevels = std::stoi(argv[i + 1]);
    else if (key == "--output")
      output = argv[i + 1];
    else if (key == "--time-limit")
      timeLimit = std::stod(argv[i + 1]);
    else if (key == "--live")
      live = argv[i + 1];
  }
  {
    // Each rank holds a slice of a 3D front-refined forest (whole trees).
    canopy::tools::SyntheticForestOptions o;
    o.dimension = 3;
    o.rootsPerAxis = 6;
    o.maxLevels = maxLevels;
    o.cutaway = false;
    o.depthFirstStorage = false;
    canopy::tools::SyntheticForest simulation(o);
    canopy::ForestDescription forest = simulation.description();
    if (rank == 0)
      std::cout << canopy::tools::describeInput(
                       "synthetic 3D, 6^3 roots, " + std::to_string(maxLevels) + " levels", forest)
                << std::endl;
    std::vector<canopy::TreeDescription> mine;
    std::size_t firstSlot = 0;
    std::size_t nodesBefore = 0;
    for (std::size_t t = 0; t < forest.trees.size(); ++t)
    {
      const bool own = static_cast<int>(t * size / forest.trees.size()) == rank;
      if (own && mine.empty())
        firstSlot = nodesBefore;
      if (own)
        mine.push_back(forest.trees[t]);
      nodesBefore += forest.trees[t].numberOfNodes;
    }
    std::size_t myNodes = 0;
    for (const auto& tree : mine)
      myNodes += tree.numberOfNodes;
    forest.trees = mine;
    // Fields: this rank's contiguous range of the (breadth-first) storage.
    std::vector<canopy::FieldDescription> fields;
    for (auto field : forest.fields)
    {
      if (field.centering != canopy::Centering::EveryNode)
        continue;
      field.data = static_cast<const char*>(field.data) + firstSlot * field.tupleStrideBytes;
      field.numberOfTuples = myNodes;
      fields.push_back(field);
    }
    forest.fields = fields;

    // The work an idle step skips: build the grid with every field.
    std::vector<double> build;
    for (int r = 0; r < 5; ++r)
    {
      const auto start = Clock::now();
      auto grid = canopy::buildHyperTreeGrid(forest);
      build.push_back(seconds(start));
    }

    canopy::InSituOptions options;
    for (const auto& path : scripts)
      options.scripts.push_back({path, {"--frequency=" + std::to_string(frequency)}});
    options.outputDirectory = output;
    options.stepTimeLimitSeconds = timeLimit;
    options.liveUrl = live;
    canopy::InSitu insitu(MPI_COMM_WORLD, options);
    std::vector<double> idle;
    std::vector<double> busy;
    std::vector<double> liveExchange; // StepReport::liveSeconds, slowest rank
    std::size_t liveWarnings = 0;
    for (int step = 0; step < steps; ++step)
    {
      MPI_Barrier(MPI_COMM_WORLD);
      const auto start = Clock::now();
      double liveLocal = -1;
      if (insitu.willExecute(step, 0.01 * step))
      {
        const auto report = insitu.execute(step, 0.01 * step, forest);
        liveLocal = live.empty() ? -1 : report.liveSeconds;
        liveWarnings += report.liveWarnings.size();
      }
      double local = seconds(start);
      double liveSlowest = -1;
      MPI_Allreduce(&liveLocal, &liveSlowest, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
      if (liveSlowest >= 0)
        liveExchange.push_back(liveSlowest);
      double slowest = 0;
      MPI_Allreduce(&local, &slowest, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
      (step % frequency == 0 ? busy : idle).push_back(slowest);
    }
    insitu.close();

    long long cells = static_cast<long long>(myNodes);
    long long totalCells = 0;
    MPI_Reduce(&cells, &totalCells, 1, MPI_LONG_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
    if (rank == 0)
    {
      const auto i = summarize(idle);
      const auto b = summarize(busy);
      const auto g = summarize(build);
      std::printf("ranks %d, cells %lld (rank 0: %lld), %zu script(s), frequency %d\n", size,
                  totalCells, cells, scripts.size(), frequency);
      std::printf("| step | steps | mean | median | max |\n|---|---|---|---|---|\n");
      std::printf("| idle (no pipeline due) | %zu | %.1f us | %.1f us | %.1f us |\n", i.count,
                  i.mean * 1e6, i.median * 1e6, i.maximum * 1e6);
      std::printf("| pipelines run (first: import) | %zu | %.1f ms | %.1f ms | %.1f ms |\n",
                  b.count, b.mean * 1e3, b.median * 1e3, b.maximum * 1e3);
      std::printf("| buildHyperTreeGrid alone, rank 0 | %zu | %.1f ms | %.1f ms | %.1f ms |\n",
                  g.count, g.mean * 1e3, g.median * 1e3, g.maximum * 1e3);
      if (!live.empty())
      {
        const auto l = summarize(liveExchange);
        std::printf("| Catalyst Live (%s), of the steps that run | %zu | %.1f us | %.1f us | "
                    "%.1f us |\n",
                    live.c_str(), l.count, l.mean * 1e6, l.median * 1e6, l.maximum * 1e6);
        std::printf("Live warnings on rank 0: %zu\n", liveWarnings);
      }
    }
  }
  MPI_Finalize();
  return 0;
}
