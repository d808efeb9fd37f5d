// Canopy's 3D views against ParaView 5.11's VTK routes to the same picture, in
// one run (under Xvfb, tests/support/with_xvfb.sh: it renders to count pixels).
//
// slices.csv  three orthogonal slices through (near) the centre, perspective view
//             of the whole grid at 1024x1024: vtkCanopyAdaptiveSlice (level of detail
//             at 1 pixel, and full resolution) against vtkHyperTreeGridAxisCut +
//             vtkHyperTreeGridGeometry per plane and vtkHyperTreeGridPlaneCutter per
//             plane; quads drawn against the pixels the slices cover.
// region.csv  the surface of a selected region, the selection changing every
//             execution: a value range (the density shell), a cut-away octant, and
//             both; vtkCanopyExtractSelection (+ another, inverted, for the cut) +
//             vtkCanopyAdaptiveSurface against vtkHyperTreeGridThreshold (new mask,
//             no copy) / vtkHyperTreeGridAxisClip + vtkHyperTreeGridGeometry.
//             The cut's box moves a little at every execution: every tree is redone.
// moving.csv  the cut-away octant of the mini-app's 3D forest, step after step
//             (--miniapp DIM,ROOTS,MAXLEVEL,STEPS[,REGRID_EVERY], default 3,16,4,20
//             and 3,16,4,20,4; means over 2 x repetitions steps): its objects move,
//             the mesh adapts every step (or every REGRID_EVERY steps), GridBuilder
//             rebuilds the trees whose refinement changed, and the
//             same filter keeps the mask of the others (SelectionMaskMemo); against a
//             new filter at each step (the whole mask computed), checked equal bit for
//             bit.
//
// Planes sit 0.013 off the centre: VTK 9.2's AxisCut aborts on a plane that lies
// on a cell face (PLATFORM.md). Debian's VTK is built with assertions on: the
// upstream filters are slower here than in a release build.
//
// Usage: canopy_bench_slice [--output DIR] [--forest ROOTS,LEVELS]... [--repetitions N]
//          [--miniapp DIM,ROOTS,MAXLEVEL,STEPS[,REGRID_EVERY]]... [--canopy-only]
//          [--breadth-first] [--far]
// (--breadth-first: nodes stored breadth-first, implicit global indices; default
// depth-first with a slot map, explicit indices; --far: the camera 4 times as far, the
// cells 4 times smaller on screen; default forests 7,6 (about 1e6 leaves) and 9,7
// (about 1e7); the region table runs on the first forest only)
#include "ChildProcess.h"
#include "ForestFingerprint.h"
#include "MiniAppForest.h"
#include "OffscreenRenderer.h"
#include "SyntheticForest.h"

#include <canopy/GridBuilder.h>
#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSlice.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <vtkBitArray.h>
#include <vtkCamera.h>
#include <vtkDataObject.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridAxisClip.h>
#include <vtkHyperTreeGridAxisCut.h>
#include <vtkHyperTreeGridGeometry.h>
#include <vtkHyperTreeGridPlaneCutter.h>
#include <vtkHyperTreeGridThreshold.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace
{

using Clock = std::chrono::steady_clock;
int Repetitions = 3;
bool CanopyOnly = false;
bool DepthFirst = true; ///< the synthetic forest's storage (--breadth-first: implicit indices)
double Distance = 1;    ///< the camera's distance, times the default (--far: 4)

/// Median over Repetitions of `run()`'s seconds; `prepare(r)` before each (not
/// timed): a changed selection, a Modified().
double median(const std::function<void(int)>& prepare, const std::function<void()>& run)
{
  std::vector<double> times;
  for (int r = 0; r <= Repetitions; ++r)
  {
    prepare(r);
    const auto start = Clock::now();
    run();
    if (r > 0) // the first execution also maps fresh memory: steady state only
    {
      times.push_back(std::chrono::duration<double>(Clock::now() - start).count());
    }
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

struct Forest
{
  std::unique_ptr<canopy::tools::SyntheticForest> simulation;
  vtkSmartPointer<vtkHyperTreeGrid> htg;
  std::string label;
};

Forest makeForest(int roots, int levels)
{
  canopy::tools::SyntheticForestOptions o;
  o.dimension = 3;
  o.rootsPerAxis = roots;
  o.maxLevels = levels;
  o.cutaway = false;
  o.depthFirstStorage = DepthFirst;
  Forest f;
  f.simulation = std::make_unique<canopy::tools::SyntheticForest>(o);
  f.htg = canopy::buildHyperTreeGrid(f.simulation->description());
  std::ostringstream label;
  label << f.simulation->numberOfLeaves() << " (" << roots << "^3 roots, " << levels << " levels)";
  f.label = label.str();
  std::cout << canopy::tools::describeInput(f.label, f.simulation->description()) << std::endl;
  return f;
}

void setView(vtkCamera* c)
{
  // The synthetic forest fills [-1, 1]^3: a perspective view of all of it.
  c->SetFocalPoint(0, 0, 0);
  c->SetPosition(2.6 * Distance, 2.0 * Distance, 3.2 * Distance);
  c->SetViewUp(0, 1, 0);
  c->ParallelProjectionOff();
  c->SetViewAngle(30);
}

/// Pixels not of the background (black; the colour map has none) in an image of `surface`.
std::size_t coveredPixels(canopy::testing::OffscreenRenderer& r, vtkPolyData* surface)
{
  const canopy::testing::Image image = r.render(surface, "density", 1, 4);
  std::size_t covered = 0;
  for (std::size_t p = 0; p + 2 < image.rgb.size(); p += 3)
  {
    covered += image.rgb[p] != 0 || image.rgb[p + 1] != 0 || image.rgb[p + 2] != 0;
  }
  return covered;
}

/// Total area of a polydata's polygons (the same picture has the same area).
double area(vtkPolyData* surface)
{
  double total = 0;
  for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
  {
    double b[6];
    surface->GetCellBounds(c, b);
    const double sides[3] = {b[1] - b[0], b[3] - b[2], b[5] - b[4]};
    // Axis-aligned rectangles: the product of the two longest sides.
    total += std::max({sides[0] * sides[1], sides[1] * sides[2], sides[0] * sides[2]});
  }
  return total;
}

constexpr double Offset = 0.013; ///< planes off the centre, off every face

void slices(std::ofstream& csv, const Forest& f, canopy::testing::OffscreenRenderer& r)
{
  vtkNew<vtkCanopyAdaptiveSlice> lod;
  lod->SetInputData(f.htg);
  lod->SetRenderer(r.renderer());
  lod->AddField("density");
  vtkNew<vtkCanopyAdaptiveSlice> full;
  full->SetInputData(f.htg);
  full->ViewDependentOff();
  full->AddField("density");
  for (auto* s : {lod.Get(), full.Get()})
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      s->AddPlane(axis, Offset);
    }
  }
  const double lodSeconds = median([&](int) { lod->Modified(); }, [&] { lod->Update(); });
  const double fullSeconds = median([&](int) { full->Modified(); }, [&] { full->Update(); });
  const vtkIdType lodQuads = lod->GetPolyDataOutput()->GetNumberOfCells();
  const vtkIdType fullQuads = full->GetPolyDataOutput()->GetNumberOfCells();
  const vtkIdType visited = lod->GetLastVisited();
  const std::size_t pixels = coveredPixels(r, lod->GetPolyDataOutput());
  const double fullArea = area(full->GetPolyDataOutput());

  double cutSeconds = -1;
  double cutterSeconds = -1;
  vtkIdType cutQuads = -1;
  vtkIdType cutterCells = -1;
  double cutArea = -1;
  if (!CanopyOnly)
  {
    std::vector<vtkSmartPointer<vtkHyperTreeGridAxisCut>> cuts;
    std::vector<vtkSmartPointer<vtkHyperTreeGridGeometry>> geometries;
    std::vector<vtkSmartPointer<vtkHyperTreeGridPlaneCutter>> cutters;
    for (int axis = 0; axis < 3; ++axis)
    {
      auto cut = vtkSmartPointer<vtkHyperTreeGridAxisCut>::New();
      cut->SetInputData(f.htg);
      cut->SetPlaneNormalAxis(axis);
      cut->SetPlanePosition(Offset);
      auto geometry = vtkSmartPointer<vtkHyperTreeGridGeometry>::New();
      geometry->SetInputConnection(cut->GetOutputPort());
      cuts.push_back(cut);
      geometries.push_back(geometry);
      auto cutter = vtkSmartPointer<vtkHyperTreeGridPlaneCutter>::New();
      cutter->SetInputData(f.htg);
      double normal[3] = {0, 0, 0};
      normal[axis] = 1;
      cutter->SetPlane(normal[0], normal[1], normal[2], Offset);
      cutters.push_back(cutter);
    }
    cutSeconds = median(
        [&](int)
        {
          for (auto& cut : cuts)
            cut->Modified();
        },
        [&]
        {
          for (auto& geometry : geometries)
            geometry->Update();
        });
    cutQuads = 0;
    cutArea = 0;
    for (auto& geometry : geometries)
    {
      cutQuads += vtkPolyData::SafeDownCast(geometry->GetOutput())->GetNumberOfCells();
      cutArea += area(vtkPolyData::SafeDownCast(geometry->GetOutput()));
    }
    cutterSeconds = median(
        [&](int)
        {
          for (auto& cutter : cutters)
            cutter->Modified();
        },
        [&]
        {
          for (auto& cutter : cutters)
            cutter->Update();
        });
    cutterCells = 0;
    for (auto& cutter : cutters)
      cutterCells += vtkPolyData::SafeDownCast(cutter->GetOutput())->GetNumberOfCells();
  }
  csv << f.simulation->numberOfLeaves() << "," << lodSeconds << "," << fullSeconds << ","
      << cutSeconds << "," << cutterSeconds << "," << lodQuads << "," << fullQuads << ","
      << cutQuads << "," << cutterCells << "," << pixels << "," << visited << "," << fullArea << ","
      << cutArea << "\n";
  std::cout << std::fixed << std::setprecision(4) << "| " << f.label << " | " << lodSeconds << " | "
            << fullSeconds << " | " << cutSeconds << " (" << std::setprecision(0)
            << cutSeconds / lodSeconds << "x) | " << std::setprecision(4) << cutterSeconds << " ("
            << std::setprecision(0) << cutterSeconds / lodSeconds << "x) | " << lodQuads << " | "
            << fullQuads << " | " << cutQuads << " | " << pixels << " | " << std::setprecision(2)
            << static_cast<double>(lodQuads) / static_cast<double>(pixels) << " | " << visited
            << " | " << std::setprecision(4) << fullArea << " | " << cutArea << " |" << std::endl;
}

/// The filter set to cut `box` away (an inverted box, as a masked grid).
void cutAway(vtkCanopyExtractSelection* filter, const double box[6])
{
  filter->SetSelectionMode(vtkCanopyExtractSelection::BOX);
  filter->SetBox(box);
  filter->InvertOn();
  filter->PreserveTopologyOn();
}

struct RegionCase
{
  const char* name;
  bool range;
  bool cut;
};

void region(std::ofstream& csv, const Forest& f, canopy::testing::OffscreenRenderer& r,
            const RegionCase& c)
{
  // The density shell (1 outside, up to 4 at the front): [low, 4.5], low
  // changing every execution; the octant towards the camera cut away.
  auto low = [](int repetition) { return 2.0 + 0.01 * repetition; };
  const double octant[6] = {0, 2, 0, 2, 0, 2};
  vtkNew<vtkCanopyExtractSelection> byValue;
  byValue->SetInputData(f.htg);
  byValue->SetSelectionMode(vtkCanopyExtractSelection::VALUE_RANGE);
  byValue->SetValueArrayName("density");
  byValue->PreserveTopologyOn();
  vtkNew<vtkCanopyExtractSelection> cut;
  cutAway(cut, octant);
  vtkAlgorithm* last = nullptr;
  if (c.range)
  {
    last = byValue;
  }
  if (c.cut)
  {
    if (last)
      cut->SetInputConnection(last->GetOutputPort());
    else
      cut->SetInputData(f.htg);
    last = cut;
  }
  vtkNew<vtkCanopyAdaptiveSurface> surface;
  surface->SetInputConnection(last->GetOutputPort());
  surface->SetRenderer(r.renderer());
  surface->AddField("density");
  vtkNew<vtkCanopyAdaptiveSurface> fullSurface;
  fullSurface->SetInputConnection(last->GetOutputPort());
  fullSurface->ViewDependentOff();
  fullSurface->AddField("density");
  auto change = [&](int repetition)
  {
    byValue->SetValueRange(low(repetition), 4.5);
    // The box moves (with the camera, say) by less than a cell: a new selection,
    // every tree redone (the filter keeps trees only for the same box).
    double moved[6];
    std::copy(octant, octant + 6, moved);
    moved[0] += 1e-9 * repetition;
    cut->SetBox(moved);
  };
  const double canopySeconds = median(change, [&] { surface->Update(); });
  // The same executions split: the selection alone, then the surface alone.
  const double selectionSeconds = median(change, [&] { last->Update(); });
  const double canopyFullSeconds = median(change, [&] { fullSurface->Update(); });
  const vtkIdType canopyQuads = surface->GetPolyDataOutput()->GetNumberOfCells();
  const vtkIdType canopyFullQuads = fullSurface->GetPolyDataOutput()->GetNumberOfCells();

  double vtkSeconds = -1;
  vtkIdType vtkQuads = -1;
  double vtkArea = -1;
  std::string vtkResult;
  if (!CanopyOnly)
  {
    // In a child: chained upstream HTG filters can abort on an assertion here.
    vtkResult = canopy::bench::inChild(
        [&]
        {
          vtkNew<vtkHyperTreeGridThreshold> threshold;
          threshold->SetInputData(f.htg);
          threshold->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS,
                                            "density");
          threshold->SetJustCreateNewMask(true);
          threshold->SetUpperThreshold(4.5);
          vtkNew<vtkHyperTreeGridAxisClip> clip;
          clip->SetClipTypeToBox();
          clip->SetBounds(octant[0], octant[1], octant[2], octant[3], octant[4], octant[5]);
          clip->InsideOutOn(); // keep what is outside the box: the octant cut away
          vtkAlgorithm* upstream = nullptr;
          if (c.range)
          {
            upstream = threshold;
          }
          if (c.cut)
          {
            if (upstream)
              clip->SetInputConnection(upstream->GetOutputPort());
            else
              clip->SetInputData(f.htg);
            upstream = clip;
          }
          vtkNew<vtkHyperTreeGridGeometry> geometry;
          geometry->SetInputConnection(upstream->GetOutputPort());
          vtkSeconds = median(
              [&](int repetition)
              {
                threshold->SetLowerThreshold(low(repetition));
                clip->Modified();
              },
              [&] { geometry->Update(); });
          auto* output = vtkPolyData::SafeDownCast(geometry->GetOutput());
          std::ostringstream result;
          result << std::setprecision(17) << vtkSeconds << " " << output->GetNumberOfCells() << " "
                 << area(output);
          return result.str();
        });
    std::istringstream(vtkResult) >> vtkSeconds >> vtkQuads >> vtkArea;
  }
  const double canopyArea = area(fullSurface->GetPolyDataOutput());
  csv << f.simulation->numberOfLeaves() << "," << c.name << "," << canopySeconds << ","
      << canopyFullSeconds << "," << vtkSeconds << "," << canopyQuads << "," << canopyFullQuads
      << "," << vtkQuads << "," << canopyArea << "," << vtkArea << "," << selectionSeconds << "\n";
  std::cout << std::fixed << std::setprecision(4) << "| " << f.label << " | " << c.name << " | "
            << canopySeconds << " (selection " << selectionSeconds << ") | " << canopyFullSeconds
            << " | ";
  if (vtkResult.empty())
    std::cout << (CanopyOnly ? "-" : "aborts (assertion)") << " | ";
  else
    std::cout << vtkSeconds << " (" << std::setprecision(0) << vtkSeconds / canopySeconds << "x, "
              << vtkSeconds / canopyFullSeconds << "x) | ";
  std::cout << canopyQuads << " | " << canopyFullQuads << " | " << vtkQuads << " | "
            << std::setprecision(4) << canopyArea << " | " << vtkArea << " |" << std::endl;
}

/// The cut-away octant of the mini-app's 3D forest, step after step: the
/// objects move, GridBuilder rebuilds the trees whose refinement changed.
void movingCut(std::ofstream& csv, const canopy::tools::MiniAppForestOptions& options,
               canopy::testing::OffscreenRenderer& r)
{
  canopy::tools::MiniAppForest simulation(options, MPI_COMM_SELF);
  std::cout << canopy::tools::describeInput(simulation.label() + " at its first step",
                                            simulation.description())
            << std::endl;
  canopy::GridBuilder builder;
  vtkSmartPointer<vtkHyperTreeGrid> grid = builder.build(simulation.description());
  double b[6];
  grid->GetBounds(b);
  // The octant towards the camera (x, y, z above the centre), as the 3D pipeline cuts.
  const double octant[6] = {0.5 * (b[0] + b[1]), b[1] + 1, 0.5 * (b[2] + b[3]), b[3] + 1,
                            0.5 * (b[4] + b[5]), b[5] + 1};
  vtkNew<vtkCanopyExtractSelection> cut;
  cut->SetInputData(grid);
  cutAway(cut, octant);
  vtkNew<vtkCanopyAdaptiveSurface> surface;
  surface->SetInputConnection(cut->GetOutputPort());
  surface->SetRenderer(r.renderer());
  surface->AddField("scalar");
  r.renderer()->ResetCamera(b);
  // What each measured step did: GridBuilder, the cut by the same filter and by
  // a new one, the surface (seconds); trees rebuilt and kept, nodes recomputed,
  // cells.
  struct Step
  {
    double build, kept, whole, shown, rebuilt, keptTrees, recomputed, cells;
  };
  std::vector<Step> steps;
  for (int step = 0; step <= 2 * Repetitions; ++step)
  {
    simulation.advance();
    auto start = Clock::now();
    grid = builder.build(simulation.description());
    const double buildSeconds = std::chrono::duration<double>(Clock::now() - start).count();
    // The last output is released first, untimed: it holds the trees the build
    // replaced, whose release a new filter (below) would not pay.
    cut->GetOutputDataObject(0)->Initialize();
    start = Clock::now();
    cut->Update();
    const double keptSeconds = std::chrono::duration<double>(Clock::now() - start).count();
    start = Clock::now();
    surface->Update();
    const double surfaceSeconds = std::chrono::duration<double>(Clock::now() - start).count();
    vtkNew<vtkCanopyExtractSelection> fresh;
    fresh->SetInputData(grid);
    cutAway(fresh, octant);
    start = Clock::now();
    fresh->Update();
    const double wholeSeconds = std::chrono::duration<double>(Clock::now() - start).count();
    vtkBitArray* a = vtkHyperTreeGrid::SafeDownCast(cut->GetOutputDataObject(0))->GetMask();
    vtkBitArray* c = vtkHyperTreeGrid::SafeDownCast(fresh->GetOutputDataObject(0))->GetMask();
    if (a->GetNumberOfValues() != c->GetNumberOfValues() ||
        std::memcmp(a->GetPointer(0), c->GetPointer(0),
                    static_cast<std::size_t>((a->GetNumberOfValues() + 7) / 8)) != 0)
    {
      std::cerr << "canopy_bench_slice: the kept mask differs from a new filter's at step "
                << simulation.step() << "\n";
      std::exit(1);
    }
    if (step == 0) // the first execution computes every tree
    {
      continue;
    }
    steps.push_back({buildSeconds, keptSeconds, wholeSeconds, surfaceSeconds,
                     static_cast<double>(builder.lastBuild().treesRebuilt),
                     static_cast<double>(cut->GetLastKeptTrees()),
                     static_cast<double>(cut->GetLastRecomputedNodes()),
                     static_cast<double>(grid->GetNumberOfCells())});
  }
  // Means over the steps: with regridding every few steps, what a step costs on average.
  auto mean = [&](double Step::*what)
  {
    double sum = 0;
    for (const Step& step : steps)
      sum += step.*what;
    return sum / static_cast<double>(steps.size());
  };
  const double build = mean(&Step::build);
  const double kept = mean(&Step::kept);
  const double whole = mean(&Step::whole);
  const double shown = mean(&Step::shown);
  const double rebuilt = mean(&Step::rebuilt);
  const double keptTrees = mean(&Step::keptTrees);
  const double recomputed = mean(&Step::recomputed);
  const double cells = mean(&Step::cells);
  const std::size_t trees = simulation.description().trees.size();
  csv << simulation.globalLeaves() << "," << trees << "," << rebuilt << "," << keptTrees << ","
      << recomputed << "," << cells << "," << build << "," << kept << "," << whole << "," << shown
      << "\n";
  std::cout << std::fixed << std::setprecision(0) << "| " << simulation.label() << ", "
            << simulation.globalLeaves() << " leaves | " << trees << " | " << rebuilt << " | "
            << keptTrees << " | " << recomputed << " of " << cells << " (" << std::setprecision(1)
            << 100.0 * recomputed / cells << "%) | " << std::setprecision(4) << build << " | "
            << kept << " | " << whole << " (" << std::setprecision(1) << whole / kept << "x) | "
            << std::setprecision(4) << shown << " |" << std::endl;
}

} // namespace

int main(int argc, char** argv)
{
  const bool ownsMpi = canopy::tools::initializeMpiIfNeeded(&argc, &argv);
  std::filesystem::path out = "bench-slice";
  std::vector<std::pair<int, int>> forests;
  std::vector<canopy::tools::MiniAppForestOptions> miniapps;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--output" && i + 1 < argc)
      out = argv[++i];
    else if (arg == "--forest" && i + 1 < argc)
    {
      int roots = 0;
      int levels = 0;
      char comma = 0;
      std::istringstream text(argv[++i]);
      if (!(text >> roots >> comma >> levels) || comma != ',' || roots < 1 || levels < 1)
      {
        std::cerr << "canopy_bench_slice: --forest ROOTS,LEVELS, got " << argv[i] << "\n";
        return 2;
      }
      forests.emplace_back(roots, levels);
    }
    else if (arg == "--miniapp" && i + 1 < argc)
      miniapps.push_back(canopy::tools::parseMiniAppForest(argv[++i]));
    else if (arg == "--repetitions" && i + 1 < argc)
      Repetitions = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--canopy-only")
      CanopyOnly = true;
    else if (arg == "--breadth-first")
      DepthFirst = false;
    else if (arg == "--far")
      Distance = 4;
    else
    {
      std::cerr << "usage: canopy_bench_slice [--output DIR] [--forest ROOTS,LEVELS]... "
                   "[--miniapp DIM,ROOTS,MAXLEVEL,STEPS[,REGRID_EVERY]]... [--repetitions N] "
                   "[--canopy-only] "
                   "[--breadth-first] [--far]\n";
      return 2;
    }
  }
  if (forests.empty())
  {
    forests = {{7, 6}, {9, 7}};
  }
  if (miniapps.empty())
  {
    miniapps = {canopy::tools::parseMiniAppForest("3,16,4,20"),
                canopy::tools::parseMiniAppForest("3,16,4,20,4")};
  }
  std::filesystem::create_directories(out);
  canopy::testing::OffscreenRenderer renderer(1024, 1024);
  setView(renderer.camera());
  // Every table below is seen from this camera: its figures depend on it.
  const double* eye = renderer.camera()->GetPosition();
  std::cout << "camera: position " << eye[0] << "," << eye[1] << "," << eye[2]
            << (Distance > 1 ? " (--far)" : " (default)") << ", view angle "
            << renderer.camera()->GetViewAngle() << ", 1024x1024 pixels" << std::endl;

  std::ofstream slicesCsv(out / "slices.csv");
  slicesCsv << "leaves,canopy_lod_s,canopy_full_s,vtk_axiscut_geometry_s,vtk_planecutter_s,"
               "canopy_lod_quads,canopy_full_quads,vtk_axiscut_quads,vtk_planecutter_cells,"
               "pixels_covered,canopy_nodes_visited,canopy_full_area,vtk_axiscut_area\n";
  std::ofstream regionCsv(out / "region.csv");
  regionCsv << "leaves,selection,canopy_s,canopy_full_s,vtk_s,canopy_quads,canopy_full_quads,"
               "vtk_quads,canopy_full_area,vtk_area,canopy_selection_s\n";
  std::cout
      << "## Three slices, 1024x1024 (median of " << Repetitions << ")\n\n"
      << "| leaves | Canopy LOD s | Canopy full s | AxisCut+Geometry s (ratio) | "
         "PlaneCutter s (ratio) | Canopy LOD quads | Canopy full quads | AxisCut quads | "
         "pixels covered | quads / pixel | nodes visited | Canopy full area | AxisCut area |\n"
      << "|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|" << std::endl;
  std::vector<Forest> built;
  for (const auto& [roots, levels] : forests)
  {
    built.push_back(makeForest(roots, levels));
    slices(slicesCsv, built.back(), renderer);
    if (built.size() > 1)
    {
      built.pop_back(); // only the first forest is kept for the region table
    }
  }
  std::cout << "\n## Selected region's surface, selection changing every execution (median of "
            << Repetitions << "), " << built.front().label << ", camera "
            << (Distance > 1 ? "--far" : "default") << "\n\n"
            << "| leaves | selection | Canopy (view) s | Canopy (full) s | VTK s (ratio to "
               "view, full) | Canopy (view) quads | Canopy (full) quads | VTK quads | Canopy "
               "(full) area | VTK area |\n"
            << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|" << std::endl;
  for (const RegionCase& c :
       {RegionCase{"value range", true, false}, RegionCase{"cut-away octant", false, true},
        RegionCase{"range + cut-away", true, true}})
  {
    region(regionCsv, built.front(), renderer, c);
  }
  std::ofstream movingCsv(out / "moving.csv");
  movingCsv << "leaves,trees,trees_rebuilt,trees_kept,nodes_recomputed,cells,build_s,"
               "cut_kept_s,cut_whole_s,surface_s\n";
  std::cout << "\n## Cut-away octant of the mini-app's 3D forest, step after step (mean of "
            << 2 * Repetitions << " steps)\n\n"
            << "| forest | trees | trees rebuilt per step | trees kept by the cut | nodes "
               "recomputed | GridBuilder s | cut, same filter s | cut, new filter s (ratio) | "
               "surface s |\n"
            << "|---|---:|---:|---:|---:|---:|---:|---:|---:|" << std::endl;
  built.clear();
  for (const auto& options : miniapps)
  {
    movingCut(movingCsv, options, renderer);
  }
  if (ownsMpi)
  {
    MPI_Finalize();
  }
  return 0;
}
