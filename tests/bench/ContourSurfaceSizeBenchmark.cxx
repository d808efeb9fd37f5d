// Time against surface size: one blob, its surface at one resolution, in forests
// of 1e6 to 1e8 leaves. What grows is the rest of the domain's refinement
// (a background at values far from the contour's), not the surface.
//
// The domain: the unit cube, 16^3 roots. The field: a smoothed indicator of a
// ball, f = (1 + tanh((R - r) / w)) / 2 at the node's centre, r the distance to
// the cube's centre, R = 0.15, w = 1.25 h with h the edge of a level-5 node
// (1/512). Nodes within 4 w (plus their half diagonal) of the sphere r = R are
// refined to level 5: the blob's band, the same in every forest. Every other node
// is refined to the background level B (--background B...): 16^3 8^B leaves,
// B = 2, 3, 4, 5 gives 1.5e6, 3.4e6, 1.8e7 and 1.35e8 leaves in all. Outside the
// band f is within 0.0004 of 0 or 1, so the contour at 0.5 is the same
// triangles in every forest (checked: the run fails if the count differs).
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
#include <canopy/ForestDescription.h>
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

constexpr int Roots = 16;
constexpr int BandLevel = 5;
constexpr double Radius = 0.15;
constexpr double RootEdge = 1.0 / Roots;
const double BandEdge = RootEdge / (1 << BandLevel);
const double Width = 1.25 * BandEdge;
const double BandHalfWidth = 4 * Width;

double secondsSince(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double field(double x, double y, double z)
{
  const double r = std::sqrt((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5) + (z - 0.5) * (z - 0.5));
  return 0.5 * (1.0 + std::tanh((Radius - r) / Width));
}

/// The simulation's side: refinement bytes per tree and one value per node,
/// breadth-first, trees back to back.
class BlobForest
{
public:
  explicit BlobForest(int backgroundLevel)
  {
    for (int i = 0; i <= Roots; ++i)
    {
      Axis.push_back(i * RootEdge);
    }
    Description.dimension = 3;
    Description.branchFactor = 2;
    Description.maxLevels = BandLevel + 1;
    Description.rootGrid = {Axis.data(), Axis.data(), Axis.data(), Axis.size(), Axis.size(),
                            Axis.size()};
    Refinement.resize(static_cast<std::size_t>(Roots * Roots * Roots));
    for (int root = 0; root < Roots * Roots * Roots; ++root)
    {
      describeTree(root, backgroundLevel);
    }
    for (std::size_t root = 0; root < Refinement.size(); ++root)
    {
      canopy::TreeDescription tree;
      tree.rootIndex = static_cast<std::int64_t>(root);
      tree.refinement = Refinement[root].data();
      tree.numberOfNodes = Refinement[root].size();
      Description.trees.push_back(tree);
    }
    Description.fields.push_back(canopy::FieldDescription::aos("f", Values.data(), Values.size()));
  }

  const canopy::ForestDescription& description() const { return Description; }
  std::size_t leaves() const { return Leaves; }

private:
  struct Node
  {
    int level;
    std::array<std::int64_t, 3> index; ///< at its level, within the whole domain
  };

  void describeTree(int root, int backgroundLevel)
  {
    std::vector<std::uint8_t>& refinement = Refinement[static_cast<std::size_t>(root)];
    std::vector<Node> level{{0, {root % Roots, (root / Roots) % Roots, root / (Roots * Roots)}}};
    std::vector<Node> next;
    while (!level.empty())
    {
      next.clear();
      for (const Node& node : level)
      {
        const double edge = RootEdge / static_cast<double>(std::int64_t{1} << node.level);
        const double c[3] = {(node.index[0] + 0.5) * edge, (node.index[1] + 0.5) * edge,
                             (node.index[2] + 0.5) * edge};
        Values.push_back(field(c[0], c[1], c[2]));
        const double r = std::sqrt((c[0] - 0.5) * (c[0] - 0.5) + (c[1] - 0.5) * (c[1] - 0.5) +
                                   (c[2] - 0.5) * (c[2] - 0.5));
        const bool inBand = std::abs(r - Radius) <= BandHalfWidth + 0.5 * std::sqrt(3.0) * edge;
        const bool refine = node.level < (inBand ? BandLevel : std::min(backgroundLevel, BandLevel));
        refinement.push_back(refine ? 1 : 0);
        if (!refine)
        {
          ++Leaves;
          continue;
        }
        for (int k = 0; k < 2; ++k)
          for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i)
              next.push_back({node.level + 1,
                              {2 * node.index[0] + i, 2 * node.index[1] + j, 2 * node.index[2] + k}});
      }
      level.swap(next);
    }
  }

  std::vector<double> Axis;
  std::vector<std::vector<std::uint8_t>> Refinement;
  std::vector<double> Values;
  std::size_t Leaves = 0;
  canopy::ForestDescription Description;
};

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
    if (b < 0 || b > BandLevel)
    {
      std::fprintf(stderr, "--background %d: a level from 0 to %d\n", b, BandLevel);
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
    BlobForest forest(b);
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
