// canopy_miniamr: a miniAMR-style adaptive mesh mini-app that runs Canopy in
// situ. Objects moving through a periodic unit domain drive refinement, a
// conservative finite-volume scheme advects a scalar on the leaves, MPI ranks
// own contiguous ranges of root trees. Every step the simulation hands its own
// arrays to Canopy through the public API (canopy::InSitu), zero-copy; with
// --blocks N, per-leaf blocks of N^d cells instead (a block forest).
// Run with --help for the options (also in docs/miniapp.md).
#include "MiniAppOptions.h"
#include "ResourceLog.h"
#include "Simulation.h"
#include "ZoomedView.h"

#include <canopy/InSitu.h>

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{

/// The default pipelines. 2D: images of the adaptive surface and a zoomed view;
/// 3D: images of three slices through the domain's centre with the blob's
/// isosurface (scalar = 0.5), and of the blob's region (scalar >= 0.5) with the
/// octant towards the camera cut away, so the inside shows. Then a selection of
/// the blob (scalar above 0.5) and full data
/// extracts (the grid as VTKHDF for current ParaView and as the .pvd series
/// ParaView 5.11 opens), from Canopy's pipelines/.
std::vector<canopy::PipelineScript> pipelineScripts(const miniamr::MiniAppOptions& o)
{
  std::vector<canopy::PipelineScript> scripts;
  if (!o.pipelines.empty())
  {
    for (std::size_t i = 0; i < o.pipelines.size(); ++i)
      scripts.push_back({o.pipelines[i], o.pipelineArguments[i]});
    return scripts;
  }
  const std::string dir = CANOPY_MINIAPP_PIPELINES_DIR;
  const std::string every = "--frequency=" + std::to_string(o.imageEvery);
  const std::vector<std::string> image{every,
                                       "--color-by=scalar",
                                       "--fields=scalar",
                                       "--image-size=1024x1024",
                                       "--show-edges=1",
                                       "--pixel-threshold=3"};
  if (o.dimension == 3)
  {
    auto slices = image;
    // The blob's isosurface at the level its region and selection use: the smooth
    // boundary of what region_<step>.png draws as cells. Opaque: a translucent one on
    // several ranks makes ParaView 5.11 redistribute every display's geometry for
    // ordered compositing, and the slices' mesh lines then show its triangles.
    slices.insert(slices.end(),
                  {"--contour-field=scalar", "--contour-values=0.5", "--file-prefix=slices"});
    scripts.push_back({dir + "/slice_image.py", slices});
    auto region = image;
    region.insert(region.end(), {"--select-field=scalar", "--select-range=0.5,1e30",
                                 "--cut-away=octant", "--file-prefix=region"});
    scripts.push_back({dir + "/surface_image.py", region});
  }
  else
  {
    scripts.push_back({dir + "/surface_image.py", image});
    // A zoomed view of the refined region: the surface culls what is outside it and
    // coarsens what recedes from the camera.
    auto zoomed = miniamr::zoomedViewCamera(o);
    if (!zoomed.empty())
    {
      zoomed.insert(zoomed.end(),
                    {every, "--color-by=scalar", "--fields=scalar", "--image-size=1024x768",
                     "--show-edges=1", "--pixel-threshold=5", "--file-prefix=zoom"});
      scripts.push_back({dir + "/surface_image_second_view.py", zoomed});
    }
  }
  scripts.push_back({dir + "/selection_extract.py",
                     {"--frequency=" + std::to_string(o.selectionEvery), "--selection=range",
                      "--value-field=scalar", "--value-range=0.5,1e30"}});
  std::vector<std::string> extracts{"--frequency=" + std::to_string(o.extractEvery),
                                    "--format=both"};
  if (!o.extractTrigger.empty())
    extracts.push_back("--trigger=" + o.extractTrigger);
  if (!o.extractTriggerMode.empty())
    extracts.push_back("--trigger-mode=" + o.extractTriggerMode);
  scripts.push_back({dir + "/data_extracts.py", extracts});
  return scripts;
}

/// "  quads: surface 1234, zoom 56" from what the image scripts measured (their
/// "<prefix> quads"), then "  triangles: slices contour 789" (slice_image.py's
/// "<prefix> contour triangles"); empty when no image was drawn this step.
std::string quadsDrawn(const canopy::StepReport& report)
{
  std::string text;
  for (const std::string suffix : {" quads", " triangles"})
  {
    std::string part;
    for (const auto& [name, value] : report.measures)
    {
      if (name.size() > suffix.size() &&
          name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      {
        part += (part.empty() ? "  " + suffix.substr(1) + ": " : ", ") +
                name.substr(0, name.size() - suffix.size()) + " " +
                std::to_string(static_cast<long long>(value));
      }
    }
    text += part;
  }
  return text;
}

/// "  max(scalar) 0.98, ..." from the step's queries, and the triggers that fired.
std::string queryValues(const canopy::StepReport& report)
{
  std::string text;
  char number[40];
  for (const auto& [name, value] : report.expressions)
  {
    std::snprintf(number, sizeof number, " %.6g", value);
    text += (text.empty() ? "  " : ", ") + name + number;
  }
  for (const auto& fired : report.triggersFired)
    text += "  [" + fired + " triggered]";
  return text;
}

double seconds(std::chrono::steady_clock::time_point since)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  int rank = 0;
  int size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int status = 0;
  try
  {
    miniamr::MiniAppOptions options;
    try
    {
      options = miniamr::parseOptions(argc, argv);
    }
    catch (const std::invalid_argument& error)
    {
      if (rank == 0)
      {
        if (*error.what())
          std::cerr << "canopy_miniamr: " << error.what() << "\n\n";
        std::cerr << miniamr::usage();
      }
      MPI_Finalize();
      return *error.what() ? 2 : 0;
    }

    miniamr::Simulation simulation(options, MPI_COMM_WORLD);
    std::unique_ptr<canopy::InSitu> insitu;
    if (!options.noInSitu)
    {
      canopy::InSituOptions insituOptions;
      insituOptions.scripts = pipelineScripts(options);
      insituOptions.outputDirectory = options.output;
      insituOptions.liveUrl = options.live;
      insituOptions.livePauseLimitSeconds = options.livePauseLimit;
      insituOptions.liveStallSeconds = options.liveStallLimit;
      insituOptions.queries = options.queries;
      insituOptions.fields = {"scalar", "velocity", "level", "rank"};
      insitu = std::make_unique<canopy::InSitu>(MPI_COMM_WORLD, insituOptions);
    }
    const double initialMass = simulation.totalMass();
    if (rank == 0 && !options.quiet)
    {
      std::string blocks;
      if (options.blocks > 0)
      {
        long long cells = simulation.globalLeaves();
        for (int a = 0; a < options.dimension; ++a)
          cells *= options.blocks;
        blocks = ", blocks of " + std::to_string(options.blocks) + "^" +
                 std::to_string(options.dimension) + " cells (" + std::to_string(cells) +
                 " cells in blocks)";
      }
      std::printf("canopy_miniamr: %dD, branch factor %d, %d ranks, %lld leaves, dt %.3g, "
                  "mass %.15g%s\n",
                  options.dimension, options.branchFactor, size,
                  static_cast<long long>(simulation.globalLeaves()), simulation.timeStep(),
                  initialMass, blocks.c_str());
    }

    miniamr::ResourceLog resources(options.resourceLog, rank);
    std::vector<std::unique_ptr<char[]>> planted; // --plant-leak: kept, never freed
    double canopySeconds = 0;
    int pipelineFailures = 0;
    bool untouched = true;
    double worstMassChange = 0;
    for (int step = 0; step <= simulation.plannedSteps(); ++step)
    {
      if (step > 0)
        simulation.advance();
      double canopyStep = 0;
      std::string drawn; // the images' quads against the grid's leaves, when drawn
      if (insitu)
      {
        const auto start = std::chrono::steady_clock::now();
        if (!options.queries.empty() || !options.extractTrigger.empty())
        {
          // Queries every step: execute() runs them (no grid unless a pipeline is due).
          const auto forest = simulation.describeForCanopy();
          const auto report = insitu->execute(simulation.step(), simulation.time(), forest);
          pipelineFailures += static_cast<int>(report.failures.size());
          drawn = quadsDrawn(report) + queryValues(report);
        }
        else if (insitu->willExecute(simulation.step(), simulation.time()))
        {
          if (options.blocks > 0)
            simulation.sampleBlocks(); // collective: every rank is here
          const auto forest = simulation.describeForCanopy();
          const auto before = options.verifyUntouched ? simulation.borrowedArraysChecksum() : 0;
          const auto report = insitu->execute(simulation.step(), simulation.time(), forest);
          pipelineFailures += static_cast<int>(report.failures.size());
          drawn = quadsDrawn(report);
          if (options.verifyUntouched && simulation.borrowedArraysChecksum() != before)
            untouched = false;
        }
        canopyStep = seconds(start);
        canopySeconds += canopyStep;
      }
      const double mass = simulation.totalMass();
      const double change = std::abs(mass - initialMass) / std::abs(initialMass);
      if (!std::isfinite(change))
        throw std::runtime_error("the solution is no longer finite at step " +
                                 std::to_string(simulation.step()) + " (unstable settings?)");
      worstMassChange = std::max(worstMassChange, change);
      const double imbalance = simulation.imbalance();
      double slowestCanopy = 0;
      MPI_Reduce(&canopyStep, &slowestCanopy, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
      if (rank == 0 && !options.quiet)
        std::printf("step %4d  time %.4f  leaves %8lld  nodes %8lld  imbalance %.3f  "
                    "mass change %.2e  canopy %.1f ms%s\n",
                    simulation.step(), simulation.time(),
                    static_cast<long long>(simulation.globalLeaves()),
                    static_cast<long long>(simulation.globalNodes()), imbalance, change,
                    1e3 * slowestCanopy, drawn.c_str());
      std::fflush(stdout);
      if (options.plantLeak > 0)
      {
        planted.emplace_back(new char[static_cast<std::size_t>(options.plantLeak)]);
        std::fill_n(planted.back().get(), options.plantLeak, char(step)); // resident
      }
      resources.record(simulation.step(), simulation.localLeaves());
    }
    if (insitu)
      insitu->close();
    if (!options.dump.empty())
      simulation.dump(options.dump);
    if (!options.exactSolution.empty())
    {
      const auto errors = simulation.errorsAgainstExact();
      // One line of key value pairs, the errors to full precision: refinement
      // studies parse it (tests/miniapp/miniapp_check.py).
      if (rank == 0)
        std::printf("exact: %s level %d leaves %lld h %.10g time %.10g L1 %.15e max %.15e\n",
                    options.exactSolution.c_str(), options.maxLevel,
                    static_cast<long long>(simulation.globalLeaves()),
                    simulation.forest().cellSize(0, options.maxLevel), simulation.time(), errors.l1,
                    errors.max);
    }
    int localUntouched = untouched ? 1 : 0;
    int allUntouched = 0;
    MPI_Allreduce(&localUntouched, &allUntouched, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (rank == 0)
    {
      std::printf("done: %d steps, %lld leaves, worst relative mass change %.2e, "
                  "%d repartition(s), canopy %.2f s, %d pipeline failure(s)\n",
                  simulation.plannedSteps(), static_cast<long long>(simulation.globalLeaves()),
                  worstMassChange, simulation.repartitions(), canopySeconds, pipelineFailures);
      if (options.verifyUntouched)
        std::printf("simulation arrays untouched by Canopy: %s\n", allUntouched ? "yes" : "NO");
    }
    status = allUntouched ? 0 : 1;
  }
  catch (const std::exception& error)
  {
    // The mini-app's own errors may strike one rank between collectives: end
    // the whole job rather than leave the other ranks waiting.
    std::cerr << "canopy_miniamr (rank " << rank << "): " << error.what() << "\n";
    if (size > 1)
      MPI_Abort(MPI_COMM_WORLD, 1);
    status = 1;
  }
  MPI_Finalize();
  return status;
}
