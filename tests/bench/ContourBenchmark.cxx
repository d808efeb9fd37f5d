// The contour of a synthetic blast-wave forest's density (tools/SyntheticForest.h:
// a shell refined around a spherical front) at one value, by vtkCanopyContour
// (pruning on and off) and by ParaView 5.11's vtkHyperTreeGridContour, both on
// one thread: time per execution (the first, and the fastest of the repeated
// ones that follow, as a step whose values changed), cells (triangles, segments), the open
// edges inside the domain (edges of one triangle whose ends are not both on
// the domain's boundary: cracks, hidden cells' borders, or a boundary strip the
// contour does not reach).
//
//   canopy_bench_contour [--forest DIM,ROOTS,LEVELS]... [--repetitions N] [--threads N]
//                        [--canopy-only] [--value V]
//
// Defaults: 3,7,6 (about 1e6 leaves), 5 repetitions, 1 thread, density 2.5.
// Debian's VTK is built with assertions on: VTK's filter is slower here than in
// a release build.
#include "SyntheticForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyContour.h>

#include <vtkCellArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridContour.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace
{

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a, Clock::time_point b)
{
  return std::chrono::duration<double>(b - a).count();
}

/// Edges of exactly one triangle whose two ends are not both on one boundary plane.
std::size_t openEdges(vtkPolyData* out, const double bounds[6])
{
  std::map<std::pair<vtkIdType, vtkIdType>, int> uses;
  vtkCellArray* polys = out->GetPolys();
  vtkNew<vtkIdList> ids;
  polys->InitTraversal();
  while (polys->GetNextCell(ids))
  {
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      const vtkIdType a = ids->GetId(k);
      const vtkIdType b = ids->GetId((k + 1) % ids->GetNumberOfIds());
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  std::size_t open = 0;
  for (const auto& [edge, n] : uses)
  {
    if (n != 1)
    {
      continue;
    }
    double a[3];
    double b[3];
    out->GetPoint(edge.first, a);
    out->GetPoint(edge.second, b);
    bool onBoundary = false;
    for (int k = 0; k < 3; ++k)
    {
      for (double side : {bounds[2 * k], bounds[2 * k + 1]})
      {
        onBoundary = onBoundary || (a[k] == side && b[k] == side);
      }
    }
    open += onBoundary ? 0 : 1;
  }
  return open;
}

struct Result
{
  double first = 0;
  double best = 1e300;
  vtkIdType triangles = 0;
  std::size_t open = 0;
  double extent[6] = {0, 0, 0, 0, 0, 0};
};

template <typename Filter>
Result timeFilter(Filter* filter, int repetitions)
{
  Result r;
  auto t0 = Clock::now();
  filter->Update();
  r.first = seconds(t0, Clock::now());
  for (int i = 0; i < repetitions; ++i)
  {
    filter->Modified();
    t0 = Clock::now();
    filter->Update();
    r.best = std::min(r.best, seconds(t0, Clock::now()));
  }
  if (repetitions == 0)
  {
    r.best = r.first;
  }
  return r;
}

} // namespace

int main(int argc, char** argv)
{
  std::vector<std::array<int, 3>> forests;
  int repetitions = 5;
  int threads = 1;
  bool canopyOnly = false;
  double value = 2.5;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--forest" && i + 1 < argc)
    {
      std::array<int, 3> f{};
      if (std::sscanf(argv[++i], "%d,%d,%d", &f[0], &f[1], &f[2]) != 3)
      {
        std::fprintf(stderr, "--forest DIM,ROOTS,LEVELS\n");
        return 2;
      }
      forests.push_back(f);
    }
    else if (arg == "--repetitions" && i + 1 < argc)
    {
      repetitions = std::atoi(argv[++i]);
    }
    else if (arg == "--threads" && i + 1 < argc)
    {
      threads = std::atoi(argv[++i]);
    }
    else if (arg == "--value" && i + 1 < argc)
    {
      value = std::atof(argv[++i]);
    }
    else if (arg == "--canopy-only")
    {
      canopyOnly = true;
    }
    else
    {
      std::fprintf(stderr, "unknown argument %s\n", argv[i]);
      return 2;
    }
  }
  if (forests.empty())
  {
    forests.push_back({{3, 7, 6}});
  }
  vtkSMPTools::Initialize(threads);
  std::printf("forest,leaves,filter,first_s,steady_s,cells,open_edges,groups_visited\n");
  for (const auto& f : forests)
  {
    canopy::tools::SyntheticForestOptions options;
    options.dimension = f[0];
    options.rootsPerAxis = f[1];
    options.maxLevels = f[2];
    options.cutaway = false; // VTK 9.2's hypertree-grid cursors assert below masked nodes
    canopy::tools::SyntheticForest forest(options);
    auto htg = canopy::buildHyperTreeGrid(forest.description());
    double bounds[6];
    htg->GetBounds(bounds);
    const std::string name =
        std::to_string(f[0]) + "D/" + std::to_string(f[1]) + "/" + std::to_string(f[2]);
    for (int prune : {1, 0})
    {
      vtkNew<vtkCanopyContour> canopy;
      canopy->SetInputData(htg);
      canopy->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "density");
      canopy->SetValue(0, value);
      canopy->SetComputeNormals(true);
      canopy->SetPruning(prune != 0);
      Result r = timeFilter(canopy.GetPointer(), repetitions);
      r.triangles = canopy->GetOutput()->GetNumberOfCells();
      r.open = f[0] == 3 ? openEdges(canopy->GetOutput(), bounds) : 0;
      std::printf("%s,%zu,canopy%s,%.4f,%.4f,%lld,%zu,%lld\n", name.c_str(),
                  forest.numberOfLeaves(), prune ? "" : "_no_pruning", r.first, r.best,
                  static_cast<long long>(r.triangles), r.open,
                  static_cast<long long>(canopy->GetLastVisited()));
      std::fflush(stdout);
    }
    if (canopyOnly)
    {
      continue;
    }
    vtkNew<vtkHyperTreeGridContour> vtk;
    vtk->SetInputData(htg);
    vtk->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "density");
    vtk->SetValue(0, value);
    Result r = timeFilter(vtk.GetPointer(), std::min(repetitions, 1));
    vtkPolyData* out = vtkPolyData::SafeDownCast(vtk->GetOutputDataObject(0));
    r.triangles = out ? out->GetNumberOfCells() : 0;
    r.open = out && f[0] == 3 ? openEdges(out, bounds) : 0;
    std::printf("%s,%zu,vtkHyperTreeGridContour,%.4f,%.4f,%lld,%zu,\n", name.c_str(),
                forest.numberOfLeaves(), r.first, r.best, static_cast<long long>(r.triangles),
                r.open);
    std::fflush(stdout);
  }
  return 0;
}
