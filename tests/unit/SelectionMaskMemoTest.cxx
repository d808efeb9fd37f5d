// A masked selection (vtkCanopyExtractSelection with PreserveTopology) re-run
// at every step of a changing forest, as a shipped region pipeline runs: at
// every step its output must equal a new filter's, bit for bit (mask, VTK's
// pure mask, selected bounds), and it must redo exactly the trees whose inputs
// changed. Which trees those are is derived here from the grids themselves: a
// tree is new (GridBuilder rebuilt it), its cells' mask bits differ from the
// step before, or, for selections that read cells by number (ids, values), its
// first global index moved; every tree when the selection itself changed.
#include "ChangingForest.h"

#include <canopy/GridBuilder.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <gtest/gtest.h>
#include <vtkBitArray.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include <map>
#include <random>
#include <string>
#include <vector>

namespace canopy::testing
{
namespace
{

enum class Mode
{
  CutAway, ///< an inverted box: an octant removed
  Box,
  Frustum,
  Locations,
  Ids,
  ValueRange
};

std::string modeName(Mode mode)
{
  switch (mode)
  {
  case Mode::CutAway:
    return "CutAway";
  case Mode::Box:
    return "Box";
  case Mode::Frustum:
    return "Frustum";
  case Mode::Locations:
    return "Locations";
  case Mode::Ids:
    return "Ids";
  default:
    return "ValueRange";
  }
}

bool readsByCellNumber(Mode mode)
{
  return mode == Mode::Ids || mode == Mode::ValueRange;
}

/// Sets the filter's selection; `variant` moves the region (or the list, or the
/// range) a little, so that a step can change the selection itself.
void select(vtkCanopyExtractSelection* filter, Mode mode, const double bounds[6], int variant)
{
  filter->PreserveTopologyOn();
  const double shift = 0.07 * variant;
  double region[6];
  for (int a = 0; a < 3; ++a)
  {
    // Not along a 2D grid's flat axis: a frustum is cut by the grid's plane.
    const bool flat = bounds[2 * a] == bounds[2 * a + 1];
    const double mid = 0.5 * (bounds[2 * a] + bounds[2 * a + 1]) + (flat ? 0 : shift);
    region[2 * a] = mode == Mode::CutAway ? mid : bounds[2 * a] + 0.3 * (mid - bounds[2 * a]);
    region[2 * a + 1] = mode == Mode::CutAway ? bounds[2 * a + 1] + 1 : mid + 0.1;
  }
  switch (mode)
  {
  case Mode::CutAway:
  case Mode::Box:
    filter->SetSelectionMode(vtkCanopyExtractSelection::BOX);
    filter->SetBox(region);
    filter->SetInvert(mode == Mode::CutAway);
    break;
  case Mode::Frustum:
  {
    // The same box as six planes, normals inwards (a x + b y + c z + d >= 0).
    double planes[24] = {};
    for (int a = 0; a < 3; ++a)
    {
      planes[8 * a + a] = 1;
      planes[8 * a + 3] = -region[2 * a];
      planes[8 * a + 4 + a] = -1;
      planes[8 * a + 7] = region[2 * a + 1];
    }
    filter->SetSelectionMode(vtkCanopyExtractSelection::FRUSTUM);
    filter->SetFrustumPlanes(planes);
    break;
  }
  case Mode::Locations:
    filter->SetSelectionMode(vtkCanopyExtractSelection::LOCATIONS);
    filter->ClearLocations();
    for (int i = 0; i < 12; ++i)
    {
      const double f = (i + 0.5) / 12;
      filter->AddLocation(bounds[0] + f * (bounds[1] - bounds[0]) + shift,
                          bounds[2] + (1 - f) * (bounds[3] - bounds[2]),
                          0.5 * (bounds[4] + bounds[5]));
    }
    break;
  case Mode::Ids:
    filter->SetSelectionMode(vtkCanopyExtractSelection::IDS);
    filter->ClearIds();
    for (vtkIdType id = 3 + variant; id < 400; id += 7)
    {
      filter->AddId(id);
    }
    break;
  case Mode::ValueRange:
    filter->SetSelectionMode(vtkCanopyExtractSelection::VALUE_RANGE);
    filter->SetValueArrayName("leafValue");
    filter->SetValueRange(-1e30, 0.5 * variant - 40);
    break;
  }
}

/// Tree by tree, what the mask of a selection depends on, read from the grid.
struct TreeState
{
  vtkSmartPointer<vtkHyperTree> tree; ///< held: no address reused while compared
  vtkIdType firstCell = 0;
  std::vector<int> maskBits;
};

std::map<vtkIdType, TreeState> treeStates(vtkHyperTreeGrid* grid)
{
  std::map<vtkIdType, TreeState> states;
  vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
  grid->InitializeTreeIterator(it);
  vtkIdType index = 0;
  while (vtkHyperTree* tree = it.GetNextTree(index))
  {
    TreeState& state = states[index];
    state.tree = tree;
    state.firstCell = tree->GetGlobalIndexFromLocal(0);
    for (vtkIdType n = 0; grid->HasMask() && n < tree->GetNumberOfVertices(); ++n)
    {
      state.maskBits.push_back(grid->GetMask()->GetValue(tree->GetGlobalIndexFromLocal(n)));
    }
  }
  return states;
}

/// The masked selection's outputs must be the same, bit for bit.
void expectSameSelection(vtkCanopyExtractSelection* kept, vtkCanopyExtractSelection* fresh,
                         const std::string& where)
{
  auto* a = vtkHyperTreeGrid::SafeDownCast(kept->GetOutputDataObject(0));
  auto* b = vtkHyperTreeGrid::SafeDownCast(fresh->GetOutputDataObject(0));
  ASSERT_NE(a, nullptr) << where;
  ASSERT_NE(b, nullptr) << where;
  ASSERT_TRUE(a->HasMask() && b->HasMask()) << where;
  ASSERT_EQ(a->GetNumberOfCells(), b->GetNumberOfCells()) << where;
  vtkBitArray* pureA = a->GetPureMask();
  vtkBitArray* pureB = b->GetPureMask();
  ASSERT_NE(pureA, nullptr);
  ASSERT_NE(pureB, nullptr);
  vtkIdType visible = 0;
  for (vtkIdType c = 0; c < b->GetNumberOfCells(); ++c)
  {
    ASSERT_EQ(a->GetMask()->GetValue(c), b->GetMask()->GetValue(c)) << where << ", cell " << c;
    ASSERT_EQ(pureA->GetValue(c), pureB->GetValue(c)) << where << ", pure mask of cell " << c;
    visible += b->GetMask()->GetValue(c) == 0;
  }
  EXPECT_GT(visible, 0) << where << ": the selection shows something";
  double boundsA[6];
  double boundsB[6];
  kept->GetLastSelectedBounds(boundsA);
  fresh->GetLastSelectedBounds(boundsB);
  for (int i = 0; i < 6; ++i)
  {
    EXPECT_EQ(boundsA[i], boundsB[i]) << where << ", selected bounds " << i;
  }
}

class KeptSelectionMask : public ::testing::TestWithParam<std::tuple<int, Mode>>
{
};

TEST_P(KeptSelectionMask, EveryStepEqualsANewFilterAndRedoesExactlyTheTreesThatChanged)
{
  const auto [dimension, mode] = GetParam();
  ChangingForest forest(dimension, dimension == 3 ? 27 : 25, false, 77 + dimension);
  std::mt19937_64 random(5);
  GridBuilder builder;
  vtkNew<vtkCanopyExtractSelection> kept;
  std::map<vtkIdType, TreeState> before;
  int variant = 0;
  int changedSteps = 0;
  int partlyKeptSteps = 0;
  for (int step = 0; step < 24; ++step)
  {
    const std::string where =
        modeName(mode) + ", " + std::to_string(dimension) + "D, step " + std::to_string(step);
    // Some steps change nothing, some re-refine or re-mask a few trees, some
    // change the selection itself.
    const int changes = step == 0 ? 0 : static_cast<int>(random() % 3);
    for (int c = 0; c < changes; ++c)
    {
      const std::size_t t = random() % forest.size();
      if (random() % 2 == 0)
      {
        forest.toggleMask(t);
      }
      else
      {
        forest.refine(t);
      }
    }
    const bool newSelection = step > 0 && random() % 5 == 0;
    variant += newSelection ? 1 : 0;

    const ForestDescription description = forest.describe(0.0);
    vtkSmartPointer<vtkHyperTreeGrid> grid = builder.build(description);
    double bounds[6];
    grid->GetBounds(bounds);
    kept->SetInputData(grid);
    select(kept, mode, bounds, variant);
    kept->Modified();
    kept->Update();
    vtkNew<vtkCanopyExtractSelection> fresh;
    fresh->SetInputData(grid);
    select(fresh, mode, bounds, variant);
    fresh->Update();
    expectSameSelection(kept, fresh, where);
    if (HasFatalFailure())
    {
      return;
    }

    // The trees the filter had to redo, from the grids.
    const std::map<vtkIdType, TreeState> now = treeStates(grid);
    vtkIdType redoneTrees = 0;
    vtkIdType redoneNodes = 0;
    for (const auto& [index, state] : now)
    {
      const auto last = before.find(index);
      // Values are fresh memory at every build: a value range reads new arrays.
      const bool redo = step == 0 || newSelection || mode == Mode::ValueRange ||
                        last == before.end() || last->second.tree != state.tree ||
                        last->second.maskBits != state.maskBits ||
                        (readsByCellNumber(mode) && last->second.firstCell != state.firstCell);
      redoneTrees += redo;
      redoneNodes += redo ? state.tree->GetNumberOfVertices() : 0;
    }
    EXPECT_EQ(kept->GetLastRecomputedNodes(), redoneNodes) << where;
    EXPECT_EQ(kept->GetLastKeptTrees(), static_cast<vtkIdType>(now.size()) - redoneTrees) << where;
    changedSteps += redoneTrees > 0 && redoneTrees < static_cast<vtkIdType>(now.size());
    partlyKeptSteps += kept->GetLastKeptTrees() > 0 && redoneTrees > 0;

    // Run again on the same grid: nothing changed, nothing is redone (a value
    // range's arrays are the same ones now), and the output stays the same.
    kept->Modified();
    kept->Update();
    EXPECT_EQ(kept->GetLastRecomputedNodes(), 0) << where << ", re-run";
    EXPECT_EQ(kept->GetLastKeptTrees(), static_cast<vtkIdType>(now.size())) << where << ", re-run";
    if (mode == Mode::Box || mode == Mode::CutAway || mode == Mode::Frustum)
    {
      EXPECT_EQ(kept->GetLastVisited(), 0) << where << ", re-run walks no tree";
    }
    expectSameSelection(kept, fresh, where + ", re-run");
    before = now;
  }
  // The sequence did exercise kept and redone trees side by side (a value
  // range reads new arrays at every build: every tree is redone each step).
  if (mode != Mode::ValueRange)
  {
    EXPECT_GE(partlyKeptSteps, 5) << modeName(mode);
    EXPECT_GE(changedSteps, 5) << modeName(mode);
  }
}

INSTANTIATE_TEST_SUITE_P(
    DimensionAndMode, KeptSelectionMask,
    ::testing::Combine(::testing::Values(2, 3),
                       ::testing::Values(Mode::CutAway, Mode::Box, Mode::Frustum, Mode::Locations,
                                         Mode::Ids, Mode::ValueRange)),
    [](const ::testing::TestParamInfo<std::tuple<int, Mode>>& info)
    { return modeName(std::get<1>(info.param)) + std::to_string(std::get<0>(info.param)) + "D"; });

} // namespace
} // namespace canopy::testing
