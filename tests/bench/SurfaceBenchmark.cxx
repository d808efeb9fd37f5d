// Canopy's adaptive surface against ParaView 5.11's VTK filters, in one run
// (run under Xvfb, tests/support/with_xvfb.sh: it renders). Writes CSV files into the output
// folder:
//   full2d.csv      full-resolution 2D surface vs vtkHyperTreeGridGeometry
//   adaptive2d.csv  view-dependent 2D at 1024x1024 vs vtkAdaptiveDataSetSurfaceFilter
//   surface3d.csv   3D surface vs both upstream filters
// (run time against image error is canopy_bench_accuracy's, AccuracyBenchmark.cxx).
// Besides the synthetic forest, the
// mini-app's own forests at a late step (real data) add rows to the first three
// tables (2D forests to the 2D tables, 3D to the 3D one).
//
// Usage: canopy_bench_surface [--output DIR] [--max-level L] [--quick] [--canopy-only]
//          [--repetitions N] [--data synthetic|miniapp|all]
//          [--miniapp DIM,ROOTS,MAX_LEVEL,STEPS]...
// (--repetitions: median of N steady-state executions; --canopy-only: skip the
// upstream filters, to profile Canopy under callgrind)
#include "ForestFingerprint.h"
#include "MiniAppForest.h"
#include "OffscreenRenderer.h"
#include "SyntheticForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>

#include <vtkAdaptiveDataSetSurfaceFilter.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridGeometry.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace
{

bool canopyOnly = false;

using canopy::testing::compare;
using canopy::testing::Image;
using canopy::testing::ImageError;
using canopy::testing::OffscreenRenderer;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Re-executions timed per measurement (--repetitions): the median is reported.
int repetitions = 1;
/// Whether the synthetic forests' rows run (--data).
bool Synthetic = true;

/// Steady state: times the second Update() of an algorithm (re-executed after
/// Modified()), as when a camera moves; with --repetitions N, the median of N
/// re-executions. The first execution also pays for mapping fresh output
/// memory, which on this VM costs 1.3-3 ns per byte.
template <typename Algorithm>
double timeUpdate(Algorithm* algorithm, double* firstSeconds = nullptr)
{
  algorithm->Modified();
  auto start = Clock::now();
  algorithm->Update();
  if (firstSeconds)
  {
    *firstSeconds = secondsSince(start);
  }
  std::vector<double> times;
  for (int r = 0; r < repetitions; ++r)
  {
    algorithm->Modified();
    start = Clock::now();
    algorithm->Update();
    times.push_back(secondsSince(start));
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

struct Forest2D
{
  std::unique_ptr<canopy::tools::SyntheticForest> simulation;
  vtkSmartPointer<vtkHyperTreeGrid> htg;
  std::size_t leaves = 0;
  std::string label;              ///< after the leaf count in tables ("" for synthetic)
  std::string field = "pressure"; ///< the leaves-only field shown
  double low = 1, high = 7;       ///< its color range
};

/// The mini-app's forests (real data), simulated once, in this process.
std::vector<std::unique_ptr<canopy::tools::MiniAppForest>> MiniAppForests;

/// A mini-app forest's grid, shown by its leaves-only scalar (in [0, 1]).
Forest2D miniAppForest(const canopy::tools::MiniAppForest& simulation)
{
  Forest2D f;
  std::cout << canopy::tools::describeInput(simulation.label(), simulation.description())
            << std::endl;
  f.htg = canopy::buildHyperTreeGrid(simulation.description());
  f.leaves = static_cast<std::size_t>(simulation.globalLeaves());
  f.label = " (" + simulation.label() + ")";
  f.field = "scalar";
  f.low = 0;
  f.high = 1;
  return f;
}

std::vector<Forest2D> miniAppForests(int dimension)
{
  std::vector<Forest2D> forests;
  for (const auto& simulation : MiniAppForests)
    if (simulation->description().dimension == dimension)
      forests.push_back(miniAppForest(*simulation));
  return forests;
}

Forest2D makeForest(int dimension, int roots, int levels, bool cutaway = false)
{
  canopy::tools::SyntheticForestOptions o;
  o.dimension = dimension;
  o.rootsPerAxis = roots;
  o.maxLevels = levels;
  o.cutaway = cutaway;
  Forest2D f;
  f.simulation = std::make_unique<canopy::tools::SyntheticForest>(o);
  std::cout << canopy::tools::describeInput("synthetic " + std::to_string(dimension) + "D, " +
                                                std::to_string(roots) + " roots per axis, " +
                                                std::to_string(levels) + " levels",
                                            f.simulation->description())
            << std::endl;
  f.htg = canopy::buildHyperTreeGrid(f.simulation->description());
  f.leaves = f.simulation->numberOfLeaves();
  return f;
}

/// Time to write `bytes` bytes of output into mapped memory (the bandwidth floor).
double writeFloorSeconds(std::size_t bytes)
{
  std::vector<unsigned char> buffer(bytes);
  std::memset(buffer.data(), 1, bytes); // map the pages
  const auto start = Clock::now();
  std::memset(buffer.data(), 2, bytes);
  return secondsSince(start);
}

void full2d(const std::filesystem::path& out, int maxLevel)
{
  std::ofstream csv(out / "full2d.csv");
  csv << "leaves,canopy_s,canopy_first_s,vtk_geometry_s,speedup,canopy_ns_per_quad,"
         "floor_ns_per_quad,canopy_quads,vtk_quads\n";
  std::cout << "\n## Full-resolution 2D surface vs vtkHyperTreeGridGeometry\n\n"
            << "| leaves | Canopy s | Canopy first run s | vtkHyperTreeGridGeometry s | speedup "
               "| Canopy ns/quad | write floor ns/quad |\n|---:|---:|---:|---:|---:|---:|---:|\n";
  // Synthetic forests are made one at a time (the largest holds 2.3e7 leaves).
  std::vector<int> levelsOf;
  for (int levels = 7; Synthetic && levels <= maxLevel; ++levels)
    levelsOf.push_back(levels);
  const std::size_t synthetic = levelsOf.size();
  std::vector<Forest2D> real = miniAppForests(2);
  for (std::size_t row = 0; row < synthetic + real.size(); ++row)
  {
    Forest2D f =
        row < synthetic ? makeForest(2, 16, levelsOf[row]) : std::move(real[row - synthetic]);
    vtkNew<vtkCanopyAdaptiveSurface> canopy;
    canopy->SetInputData(f.htg);
    canopy->ViewDependentOff();
    canopy->AddField(f.field.c_str());
    double canopyFirst = 0;
    const double canopySeconds = timeUpdate(canopy.Get(), &canopyFirst);
    vtkNew<vtkHyperTreeGridGeometry> geometry;
    geometry->SetInputData(f.htg);
    const double vtkSeconds = canopyOnly ? -1 : timeUpdate(geometry.Get());
    const auto quads = static_cast<double>(canopy->GetPolyDataOutput()->GetNumberOfCells());
    // What the output holds per quad: 4 double points, 4 connectivity ids and an
    // offset, the original id, the level and one double field.
    const std::size_t bytesPerQuad = 4 * 24 + 5 * 8 + 8 + 1 + 8;
    const double floor =
        writeFloorSeconds(static_cast<std::size_t>(quads) * bytesPerQuad) / quads * 1e9;
    const double ns = canopySeconds / quads * 1e9;
    csv << f.leaves << f.label << "," << canopySeconds << "," << canopyFirst << "," << vtkSeconds
        << "," << vtkSeconds / canopySeconds << "," << ns << "," << floor << "," << quads << ","
        << vtkPolyData::SafeDownCast(geometry->GetOutput())->GetNumberOfCells() << "\n";
    std::cout << std::fixed << std::setprecision(3) << "| " << f.leaves << f.label << " | "
              << canopySeconds << " | " << canopyFirst << " | " << vtkSeconds << " | "
              << std::setprecision(1) << vtkSeconds / canopySeconds << "x | " << ns << " | "
              << floor << " |" << std::endl;
  }
}

void setTopView(vtkCamera* c, double x, double y, double scale)
{
  c->SetFocalPoint(x, y, 0);
  c->SetPosition(x, y, 5);
  c->SetViewUp(0, 1, 0);
  c->ParallelProjectionOn();
  c->SetParallelScale(scale);
}

void adaptive2d(const std::filesystem::path& out, int maxLevel)
{
  std::ofstream csv(out / "adaptive2d.csv");
  csv << "leaves,canopy_s,vtk_adaptive_s,speedup,canopy_quads,vtk_quads,canopy_rmse,vtk_rmse,"
         "canopy_share_off,vtk_share_off\n";
  std::cout << "\n## Adaptive 2D at 1024x1024 vs vtkAdaptiveDataSetSurfaceFilter\n\n"
            << "| leaves | Canopy s | vtkAdaptiveDataSetSurfaceFilter s | speedup | Canopy "
               "quads | VTK quads | RMSE Canopy / VTK (vs full resolution) |\n"
            << "|---:|---:|---:|---:|---:|---:|---:|\n";
  OffscreenRenderer r(1024, 1024);
  std::vector<int> levelsOf;
  for (int levels = 9; Synthetic && levels <= maxLevel; ++levels)
    levelsOf.push_back(levels);
  const std::size_t synthetic = levelsOf.size();
  std::vector<Forest2D> real = miniAppForests(2);
  for (std::size_t row = 0; row < synthetic + real.size(); ++row)
  {
    Forest2D f =
        row < synthetic ? makeForest(2, 16, levelsOf[row]) : std::move(real[row - synthetic]);
    // A fixed view on part of the front; on the mini-app's unit square the same
    // share of the domain (30% across), at its centre.
    if (row < synthetic)
      setTopView(r.camera(), 0.44, 0.44, 0.3);
    else
      setTopView(r.camera(), 0.5, 0.5, 0.15);
    const char* field = f.field.c_str();
    vtkNew<vtkCanopyAdaptiveSurface> canopy;
    canopy->SetInputData(f.htg);
    canopy->SetRenderer(r.renderer());
    canopy->AddField(field);
    const double canopySeconds = timeUpdate(canopy.Get());
    vtkNew<vtkAdaptiveDataSetSurfaceFilter> upstream;
    upstream->SetInputData(f.htg);
    upstream->SetRenderer(r.renderer());
    const double vtkSeconds = timeUpdate(upstream.Get());
    // Reference: every visible leaf (culled, no level of detail: same pixels as all leaves).
    vtkNew<vtkCanopyAdaptiveSurface> full;
    full->SetInputData(f.htg);
    full->SetRenderer(r.renderer());
    full->LevelOfDetailOff();
    full->AddField(field);
    full->Update();
    const Image reference = r.render(full->GetPolyDataOutput(), field, f.low, f.high);
    const ImageError ce =
        compare(r.render(canopy->GetPolyDataOutput(), field, f.low, f.high), reference, 8);
    const ImageError ve =
        compare(r.render(upstream->GetOutput(), field, f.low, f.high), reference, 8);
    const auto cq = canopy->GetPolyDataOutput()->GetNumberOfCells();
    const auto vq = upstream->GetOutput()->GetNumberOfCells();
    csv << f.leaves << f.label << "," << canopySeconds << "," << vtkSeconds << ","
        << vtkSeconds / canopySeconds << "," << cq << "," << vq << "," << ce.rmse << "," << ve.rmse
        << "," << ce.shareOff << "," << ve.shareOff << "\n";
    std::cout << std::fixed << std::setprecision(4) << "| " << f.leaves << f.label << " | "
              << canopySeconds << " | " << vtkSeconds << " | " << std::setprecision(1)
              << vtkSeconds / canopySeconds << "x | " << cq << " | " << vq << " | "
              << std::setprecision(2) << ce.rmse << " / " << ve.rmse << " |" << std::endl;
  }
}

void surface3d(const std::filesystem::path& out, int maxLevel)
{
  std::ofstream csv(out / "surface3d.csv");
  csv << "leaves,masked,canopy_s,vtk_geometry_s,vtk_adaptive_s,canopy_quads,vtk_geometry_quads,"
         "vtk_adaptive_quads\n";
  std::cout << "\n## 3D surface (perspective view of most of the grid, 1024x768)\n\n"
            << "| leaves | cut-away mask | Canopy s | vtkHyperTreeGridGeometry s | "
               "vtkAdaptiveDataSetSurfaceFilter s | Canopy quads | Geometry quads | Adaptive "
               "quads |\n|---:|---|---:|---:|---:|---:|---:|---:|\n";
  OffscreenRenderer r(1024, 768);
  struct Row
  {
    int levels;
    bool cutaway;
  };
  std::vector<Row> rows;
  for (int levels = 5; Synthetic && levels <= std::min(maxLevel - 4, 7); ++levels)
    for (bool cutaway : {false, true})
      rows.push_back({levels, cutaway});
  const std::size_t synthetic = rows.size();
  std::vector<Forest2D> real = miniAppForests(3);
  for (std::size_t row = 0; row < synthetic + real.size(); ++row)
  {
    {
      const bool cutaway = row < synthetic && rows[row].cutaway;
      Forest2D f = row < synthetic ? makeForest(3, 6, rows[row].levels, cutaway)
                                   : std::move(real[row - synthetic]);
      vtkCamera* c = r.camera();
      if (row < synthetic)
      {
        c->SetFocalPoint(0, 0, 0);
        c->SetPosition(2.2, 2.6, 1.8); // looking into the cut-away octant
      }
      else
      {
        // The same view of the mini-app's unit cube (half the synthetic's [-1, 1]^3).
        c->SetFocalPoint(0.5, 0.5, 0.5);
        c->SetPosition(0.5 + 1.1, 0.5 + 1.3, 0.5 + 0.9);
      }
      c->SetViewUp(0, 0, 1);
      c->ParallelProjectionOff();
      c->SetViewAngle(30);
      vtkNew<vtkCanopyAdaptiveSurface> canopy;
      canopy->SetInputData(f.htg);
      canopy->SetRenderer(r.renderer());
      canopy->AddField(row < synthetic ? "density" : "scalar");
      const double canopySeconds = timeUpdate(canopy.Get());
      vtkNew<vtkHyperTreeGridGeometry> geometry;
      geometry->SetInputData(f.htg);
      const double geometrySeconds = canopyOnly ? -1 : timeUpdate(geometry.Get());
      const vtkIdType gq =
          canopyOnly ? -1 : vtkPolyData::SafeDownCast(geometry->GetOutput())->GetNumberOfCells();
      // vtkAdaptiveDataSetSurfaceFilter aborts on an assertion with masked 3D
      // input in Debian's build (it descends into masked nodes): unmasked only.
      double adaptiveSeconds = -1;
      vtkIdType aq = -1;
      if (!cutaway && !canopyOnly)
      {
        vtkNew<vtkAdaptiveDataSetSurfaceFilter> upstream;
        upstream->SetInputData(f.htg);
        upstream->SetRenderer(r.renderer());
        adaptiveSeconds = timeUpdate(upstream.Get());
        aq = upstream->GetOutput()->GetNumberOfCells();
      }
      const auto cq = canopy->GetPolyDataOutput()->GetNumberOfCells();
      csv << f.leaves << f.label << "," << cutaway << "," << canopySeconds << "," << geometrySeconds
          << "," << adaptiveSeconds << "," << cq << "," << gq << "," << aq << "\n";
      std::cout << std::fixed << std::setprecision(4) << "| " << f.leaves << f.label << " | "
                << (cutaway ? "yes" : "no") << " | " << canopySeconds << " | " << geometrySeconds
                << " | " << (cutaway ? std::string("aborts") : std::to_string(adaptiveSeconds))
                << " | " << cq << " | " << gq << " | "
                << (cutaway ? std::string("-") : std::to_string(aq)) << " |" << std::endl;
    }
  }
}

} // namespace

int main(int argc, char** argv)
{
  std::filesystem::path out = "surface-benchmark";
  int maxLevel = 11;
  std::string data = "all";
  std::vector<std::string> miniAppSpecs;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--output" && i + 1 < argc)
      out = argv[++i];
    else if (arg == "--max-level" && i + 1 < argc)
      maxLevel = std::atoi(argv[++i]);
    else if (arg == "--quick")
      maxLevel = 9;
    else if (arg == "--canopy-only")
      canopyOnly = true;
    else if (arg == "--repetitions" && i + 1 < argc)
      repetitions = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--data" && i + 1 < argc)
      data = argv[++i];
    else if (arg == "--miniapp" && i + 1 < argc)
      miniAppSpecs.push_back(argv[++i]);
    else
    {
      std::cerr << "usage: canopy_bench_surface [--output DIR] [--max-level L] [--quick]\n"
                   "         [--canopy-only] [--repetitions N] [--data synthetic|miniapp|all]\n"
                   "         [--miniapp DIM,ROOTS,MAX_LEVEL,STEPS]...\n";
      return 2;
    }
  }
  if (data != "all" && data != "synthetic" && data != "miniapp")
  {
    std::cerr << "canopy_bench_surface: --data is synthetic, miniapp or all\n";
    return 2;
  }
  Synthetic = data != "miniapp";
  // The mini-app's forests: 2D and 3D at a late step (its library needs MPI).
  const bool mpiStarted = data != "synthetic" && canopy::tools::initializeMpiIfNeeded(&argc, &argv);
  if (data != "synthetic")
  {
    if (miniAppSpecs.empty())
      miniAppSpecs = {"2,32,9,20", "3,8,4,20"};
    for (const auto& spec : miniAppSpecs)
    {
      MiniAppForests.push_back(
          std::make_unique<canopy::tools::MiniAppForest>(canopy::tools::parseMiniAppForest(spec)));
      std::cerr << "bench: " << MiniAppForests.back()->label() << ": "
                << MiniAppForests.back()->globalLeaves() << " leaves ("
                << MiniAppForests.back()->commandLine() << ")\n";
    }
  }
  std::filesystem::create_directories(out);
  std::cout << "# Canopy surface benchmarks (Debian's VTK has assertions on)\n";
  const std::string only = std::getenv("CANOPY_BENCH_ONLY") ? std::getenv("CANOPY_BENCH_ONLY") : "";
  if (only.empty() || only == "full2d")
    full2d(out, maxLevel);
  if (only.empty() || only == "adaptive2d")
    adaptive2d(out, maxLevel);
  if (only.empty() || only == "surface3d")
    surface3d(out, maxLevel);
  MiniAppForests.clear();
  if (mpiStarted)
    MPI_Finalize();
  return 0;
}
