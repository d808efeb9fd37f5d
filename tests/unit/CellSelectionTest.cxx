// CellSelection (adaptor/filters/CellSelection.h), through its own header:
// which nodes a selection picks, outside VTK's pipeline. Its location rule
// (cells half-open [lo, hi) along each axis, the grid's last cell also owning
// the upper boundary: a point on a shared face, edge or corner belongs to the
// cell on its upper side) on hand-worked forests, 2D binary and ternary and 3D,
// where each point's cell is worked out by hand; then every selection mode
// against a brute force over all nodes read with VTK's cursors (bounds exact:
// binary trees over dyadic coordinates): locations at every leaf's corners, edge
// midpoints and centres, ids, value ranges, boxes (with the nodes a box
// selection visits), and the complement.
#include "CellSelection.h"
#include "RandomForest.h"

#include <canopy/HtgBuilder.h>

#include <gtest/gtest.h>
#include <vtkBitArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <ostream>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace canopy::testing
{
namespace
{

/// A forest written out by hand: root coordinates, and per tree its root cell,
/// breadth-first refinement and mask.
struct HandTree
{
  std::int64_t root;
  std::vector<std::uint8_t> refinement;
  std::vector<std::uint8_t> masked;
};

vtkSmartPointer<vtkHyperTreeGrid> buildHandForest(int dimension, int branchFactor,
                                                  const std::array<std::vector<double>, 3>& axes,
                                                  const std::vector<HandTree>& trees)
{
  ForestDescription d;
  d.dimension = dimension;
  d.branchFactor = branchFactor;
  d.maxLevels = 8;
  d.rootGrid = {axes[0].data(), axes[1].data(), axes[2].data(),
                axes[0].size(), axes[1].size(), axes[2].size()};
  for (const HandTree& t : trees)
  {
    d.trees.push_back({t.root, t.refinement.data(), t.refinement.size(),
                       t.masked.empty() ? nullptr : t.masked.data(), nullptr, nullptr});
  }
  return buildHyperTreeGrid(d, FieldRequest::none());
}

/// What a point selected, or why it selected nothing.
struct Expected
{
  Vec3 point;
  enum
  {
    Cell,
    Outside,
    Masked
  } outcome;
  vtkIdType root = -1; ///< its tree's root cell
  int level = 0;
  std::array<std::int64_t, 3> ijk{{0, 0, 0}};
};

Expected at(Vec3 p, vtkIdType root, int level, std::array<std::int64_t, 3> ijk)
{
  return {p, Expected::Cell, root, level, ijk};
}
Expected outside(Vec3 p)
{
  return {p, Expected::Outside};
}
Expected masked(Vec3 p)
{
  return {p, Expected::Masked};
}

/// Each point alone (no duplicates): what it selects is what the table says.
void expectLocations(const HyperTreeAccess& access, bool allowMasked,
                     const std::vector<Expected>& table)
{
  const CellSelection selection(access, allowMasked);
  for (const Expected& e : table)
  {
    SCOPED_TRACE("point (" + std::to_string(e.point[0]) + ", " + std::to_string(e.point[1]) + ", " +
                 std::to_string(e.point[2]) + ")");
    SelectionReport report;
    const auto nodes = selection.byLocation({e.point}, report);
    EXPECT_EQ(report.outside, e.outcome == Expected::Outside ? 1u : 0u);
    EXPECT_EQ(report.masked, e.outcome == Expected::Masked ? 1u : 0u);
    EXPECT_EQ(report.duplicates, 0u);
    ASSERT_EQ(nodes.size(), e.outcome == Expected::Cell ? 1u : 0u);
    if (e.outcome == Expected::Cell)
    {
      EXPECT_EQ(nodes[0].tree->treeIndex, e.root);
      EXPECT_EQ(nodes[0].level, e.level);
      EXPECT_EQ(nodes[0].ijk, e.ijk);
      EXPECT_EQ(nodes[0].global, nodes[0].tree->globalIndex(nodes[0].node));
      EXPECT_TRUE(nodes[0].tree->isLeaf(nodes[0].node));
    }
  }
}

constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

// 2x2 root cells of side 1 on [0, 2]^2 (the XY plane at z = 0.5):
//   root 0 ([0,1]^2): refined once (children of side 0.5);
//   root 1 ([1,2]x[0,1]): a leaf;
//   root 2 ([0,1]x[1,2]): no tree;
//   root 3 ([1,2]^2): refined, its child 0 ([1,1.5]^2) refined again (side
//   0.25), its child 1 ([1.5,2]x[1,1.5]) masked.
// Child c has digits (c % 2, c / 2): x fastest.
vtkSmartPointer<vtkHyperTreeGrid> handForest2D()
{
  static const std::array<std::vector<double>, 3> axes{{{0, 1, 2}, {0, 1, 2}, {0.5}}};
  return buildHandForest(2, 2, axes,
                         {{0, {1, 0, 0, 0, 0}, {0, 0, 0, 0, 0}},
                          {1, {0}, {0}},
                          {3, {1, 1, 0, 0, 0, 0, 0, 0, 0}, {0, 0, 1, 0, 0, 0, 0, 0, 0}}});
}

TEST(CellSelectionByLocation, PointsOnSharedFacesEdgesAndCornersGoToTheUpperSide2D)
{
  vtkSmartPointer<vtkHyperTreeGrid> grid = handForest2D();
  const HyperTreeAccess access(grid);
  expectLocations(access, false,
                  {
                      // The corner of roots 0, 1, 2 (no tree) and 3: root 3, whose
                      // finest cell there is [1, 1.25]^2.
                      at({{1, 1, 0.5}}, 3, 2, {{0, 0, 0}}),
                      // The corner of root 0's four children: the upper one.
                      at({{0.5, 0.5, 0.5}}, 0, 1, {{1, 1, 0}}),
                      // On the face between roots 0 and 1: root 1.
                      at({{1, 0.5, 0.5}}, 1, 0, {{0, 0, 0}}),
                      at({{1, 0, 0.5}}, 1, 0, {{0, 0, 0}}),
                      // The domain's upper corner and faces: the last cells.
                      at({{2, 2, 0.5}}, 3, 1, {{1, 1, 0}}),
                      at({{2, 0, 0.5}}, 1, 0, {{0, 0, 0}}),
                      at({{2, 0.25, 0.5}}, 1, 0, {{0, 0, 0}}),
                      // On root 0's upper face: root 2's, which has no tree.
                      outside({{0.25, 1, 0.5}}),
                      // The lower boundary belongs to the first cells.
                      at({{0, 0, 0.5}}, 0, 1, {{0, 0, 0}}),
                      // Inside root 3: corners at every level.
                      at({{1.5, 1.5, 0.5}}, 3, 1, {{1, 1, 0}}),
                      at({{1.25, 1.25, 0.5}}, 3, 2, {{1, 1, 0}}),
                      at({{1.25, 1.5, 0.5}}, 3, 1, {{0, 1, 0}}),
                      // On the face between [1, 1.5]^2 and the masked [1.5, 2] x
                      // [1, 1.5]: the masked one, not its visible neighbour.
                      masked({{1.5, 1.25, 0.5}}),
                      masked({{1.75, 1.25, 0.5}}),
                      // A root cell without a tree, outside the domain, NaN.
                      outside({{0.5, 1.5, 0.5}}),
                      outside({{-0.001, 0.5, 0.5}}),
                      outside({{2.0000001, 1, 0.5}}),
                      outside({{1, 2.5, 0.5}}),
                      outside({{NaN, 0.5, 0.5}}),
                      // The coordinate along the flat axis is ignored.
                      at({{0.25, 0.25, 1e6}}, 0, 1, {{0, 0, 0}}),
                      at({{0.25, 0.25, NaN}}, 0, 1, {{0, 0, 0}}),
                  });
  // Masked cells may be selected when allowed: the leaf itself.
  expectLocations(
      access, true,
      {at({{1.5, 1.25, 0.5}}, 3, 1, {{1, 0, 0}}), at({{1.75, 1.25, 0.5}}, 3, 1, {{1, 0, 0}})});
}

TEST(CellSelectionByLocation, PointsOnSharedFacesTernary)
{
  // One root [0, 9]^2, children of side 3, its centre child ([3, 6]^2) refined
  // into cells of side 1: every bound is an integer.
  static const std::array<std::vector<double>, 3> axes{{{0, 9}, {0, 9}, {0}}};
  std::vector<std::uint8_t> refinement(1 + 9 + 9, 0);
  refinement[0] = 1;
  refinement[1 + 4] = 1;
  vtkSmartPointer<vtkHyperTreeGrid> grid = buildHandForest(2, 3, axes, {{0, refinement, {}}});
  const HyperTreeAccess access(grid);
  expectLocations(access, false,
                  {at({{3, 3, 0}}, 0, 2, {{3, 3, 0}}), at({{4, 4, 0}}, 0, 2, {{4, 4, 0}}),
                   at({{5, 6, 0}}, 0, 1, {{1, 2, 0}}), at({{6, 6, 0}}, 0, 1, {{2, 2, 0}}),
                   at({{6, 3, 0}}, 0, 1, {{2, 1, 0}}), at({{9, 9, 0}}, 0, 1, {{2, 2, 0}}),
                   at({{5.5, 5.5, 0}}, 0, 2, {{5, 5, 0}}), at({{0, 9, 0}}, 0, 1, {{0, 2, 0}})});
}

TEST(CellSelectionByLocation, PointsOnSharedFacesEdgesAndCorners3D)
{
  // Roots [0,1] and [1,2] along x; root 0 refined once (side 0.5).
  static const std::array<std::vector<double>, 3> axes{{{0, 1, 2}, {0, 1}, {0, 1}}};
  std::vector<std::uint8_t> refinement(9, 0);
  refinement[0] = 1;
  vtkSmartPointer<vtkHyperTreeGrid> grid =
      buildHandForest(3, 2, axes, {{0, refinement, {}}, {1, {0}, {}}});
  const HyperTreeAccess access(grid);
  expectLocations(access, false,
                  {// The corner of eight children, an edge of four, a face of two.
                   at({{0.5, 0.5, 0.5}}, 0, 1, {{1, 1, 1}}),
                   at({{0.5, 0.5, 0.25}}, 0, 1, {{1, 1, 0}}),
                   at({{0.25, 0.5, 0.25}}, 0, 1, {{0, 1, 0}}),
                   // On the upper faces of the domain along y and z.
                   at({{0.5, 0.25, 1}}, 0, 1, {{1, 0, 1}}), at({{0.25, 1, 1}}, 0, 1, {{0, 1, 1}}),
                   // The face between the roots: root 1.
                   at({{1, 0.5, 0.5}}, 1, 0, {{0, 0, 0}}), at({{1, 1, 1}}, 1, 0, {{0, 0, 0}}),
                   at({{2, 1, 1}}, 1, 0, {{0, 0, 0}}), outside({{2, 1, 1.0000001}})});
}

TEST(CellSelectionByLocation, DuplicatesAndCountsOverManyPoints)
{
  vtkSmartPointer<vtkHyperTreeGrid> grid = handForest2D();
  const HyperTreeAccess access(grid);
  const CellSelection selection(access, false);
  SelectionReport report;
  const auto nodes = selection.byLocation({{{0.5, 0.5, 0}},
                                           {{0.6, 0.6, 0}},
                                           {{1, 0.5, 0}},
                                           {{2, 0, 0}},
                                           {{1.75, 1.25, 0}},
                                           {{0.5, 1.5, 0}},
                                           {{-1, 0, 0}},
                                           {{1.9, 0.9, 0}}},
                                          report);
  ASSERT_EQ(nodes.size(), 2u);
  EXPECT_EQ(nodes[0].tree->treeIndex, 0);
  EXPECT_EQ(nodes[1].tree->treeIndex, 1);
  EXPECT_EQ(report.duplicates, 3u); // (0.6, 0.6) in root 0's child 3; (2, 0), (1.9, 0.9) in root 1
  EXPECT_EQ(report.masked, 1u);
  EXPECT_EQ(report.outside, 2u);
}

// ---- Brute force over random forests (binary, dyadic coordinates) ----

/// Every node as VTK's cursors see it (masks ignored, so masked subtrees too).
struct NodeBox
{
  vtkIdType global;
  vtkIdType tree;
  int level;
  std::array<double, 6> bounds;
  bool leaf;
  bool hidden; ///< itself or an ancestor masked
  std::vector<vtkIdType> children;
};

/// All nodes by global index, and the tree roots' globals.
struct Nodes
{
  std::map<vtkIdType, NodeBox> byGlobal;
  std::vector<vtkIdType> roots;
};

Nodes allNodes(vtkHyperTreeGrid* masked)
{
  // VTK's cursors refuse to enter a masked node: walk a copy without the mask,
  // reading the mask's bits from the grid.
  vtkBitArray* mask = masked->HasMask() ? masked->GetMask() : nullptr;
  vtkNew<vtkHyperTreeGrid> grid;
  grid->ShallowCopy(masked);
  grid->SetMask(nullptr);
  Nodes nodes;
  vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
  grid->InitializeTreeIterator(it);
  vtkIdType index = 0;
  while (it.GetNextTree(index))
  {
    vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> cursor;
    grid->InitializeNonOrientedGeometryCursor(cursor, index);
    nodes.roots.push_back(cursor->GetGlobalNodeIndex());
    auto walk = [&](auto& self, bool hiddenAbove) -> vtkIdType
    {
      NodeBox box;
      box.global = cursor->GetGlobalNodeIndex();
      box.tree = index;
      box.level = static_cast<int>(cursor->GetLevel());
      cursor->GetBounds(box.bounds.data());
      box.leaf = cursor->IsLeaf();
      box.hidden = hiddenAbove || (mask != nullptr && mask->GetValue(box.global) != 0);
      if (!box.leaf)
      {
        for (unsigned char c = 0; c < cursor->GetNumberOfChildren(); ++c)
        {
          cursor->ToChild(c);
          box.children.push_back(self(self, box.hidden));
          cursor->ToParent();
        }
      }
      nodes.byGlobal[box.global] = box;
      return box.global;
    };
    walk(walk, false);
  }
  return nodes;
}

/// Dyadic, non-uniform root coordinates for `points` points from `origin`.
std::vector<double> dyadicAxis(std::size_t points, double origin)
{
  static const double widths[] = {0.5, 0.75, 1.25, 1.0, 0.625};
  std::vector<double> axis{origin};
  for (std::size_t i = 1; i < points; ++i)
  {
    axis.push_back(axis.back() + widths[i % 5]);
  }
  return axis;
}

struct RandomCase
{
  int dimension;
  std::uint64_t seed;
};

/// A random binary forest (masked nodes, every other root without a tree) on
/// dyadic coordinates, with a node field "value" (NaN now and then) and a
/// two-component "vector".
class CellSelectionBruteForce : public ::testing::TestWithParam<RandomCase>
{
protected:
  void SetUp() override
  {
    RandomForestOptions o;
    o.dimension = GetParam().dimension;
    o.rootCells = o.dimension == 2 ? std::array<std::size_t, 3>{{6, 5, 1}}
                                   : std::array<std::size_t, 3>{{3, 3, 2}};
    o.maxLevels = 4;
    o.refineProbability = 0.45;
    o.maskProbability = 0.12;
    o.skipEveryOtherRoot = true;
    o.seed = GetParam().seed;
    Forest = std::make_unique<RandomForest>(o);
    ForestDescription& d = Forest->description();
    for (int a = 0; a < 3; ++a)
    {
      const std::size_t points = a == 0   ? d.rootGrid.pointsX
                                 : a == 1 ? d.rootGrid.pointsY
                                          : d.rootGrid.pointsZ;
      Axes[a] = dyadicAxis(points, -1.0 + 0.5 * a);
    }
    d.rootGrid.x = Axes[0].data();
    d.rootGrid.y = Axes[1].data();
    d.rootGrid.z = Axes[2].data();
    std::mt19937_64 random(GetParam().seed + 100);
    std::uniform_int_distribution<int> level(0, 7);
    for (std::size_t n = 0; n < Forest->numberOfNodes(); ++n)
    {
      // Few distinct values, so that range bounds equal some of them exactly.
      Values.push_back(n % 17 == 0 ? NaN : 0.5 * level(random));
      Vectors.push_back(level(random) - 3.0);
      Vectors.push_back(level(random) - 3.0);
    }
    d.fields.push_back(FieldDescription::aos("value", Values.data(), Values.size()));
    d.fields.push_back(FieldDescription::aos("vector", Vectors.data(), Values.size(), 2));
    Grid = buildHyperTreeGrid(d);
    Access = std::make_unique<HyperTreeAccess>(Grid);
    All = allNodes(Grid);
  }

  /// The point's leaf by the rule, or nullptr (outside, or a root without a tree).
  const NodeBox* leafContaining(const Vec3& p) const
  {
    const auto& domain = Access->bounds();
    const NodeBox* found = nullptr;
    for (const auto& [global, node] : All.byGlobal)
    {
      if (!node.leaf)
      {
        continue;
      }
      bool inside = true;
      for (int a : Access->activeAxes())
      {
        const double lo = node.bounds[2 * a];
        const double hi = node.bounds[2 * a + 1];
        inside = inside && ((lo <= p[a] && p[a] < hi) || (p[a] == hi && hi == domain[2 * a + 1]));
      }
      if (inside)
      {
        EXPECT_EQ(found, nullptr) << "two leaves hold a point: the brute force is wrong";
        found = &node;
      }
    }
    return found;
  }

  /// Leaves a selection may return: not hidden, or masked with allowMasked.
  std::set<vtkIdType> selectableLeaves(bool allowMasked) const
  {
    std::set<vtkIdType> leaves;
    for (const auto& [global, node] : All.byGlobal)
    {
      if (node.leaf && (allowMasked || !node.hidden))
      {
        leaves.insert(global);
      }
    }
    return leaves;
  }

  static std::set<vtkIdType> globals(const std::vector<SelectedNode>& nodes)
  {
    std::set<vtkIdType> ids;
    for (const SelectedNode& n : nodes)
    {
      EXPECT_TRUE(ids.insert(n.global).second) << "selected twice: " << n.global;
    }
    return ids;
  }

  /// Each selected node's level and bounds are VTK's for that cell.
  void expectCursorsAgree(const CellSelection& selection, const std::vector<SelectedNode>& nodes)
  {
    for (const SelectedNode& n : nodes)
    {
      const NodeBox& box = All.byGlobal.at(n.global);
      EXPECT_EQ(n.level, box.level) << "cell " << n.global;
      Vec3 lo;
      Vec3 hi;
      selection.bounds(n, lo, hi);
      for (int a = 0; a < 3; ++a)
      {
        EXPECT_EQ(lo[a], box.bounds[2 * a]) << "cell " << n.global;
        EXPECT_EQ(hi[a], box.bounds[2 * a + 1]) << "cell " << n.global;
      }
    }
  }

  std::unique_ptr<RandomForest> Forest;
  std::array<std::vector<double>, 3> Axes;
  std::vector<double> Values;
  std::vector<double> Vectors;
  vtkSmartPointer<vtkHyperTreeGrid> Grid;
  std::unique_ptr<HyperTreeAccess> Access;
  Nodes All;
};

TEST_P(CellSelectionBruteForce, LocationsAtEveryLeafsCornersMidpointsAndCentre)
{
  // Each leaf's corners, edge and face midpoints and centre (3^d points), the
  // domain's corners, and points just outside it.
  std::vector<Vec3> points;
  for (const auto& [global, node] : All.byGlobal)
  {
    if (!node.leaf)
    {
      continue;
    }
    const int d = Access->dimension();
    int count = 1;
    for (int i = 0; i < d; ++i)
    {
      count *= 3;
    }
    for (int k = 0; k < count; ++k)
    {
      Vec3 p{{node.bounds[0], node.bounds[2], node.bounds[4]}};
      int rest = k;
      for (int a : Access->activeAxes())
      {
        const double lo = node.bounds[2 * a];
        const double hi = node.bounds[2 * a + 1];
        p[a] = rest % 3 == 0 ? lo : rest % 3 == 1 ? 0.5 * (lo + hi) : hi;
        rest /= 3;
      }
      points.push_back(p);
    }
  }
  const auto& b = Access->bounds();
  points.push_back({{b[1], b[3], b[5]}});
  points.push_back({{b[0], b[2], b[4]}});
  points.push_back({{b[1] + 1e-9, b[2], b[4]}});
  points.push_back({{b[0], b[2] - 1e-9, b[4]}});
  for (bool allowMasked : {false, true})
  {
    SCOPED_TRACE(allowMasked ? "masked allowed" : "masked not allowed");
    const CellSelection selection(*Access, allowMasked);
    SelectionReport report;
    const auto nodes = selection.byLocation(points, report);
    std::vector<vtkIdType> expected;
    std::set<vtkIdType> seen;
    SelectionReport counts;
    for (const Vec3& p : points)
    {
      const NodeBox* leaf = leafContaining(p);
      if (leaf == nullptr)
      {
        ++counts.outside;
      }
      else if (leaf->hidden && !allowMasked)
      {
        ++counts.masked;
      }
      else if (!seen.insert(leaf->global).second)
      {
        ++counts.duplicates;
      }
      else
      {
        expected.push_back(leaf->global);
      }
    }
    std::vector<vtkIdType> got;
    for (const SelectedNode& n : nodes)
    {
      got.push_back(n.global);
    }
    EXPECT_EQ(got, expected) << "in the points' order";
    EXPECT_EQ(report.outside, counts.outside);
    EXPECT_EQ(report.masked, counts.masked);
    EXPECT_EQ(report.duplicates, counts.duplicates);
    if (!allowMasked)
    {
      EXPECT_GT(counts.masked, 0u) << "premise: masked cells are hit";
    }
    expectCursorsAgree(selection, nodes);
  }
}

TEST_P(CellSelectionBruteForce, IdsSelectCoarseAndFineNodes)
{
  std::mt19937_64 random(GetParam().seed);
  const auto cells = static_cast<vtkIdType>(Access->numberOfCells());
  std::uniform_int_distribution<vtkIdType> id(-3, cells + 2);
  std::vector<vtkIdType> ids;
  for (int i = 0; i < 300; ++i)
  {
    ids.push_back(id(random));
  }
  for (bool allowMasked : {false, true})
  {
    SCOPED_TRACE(allowMasked ? "masked allowed" : "masked not allowed");
    const CellSelection selection(*Access, allowMasked);
    SelectionReport report;
    const auto nodes = selection.byId(ids, report);
    std::set<vtkIdType> expected;
    std::set<vtkIdType> asked;
    SelectionReport counts;
    for (vtkIdType i : ids)
    {
      if (i < 0 || i >= cells)
      {
        ++counts.outOfRange;
      }
      else if (!asked.insert(i).second)
      {
        ++counts.duplicates;
      }
      else if (All.byGlobal.at(i).hidden && !allowMasked)
      {
        ++counts.masked;
      }
      else
      {
        expected.insert(i);
      }
    }
    EXPECT_EQ(globals(nodes), expected);
    EXPECT_EQ(report.outOfRange, counts.outOfRange);
    EXPECT_EQ(report.duplicates, counts.duplicates);
    EXPECT_EQ(report.masked, counts.masked);
    expectCursorsAgree(selection, nodes);
    // In tree order.
    for (std::size_t k = 1; k < nodes.size(); ++k)
    {
      EXPECT_LE(nodes[k - 1].tree, nodes[k].tree);
    }
  }
}

TEST_P(CellSelectionBruteForce, ValueRangesWithExactBoundsNaNAndMagnitudes)
{
  vtkDataArray* values = Grid->GetCellData()->GetArray("value");
  vtkDataArray* vectors = Grid->GetCellData()->GetArray("vector");
  ASSERT_NE(values, nullptr);
  ASSERT_NE(vectors, nullptr);
  struct Range
  {
    vtkDataArray* array;
    int component;
    double low;
    double high;
  };
  for (const Range& r : {Range{values, 0, 1.0, 2.5}, Range{values, 0, 1.5, 1.5},
                         Range{values, 0, -HUGE_VAL, HUGE_VAL}, Range{vectors, 1, -1, 0},
                         Range{vectors, -1, 0, std::sqrt(8.0)}, Range{vectors, -1, 5, 5}})
  {
    for (bool allowMasked : {false, true})
    {
      const CellSelection selection(*Access, allowMasked);
      const auto nodes = selection.byValue(r.array, r.component, r.low, r.high);
      std::set<vtkIdType> expected;
      for (vtkIdType leaf : selectableLeaves(allowMasked))
      {
        double v = 0;
        if (r.component >= 0)
        {
          v = r.array->GetComponent(leaf, r.component);
        }
        else
        {
          const double x = r.array->GetComponent(leaf, 0);
          const double y = r.array->GetComponent(leaf, 1);
          v = std::sqrt(x * x + y * y);
        }
        if (v >= r.low && v <= r.high)
        {
          expected.insert(leaf);
        }
      }
      EXPECT_EQ(globals(nodes), expected)
          << "component " << r.component << ", [" << r.low << ", " << r.high << "]";
      EXPECT_FALSE(expected.empty()) << "premise: the range selects something: component "
                                     << r.component << ", [" << r.low << ", " << r.high << "]";
    }
  }
}

TEST_P(CellSelectionBruteForce, BoxesSelectLeavesOverlappingThemAndVisitOnlyWhatOverlaps)
{
  // Boxes on the leaves' own bounds (touching neighbours must not be selected),
  // random boxes, boxes of zero thickness, boxes reaching outside.
  std::mt19937_64 random(GetParam().seed + 7);
  const auto& b = Access->bounds();
  std::vector<std::array<double, 6>> boxes;
  std::vector<vtkIdType> leaves;
  for (const auto& [global, node] : All.byGlobal)
  {
    if (node.leaf && !node.hidden)
    {
      leaves.push_back(global);
    }
  }
  for (int i = 0; i < 6; ++i)
  {
    const NodeBox& leaf = All.byGlobal.at(leaves[random() % leaves.size()]);
    std::array<double, 6> box;
    std::copy(leaf.bounds.begin(), leaf.bounds.end(), box.begin());
    boxes.push_back(box);
  }
  std::uniform_real_distribution<double> unit(0, 1);
  for (int i = 0; i < 20; ++i)
  {
    std::array<double, 6> box;
    for (int a = 0; a < 3; ++a)
    {
      double x = b[2 * a] - 0.5 + (b[2 * a + 1] - b[2 * a] + 1) * unit(random);
      double y = b[2 * a] - 0.5 + (b[2 * a + 1] - b[2 * a] + 1) * unit(random);
      box[2 * a] = std::min(x, y);
      box[2 * a + 1] = i % 5 == 0 && a == 0 ? box[2 * a] : std::max(x, y);
    }
    boxes.push_back(box);
  }
  for (const auto& box : boxes)
  {
    const CellSelection selection(*Access, false);
    const SelectionRegion region = selection.boxRegion(box);
    SelectionReport report;
    const auto nodes = selection.byRegion(region, report);
    // Brute force: every visible leaf whose box overlaps with positive length
    // along each active axis; and the walk: roots, then the children of every
    // visible, overlapping coarse node.
    auto overlaps = [&](const NodeBox& n)
    {
      for (int a : Access->activeAxes())
      {
        if (!(std::max(n.bounds[2 * a], box[2 * a]) <
              std::min(n.bounds[2 * a + 1], box[2 * a + 1])))
        {
          return false;
        }
      }
      return true;
    };
    std::set<vtkIdType> expected;
    std::size_t visited = 0;
    auto walk = [&](auto& self, vtkIdType global) -> void
    {
      ++visited;
      const NodeBox& n = All.byGlobal.at(global);
      if (n.hidden || !overlaps(n))
      {
        return;
      }
      if (n.leaf)
      {
        expected.insert(global);
      }
      for (vtkIdType child : n.children)
      {
        self(self, child);
      }
    };
    for (vtkIdType root : All.roots)
    {
      walk(walk, root);
    }
    EXPECT_EQ(globals(nodes), expected);
    EXPECT_EQ(report.visited, visited);
    expectCursorsAgree(selection, nodes);
    // contains(): a box inside the region holds only selected leaves.
    for (const auto& [global, node] : All.byGlobal)
    {
      const Vec3 lo{{node.bounds[0], node.bounds[2], node.bounds[4]}};
      const Vec3 hi{{node.bounds[1], node.bounds[3], node.bounds[5]}};
      if (region.contains(lo, hi))
      {
        EXPECT_TRUE(overlaps(node)) << "cell " << global << " is contained but does not overlap";
      }
    }
  }
}

TEST_P(CellSelectionBruteForce, TheComplementIsEverySelectableLeafNotSelected)
{
  std::mt19937_64 random(GetParam().seed + 3);
  for (bool allowMasked : {false, true})
  {
    const CellSelection selection(*Access, allowMasked);
    // Some coarse nodes and some leaves, by id.
    std::vector<vtkIdType> ids;
    for (int i = 0; i < 12; ++i)
    {
      ids.push_back(static_cast<vtkIdType>(random() % Access->numberOfCells()));
    }
    SelectionReport report;
    const auto chosen = selection.byId(ids, report);
    const auto rest = selection.complement(chosen);
    // Leaves below a chosen node are left out with it.
    std::set<vtkIdType> covered;
    auto cover = [&](auto& self, vtkIdType global) -> void
    {
      covered.insert(global);
      for (vtkIdType child : All.byGlobal.at(global).children)
      {
        self(self, child);
      }
    };
    for (const SelectedNode& n : chosen)
    {
      cover(cover, n.global);
    }
    std::set<vtkIdType> expected;
    for (vtkIdType leaf : selectableLeaves(allowMasked))
    {
      if (!covered.count(leaf))
      {
        expected.insert(leaf);
      }
    }
    EXPECT_EQ(globals(rest), expected);
    EXPECT_FALSE(chosen.empty()) << "premise: some ids were selectable";
  }
}

void PrintTo(const RandomCase& c, std::ostream* out)
{
  *out << c.dimension << "D, seed " << c.seed;
}

std::string caseName(const ::testing::TestParamInfo<RandomCase>& info)
{
  return std::to_string(info.param.dimension) + "D_seed" + std::to_string(info.param.seed);
}

INSTANTIATE_TEST_SUITE_P(Forests, CellSelectionBruteForce,
                         ::testing::Values(RandomCase{2, 1}, RandomCase{2, 2}, RandomCase{3, 3},
                                           RandomCase{3, 4}),
                         caseName);

} // namespace
} // namespace canopy::testing
