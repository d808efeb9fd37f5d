// Contours of a forest split between ranks (ContourGhosts.h): every rank
// contours its part with the other ranks' border leaves; rank 0 gathers every
// rank's cells and compares them with the contour of the whole forest on one
// process: the same cells, point for point to the last bit, each drawn by
// exactly one rank. A gap along a rank border (a cell no rank draws), an
// overlap (a cell two ranks draw) or a point two ranks compute differently
// (a crack) fails it. Trees cut between ranks (p4est's partition) and whole
// trees dealt out in turn; 2D and 3D, binary and ternary; a linear field
// (whose contour is also on its plane) and a wavy one; full resolution and
// a maximum level. Run with mpirun -np 1, 2 and 4.
#include "GatherPieces.h"
#include "NodeCentreField.h"
#include "RandomForest.h"
#include "RankForestPart.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyContour.h>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace canopy::testing
{
namespace
{

vtkMultiProcessController* world()
{
  return vtkMultiProcessController::GetGlobalController();
}

using Field = std::function<double(const double*)>;

vtkSmartPointer<vtkHyperTreeGrid> partOf(const ForestDescription& whole, bool splitTrees,
                                         std::shared_ptr<void>& keep)
{
  return rankForestPart(whole, splitTrees, world()->GetLocalProcessId(),
                        world()->GetNumberOfProcesses(), keep);
}

vtkSmartPointer<vtkPolyData> contourOf(vtkHyperTreeGrid* htg, const char* field, double value,
                                       int maximumLevel, vtkMultiProcessController* controller,
                                       vtkIdType* ghosts = nullptr)
{
  vtkNew<vtkCanopyContour> filter;
  filter->SetController(controller);
  filter->SetInputData(htg);
  filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, field);
  filter->SetValue(0, value);
  filter->SetMaximumLevel(maximumLevel);
  filter->Update();
  if (ghosts)
  {
    *ghosts = filter->GetLastGhostsReceived();
  }
  return filter->GetOutput();
}

/// Each cell as its sorted points (exact coordinates).
using Cell = std::vector<std::array<double, 3>>;
std::vector<Cell> cellsOf(vtkPolyData* out)
{
  std::vector<Cell> cells;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    out->GetCellPoints(c, n, ids);
    Cell cell;
    for (vtkIdType k = 0; k < n; ++k)
    {
      std::array<double, 3> x;
      out->GetPoint(ids[k], x.data());
      cell.push_back(x);
    }
    std::sort(cell.begin(), cell.end());
    cells.push_back(cell);
  }
  return cells;
}

/// Rank 0: the gathered contour is watertight (3D: every triangle edge not on
/// the domain's boundary used by exactly two triangles; 2D: every segment end
/// inside the domain by exactly two segments), has no cell twice, and with a
/// linear field every point on its plane. Returns the cells checked.
std::size_t expectWatertight(vtkPolyData* all, vtkHyperTreeGrid* whole, const Field* linear,
                             double value, const std::string& what)
{
  double b[6];
  whole->GetBounds(b);
  const int dimension = static_cast<int>(whole->GetDimension());
  // Points all on one side of the domain's box: an edge (3D) or an end (2D)
  // along the boundary, used once.
  auto onBoundary = [&](const std::vector<std::array<double, 3>>& points)
  {
    for (int a = 0; a < 3; ++a)
    {
      for (int side = 0; side < 2 && b[2 * a] < b[2 * a + 1]; ++side)
      {
        if (std::all_of(points.begin(), points.end(),
                        [&](const std::array<double, 3>& x) { return x[a] == b[2 * a + side]; }))
        {
          return true;
        }
      }
    }
    return false;
  };
  const std::vector<Cell> cells = cellsOf(all);
  std::map<Cell, int> seen;
  std::map<std::vector<std::array<double, 3>>, int> uses;
  std::size_t offPlane = 0;
  for (const Cell& c : cells)
  {
    EXPECT_EQ(++seen[c], 1) << what << ": a cell drawn twice";
    for (std::size_t i = 0; i < c.size(); ++i)
    {
      if (linear && std::abs((*linear)(c[i].data()) - value) > 1e-9)
      {
        ++offPlane;
      }
      if (dimension == 2)
      {
        ++uses[{c[i]}];
        continue;
      }
      for (std::size_t j = i + 1; j < c.size(); ++j)
      {
        ++uses[{c[i], c[j]}];
      }
    }
  }
  std::size_t open = 0;
  for (const auto& entry : uses)
  {
    const bool boundary = onBoundary(entry.first);
    if (!boundary && entry.second != 2)
    {
      ++open;
    }
  }
  EXPECT_EQ(open, 0u) << what << ": edges or ends not shared by exactly two cells (a crack)";
  EXPECT_EQ(offPlane, 0u) << what << ": points off the linear field's plane";
  EXPECT_GT(cells.size(), 10u) << what;
  return cells.size();
}

struct Case
{
  int dimension;
  int branchFactor;
  std::array<std::size_t, 3> roots;
  int maxLevels;
  std::uint64_t seed;
};

TEST(SplitContour, RanksTogetherDrawTheWholeForestsContourOnce)
{
  const double a[3] = {0.7, -0.4, 0.55};
  const Field linear = [&](const double* x) { return a[0] * x[0] + a[1] * x[1] + a[2] * x[2]; };
  const Field wavy = [](const double* x)
  { return std::sin(2.1 * x[0]) * std::cos(1.7 * x[1]) + 0.5 * std::sin(1.3 * x[2] + 0.4); };
  const std::vector<Case> cases = {{2, 2, {{5, 4, 1}}, 7, 31},
                                   {2, 3, {{4, 3, 1}}, 5, 37},
                                   {3, 2, {{3, 3, 2}}, 5, 41},
                                   {3, 3, {{2, 2, 2}}, 3, 43}};
  const bool root = world()->GetLocalProcessId() == 0;
  std::size_t compared = 0;
  vtkIdType ghostsSeen = 0;
  for (const Case& k : cases)
  {
    RandomForestOptions o;
    o.dimension = k.dimension;
    o.branchFactor = k.branchFactor;
    o.rootCells = k.roots;
    o.maxLevels = k.maxLevels;
    o.refineProbability = 0.55;
    o.seed = k.seed;
    RandomForest whole(o);
    for (bool splitTrees : {true, false})
    {
      std::shared_ptr<void> keep;
      auto part = partOf(whole.description(), splitTrees, keep);
      addNodeCentreField(part, "linear", linear);
      addNodeCentreField(part, "wavy", wavy);
      vtkSmartPointer<vtkHyperTreeGrid> reference;
      if (root)
      {
        reference = buildHyperTreeGrid(whole.description());
        addNodeCentreField(reference, "linear", linear);
        addNodeCentreField(reference, "wavy", wavy);
      }
      for (const char* field : {"linear", "wavy"})
      {
        for (int maximumLevel : {-1, 2})
        {
          const std::string what = std::to_string(k.dimension) + "D, branch factor " +
                                   std::to_string(k.branchFactor) + ", " + field +
                                   (splitTrees ? ", trees split" : ", whole trees") +
                                   ", maximum level " + std::to_string(maximumLevel) + ", " +
                                   std::to_string(world()->GetNumberOfProcesses()) + " ranks";
          const bool linearField = std::string(field) == "linear";
          const double value = linearField ? 1.1 : 0.2;
          vtkIdType ghosts = 0;
          auto mine = contourOf(part, field, value, maximumLevel, world(), &ghosts);
          ghostsSeen += ghosts;
          vtkSmartPointer<vtkPolyData> all = gatherPieces(mine);
          if (!root)
          {
            continue;
          }
          if (splitTrees && maximumLevel >= 0)
          {
            // A node with several ranks' leaves below is not a leaf at the
            // maximum level (no rank could draw it alone): the ranks draw a
            // finer contour there than one process would. Checked as it is:
            // watertight, no cell twice, on the linear field's plane.
            compared +=
                expectWatertight(all, reference, linearField ? &linear : nullptr, value, what);
            continue;
          }
          auto whole1 = contourOf(reference, field, value, maximumLevel, nullptr);
          std::map<Cell, int> expected;
          for (const Cell& c : cellsOf(whole1))
          {
            ++expected[c];
          }
          EXPECT_GT(expected.size(), 15u) << what; // no ASSERT: the other ranks go on
          std::size_t extra = 0;
          for (const Cell& c : cellsOf(all))
          {
            const auto found = expected.find(c);
            if (found == expected.end())
            {
              ++extra;
              continue;
            }
            --found->second;
          }
          std::size_t missing = 0;
          std::size_t twice = 0;
          for (const auto& entry : expected)
          {
            missing += entry.second > 0 ? static_cast<std::size_t>(entry.second) : 0;
            twice += entry.second < 0 ? static_cast<std::size_t>(-entry.second) : 0;
          }
          EXPECT_EQ(missing, 0u) << what << ": cells no rank drew (a gap)";
          EXPECT_EQ(twice, 0u) << what << ": cells drawn twice (an overlap)";
          EXPECT_EQ(extra, 0u) << what << ": cells the whole forest does not have (a crack)";
          compared += expected.size();
        }
      }
    }
  }
  if (root)
  {
    EXPECT_GT(compared, 2000u);
    std::cout << compared << " cells compared; ghosts received by rank 0: " << ghostsSeen << "\n";
  }
  if (world()->GetNumberOfProcesses() > 1)
  {
    // Rank 0's part always borders another rank's: it must have received some.
    EXPECT_GT(ghostsSeen, 0);
  }
}

} // namespace
} // namespace canopy::testing
