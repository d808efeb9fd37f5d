// Time against surface size: one blob, its surface at one resolution, in forests
// of 1e6 to 1e8 leaves. What grows is the rest of the domain's refinement
// (a background at values far from the contour's), not the surface.
//
// The forest: BlobForest.h, its band at level 5 (h = 1/512, w = 1.25 h, 4 w
// each side), the same in every forest; every other node refined to the
// background level B (--background B...): B = 2, 3, 4, 5 give 1.3e6, 3.1e6,
// 1.8e7 and 1.35e8 leaves. The contour at 0.5 is the same triangles in every
// forest (checked: the run fails if the count differs).
//
// Per forest, vtkCanopyContour at f = 0.5 on one thread (the best of
// --repetitions executions each):
//   first        the first execution: the pass over the nodes for their value
//                ranges, then the pruned traversal
//   new values   the field array modified (a step whose values changed): the
//                ranges again, then the traversal
//   kept ranges  the filter modified, the array not (a camera move, a new
//                contour value): the traversal alone
//   no pruning   the traversal of every node, no ranges
// and ParaView 5.11's vtkHyperTreeGridContour (one execution) on the forests of
// at most --vtk-max-leaves leaves. The field is read in place (EveryNode,
// breadth-first, trees back to back, no slot map).
//
//   canopy_bench_contour_surface_size [--background B]... [--repetitions N]
//                                     [--vtk-max-leaves N]
// Defaults: B = 2 3 4 5, 3 repetitions, VTK up to 4e6 leaves.
#include "BlobForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyContour.h>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridContour.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace
{

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

struct Times
{
  double first = 0;
  double newValues = 1e300;
  double keptRanges = 1e300;
  double noPruning = 1e300;
  vtkIdType triangles = 0;
  vtkIdType visited = 0;
  vtkIdType visitedNoPruning = 0;
};

vtkNew<vtkCanopyContour> makeContour(vtkHyperTreeGrid* htg, bool pruning)
{
  vtkNew<vtkCanopyContour> contour;
  contour->SetInputData(htg);
  contour->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "f");
  contour->SetValue(0, 0.5);
  contour->SetComputeNormals(true);
  contour->SetPruning(pruning);
  return contour;
}

Times timeCanopy(vtkHyperTreeGrid* htg, int repetitions)
{
  Times t;
  vtkNew<vtkCanopyContour> contour = makeContour(htg, true);
  auto start = Clock::now();
  contour->Update();
  t.first = secondsSince(start);
  t.triangles = contour->GetOutput()->GetNumberOfCells();
  t.visited = contour->GetLastVisited();
  vtkDataArray* values = htg->GetCellData()->GetArray("f");
  for (int r = 0; r < repetitions; ++r)
  {
    values->Modified(); // as a simulation's step says its values changed
    htg->Modified();
    start = Clock::now();
    contour->Update();
    t.newValues = std::min(t.newValues, secondsSince(start));
    if (contour->GetLastRangesKept())
    {
      std::fprintf(stderr, "the ranges were kept after the values were modified\n");
      std::exit(1);
    }
    contour->Modified();
    start = Clock::now();
    contour->Update();
    t.keptRanges = std::min(t.keptRanges, secondsSince(start));
    if (!contour->GetLastRangesKept() || contour->GetOutput()->GetNumberOfCells() != t.triangles)
    {
      std::fprintf(stderr, "the ranges were not kept, or the contour changed\n");
      std::exit(1);
    }
  }
  vtkNew<vtkCanopyContour> every = makeContour(htg, false);
  for (int r = 0; r < std::max(1, repetitions); ++r)
  {
    every->Modified();
    start = Clock::now();
    every->Update();
    t.noPruning = std::min(t.noPruning, secondsSince(start));
  }
  t.visitedNoPruning = every->GetLastVisited();
  if (every->GetOutput()->GetNumberOfCells() != t.triangles)
  {
    std::fprintf(stderr, "pruning changed the contour\n");
    std::exit(1);
  }
  return t;
}

} // namespace

int main(int argc, char** argv)
{
  std::vector<int> backgrounds;
  int repetitions = 3;
  double vtkMaxLeaves = 4e6;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--background" && i + 1 < argc)
    {
      backgrounds.push_back(std::atoi(argv[++i]));
    }
    else if (arg == "--repetitions" && i + 1 < argc)
    {
      repetitions = std::atoi(argv[++i]);
    }
    else if (arg == "--vtk-max-leaves" && i + 1 < argc)
    {
      vtkMaxLeaves = std::atof(argv[++i]);
    }
    else
    {
      std::fprintf(stderr, "unknown argument %s (see the file's header)\n", argv[i]);
      return 2;
    }
  }
  if (backgrounds.empty())
  {
    backgrounds = {2, 3, 4, 5};
  }
  for (int b : backgrounds)
  {
    if (b < 0 || b > 5)
    {
      std::fprintf(stderr, "--background %d: a level from 0 to 5 (the band's)\n", b);
      return 2;
    }
  }
  vtkSMPTools::Initialize(1);
  std::printf("| background level | leaves | triangles | describe + build (s) | first (s) | "
              "new values (s) | kept ranges (s) | no pruning (s) | groups visited (pruned / "
              "not) | vtkHyperTreeGridContour (s) |\n|---|---|---|---|---|---|---|---|---|---|\n");
  vtkIdType triangles = -1;
  for (int b : backgrounds)
  {
    auto start = Clock::now();
    canopy::bench::BlobForestOptions options;
    options.backgroundLevel = b;
    canopy::bench::BlobForest forest(options);
    auto htg = canopy::buildHyperTreeGrid(forest.description());
    const double build = secondsSince(start);
    const Times t = timeCanopy(htg, repetitions);
    if (triangles >= 0 && t.triangles != triangles)
    {
      std::fprintf(stderr, "the surface changed with the background: %lld triangles, then %lld\n",
                   static_cast<long long>(triangles), static_cast<long long>(t.triangles));
      return 1;
    }
    triangles = t.triangles;
    std::string vtkTime = "not run";
    if (static_cast<double>(forest.leaves()) <= vtkMaxLeaves)
    {
      vtkNew<vtkHyperTreeGridContour> vtk;
      vtk->SetInputData(htg);
      vtk->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "f");
      vtk->SetValue(0, 0.5);
      start = Clock::now();
      vtk->Update();
      char text[64];
      std::snprintf(text, sizeof text, "%.2f", secondsSince(start));
      vtkTime = text;
    }
    std::printf("| %d | %zu | %lld | %.2f | %.3f | %.3f | %.3f | %.3f | %lld / %lld | %s |\n", b,
                forest.leaves(), static_cast<long long>(t.triangles), build, t.first, t.newValues,
                t.keptRanges, t.noPruning, static_cast<long long>(t.visited),
                static_cast<long long>(t.visitedNoPruning), vtkTime.c_str());
    std::fflush(stdout);
  }
  return 0;
}
