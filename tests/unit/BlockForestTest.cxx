// Block forests (octrees of blocks with ghost zones) checked cell by cell against
// the simulation's block arrays. The oracle walks the test's own description
// (BlockForest.h) and VTK's cursors, never Canopy's index: every cell VTK reaches
// is found by its tree, level and integer position; a cell inside a block must
// read the stored value of its interior cell (ghost offsets, both variable
// orders, interleaved and separate components, per-block and one-array
// allocation, 2D in two planes and 3D, float and double, the simulation's own
// block order, trees split between ranks), a coarse cell the volume average of
// the leaves below it (the leaves-only rule above blocks: unmasked children,
// absent ones left out). Ghost cells hold NaN, so a ghost read anywhere shows.
#include "BlockForest.h"
#include "HtgWalk.h"

#include <canopy/ForestValidation.h>
#include <canopy/GridBuilder.h>
#include <canopy/HtgBuilder.h>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkUnsignedCharArray.h>

#include <cmath>
#include <limits>
#include <map>
#include <ostream>
#include <set>
#include <string>
#include <tuple>

namespace canopy::testing
{
namespace
{

struct BlockCase
{
  std::string name;
  int dimension;
  int flatAxis;
  int cellsPerSide;
  BlockStorage storage;
  bool single;
  bool shuffled;
  int ranks;
  double maskProbability;
  int branchFactor = 2;
};

/// GoogleTest prints a parameter by name (a byte dump would read the padding).
void PrintTo(const BlockCase& c, std::ostream* out)
{
  *out << c.name;
}

BlockForestOptions optionsOf(const BlockCase& c, int rank)
{
  BlockForestOptions o;
  o.shape.dimension = c.dimension;
  o.shape.branchFactor = c.branchFactor;
  o.shape.flatAxis = c.flatAxis;
  o.shape.rootCells = c.dimension == 3 ? std::array<std::size_t, 3>{{2, 1, 2}}
                                       : std::array<std::size_t, 3>{{3, 2, 2}};
  o.shape.maxLevels = c.branchFactor == 3 ? 2 : 3;
  o.shape.refineProbability = 0.5;
  o.shape.maskProbability = c.maskProbability;
  o.shape.seed = 5;
  o.cellsPerSide = c.cellsPerSide;
  o.ghostCells = 2;
  o.components = c.storage == BlockStorage::SeparateComponents ? 3 : 2;
  o.storage = c.storage;
  o.singlePrecision = c.single;
  o.shuffledBlocks = c.shuffled;
  o.rank = rank;
  o.ranks = c.ranks;
  return o;
}

using Position = std::array<long long, 3>;
using Key = std::tuple<vtkIdType, unsigned int, long long, long long, long long>;

/// The test's own view of a block forest: every described node by its place.
class Oracle
{
public:
  explicit Oracle(const BlockForest& forest) : Forest(forest)
  {
    const ForestDescription& d = forest.description();
    Children = 1;
    for (int a = 0; a < d.dimension; ++a)
    {
      Children *= static_cast<std::size_t>(d.branchFactor);
    }
    for (std::size_t b = 0; b < forest.blocks().size(); ++b)
    {
      BlockOf[{forest.blocks()[b].tree, forest.blocks()[b].node}] = b;
    }
    for (std::size_t t = 0; t < d.trees.size(); ++t)
    {
      const TreeDescription& tree = d.trees[t];
      std::vector<Position> position(tree.numberOfNodes, Position{{0, 0, 0}});
      std::vector<unsigned int> level(tree.numberOfNodes, 0);
      FirstChild.emplace_back(tree.numberOfNodes, 0);
      for (std::size_t n = 0, next = 1; n < tree.numberOfNodes; ++n)
      {
        Nodes[Key{tree.rootIndex, level[n], position[n][0], position[n][1], position[n][2]}] = {t,
                                                                                                n};
        if (!tree.refinement[n])
        {
          continue;
        }
        FirstChild[t][n] = next;
        for (std::size_t c = 0; c < Children; ++c, ++next)
        {
          std::size_t digit = c;
          for (int a = 0; a < d.dimension; ++a)
          {
            const auto axis = static_cast<std::size_t>(a);
            position[next][axis] =
                position[n][axis] * d.branchFactor + static_cast<long long>(digit % d.branchFactor);
            digit /= static_cast<std::size_t>(d.branchFactor);
          }
          level[next] = level[n] + 1;
        }
      }
      Positions.push_back(std::move(position));
      Levels.push_back(std::move(level));
    }
  }

  /// The expected component c of the cell at (root, level, position), and whether
  /// that cell is an absent one.
  double expected(vtkIdType root, unsigned int level, const Position& p, int c, bool* absent)
  {
    *absent = false;
    const ForestDescription& d = Forest.description();
    const auto it = Nodes.find(Key{root, level, p[0], p[1], p[2]});
    if (it != Nodes.end())
    {
      const auto [t, n] = it->second;
      *absent = d.trees[t].absent && d.trees[t].absent[n];
      return nodeValue(t, n, c);
    }
    // Inside a block: its root is the one described ancestor that is a leaf.
    const long long bf = d.branchFactor;
    long long scale = 1;
    for (unsigned int up = 1; up <= level; ++up)
    {
      scale *= bf;
      const Position q{{p[0] / scale, p[1] / scale, p[2] / scale}};
      const auto found = Nodes.find(Key{root, level - up, q[0], q[1], q[2]});
      if (found == Nodes.end())
      {
        continue;
      }
      const auto [t, n] = found->second;
      const std::size_t block = BlockOf.at({t, n});
      Position inBlock{{0, 0, 0}};
      for (int a = 0; a < d.dimension; ++a)
      {
        const auto axis = static_cast<std::size_t>(a);
        inBlock[axis] = p[axis] - q[axis] * scale;
      }
      return blockMean(block, inBlock, scale, c);
    }
    ADD_FAILURE() << "cell at level " << level << " of tree " << root << " is in no block";
    return 0;
  }

  /// Mean of the leaves under cell `inBlock` of a block level that is `scale` cells
  /// across the block (scale == cellsPerSide: the cell itself).
  double blockMean(std::size_t block, const Position& inBlock, long long scale, int c)
  {
    const int dimension = Forest.description().dimension;
    const long long n = Forest.options().cellsPerSide;
    const long long width = n / scale;
    double sum = 0;
    long long count = 0;
    std::array<int, 3> cell{{0, 0, 0}};
    const long long wj = dimension >= 2 ? width : 1;
    const long long wk = dimension >= 3 ? width : 1;
    for (long long k = 0; k < wk; ++k)
      for (long long j = 0; j < wj; ++j)
        for (long long i = 0; i < width; ++i)
        {
          cell[0] = static_cast<int>(inBlock[0] * width + i);
          cell[1] = static_cast<int>(inBlock[1] * width + j);
          cell[2] = static_cast<int>(inBlock[2] * width + k);
          sum += Forest.stored(block, cell, c);
          ++count;
        }
    return sum / static_cast<double>(count);
  }

  double nodeValue(std::size_t t, std::size_t n, int c)
  {
    const TreeDescription& tree = Forest.description().trees[t];
    if (tree.absent && tree.absent[n])
    {
      return std::numeric_limits<double>::quiet_NaN();
    }
    if (!tree.refinement[n])
    {
      return blockMean(BlockOf.at({t, n}), Position{{0, 0, 0}}, 1, c);
    }
    double sum = 0;
    int used = 0;
    for (int pass = 0; pass < 2 && used == 0; ++pass)
    {
      for (std::size_t k = 0; k < Children; ++k)
      {
        const std::size_t child = FirstChild[t][n] + k;
        if ((tree.absent && tree.absent[child]) || (pass == 0 && tree.masked && tree.masked[child]))
        {
          continue;
        }
        sum += nodeValue(t, child, c);
        ++used;
      }
    }
    return used ? sum / used : std::numeric_limits<double>::quiet_NaN();
  }

private:
  const BlockForest& Forest;
  std::size_t Children = 1;
  std::map<Key, std::pair<std::size_t, std::size_t>> Nodes;
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> BlockOf;
  std::vector<std::vector<std::size_t>> FirstChild;
  std::vector<std::vector<Position>> Positions;
  std::vector<std::vector<unsigned int>> Levels;
};

/// The forest's axes that are not flat, in x, y, z order: the blocks' i, j, k.
std::vector<int> activeAxes(const ForestDescription& d)
{
  const std::size_t points[3] = {d.rootGrid.pointsX, d.rootGrid.pointsY, d.rootGrid.pointsZ};
  std::vector<int> axes;
  for (int a = 0; a < 3; ++a)
  {
    if (points[a] > 1)
    {
      axes.push_back(a);
    }
  }
  return axes;
}

/// Checks every cell VTK's cursors reach against the oracle; returns the number of
/// block leaves reached.
std::size_t checkEveryCell(vtkHyperTreeGrid* htg, BlockForest& forest)
{
  Oracle oracle(forest);
  const ForestDescription& d = forest.description();
  vtkDataArray* field = htg->GetCellData()->GetArray("f");
  EXPECT_NE(field, nullptr);
  if (!field)
  {
    return 0;
  }
  auto* ghosts = vtkUnsignedCharArray::SafeDownCast(
      htg->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()));
  const std::vector<int> axes = activeAxes(d);
  const double tolerance = forest.options().singlePrecision ? 1e-6 : 1e-12;
  const auto blockLevels = static_cast<unsigned int>(
      std::lround(std::log(forest.options().cellsPerSide) / std::log(d.branchFactor)));
  std::size_t leaves = 0;
  std::size_t mismatches = 0;
  std::set<std::pair<vtkIdType, std::vector<long long>>> seen;
  forEachReachableNode(
      htg,
      [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor, const std::vector<vtkIdType>&)
      {
        double rootOrigin[3];
        double rootSize[3];
        const vtkIdType root = cursor->GetTree()->GetTreeIndex();
        htg->GetLevelZeroOriginAndSizeFromIndex(root, rootOrigin, rootSize);
        const double* origin = cursor->GetOrigin();
        const double* size = cursor->GetSize();
        Position p{{0, 0, 0}};
        for (std::size_t a = 0; a < axes.size(); ++a)
        {
          const auto axis = static_cast<std::size_t>(axes[a]);
          p[a] = std::llround((origin[axis] - rootOrigin[axis]) / size[axis]);
        }
        const unsigned int level = cursor->GetLevel();
        const vtkIdType cell = cursor->GetGlobalNodeIndex();
        for (int c = 0; c < field->GetNumberOfComponents(); ++c)
        {
          bool absent = false;
          const double want = oracle.expected(root, level, p, c, &absent);
          const double got = field->GetComponent(cell, c);
          const bool same = std::isnan(want)
                                ? std::isnan(got)
                                : std::abs(got - want) <= tolerance * std::max(1.0, std::abs(want));
          if (!same && ++mismatches <= 5)
          {
            ADD_FAILURE() << "tree " << root << " level " << level << " position (" << p[0] << ", "
                          << p[1] << ", " << p[2] << ") component " << c << ": read " << got
                          << ", the arrays say " << want;
          }
          if (c == 0 && ghosts)
          {
            EXPECT_EQ(ghosts->GetValue(cell) == vtkDataSetAttributes::DUPLICATECELL, absent);
          }
          if (c == 0 && absent)
          {
            EXPECT_TRUE(cursor->IsMasked()) << "absent cells are masked";
          }
        }
        if (cursor->IsLeaf() && !cursor->IsMasked() && level >= blockLevels)
        {
          EXPECT_TRUE(seen.insert({root, {level, p[0], p[1], p[2]}}).second);
          ++leaves;
        }
      });
  EXPECT_EQ(mismatches, 0u);
  return leaves;
}

/// Cells of the blocks with neither a masked ancestor nor a mask of their own
/// (VTK's cursors stop at a masked node).
std::size_t unmaskedBlockCells(const BlockForest& forest)
{
  const ForestDescription& d = forest.description();
  std::size_t cellsPerBlock = 1;
  std::size_t children = 1;
  for (int a = 0; a < d.dimension; ++a)
  {
    cellsPerBlock *= static_cast<std::size_t>(forest.options().cellsPerSide);
    children *= static_cast<std::size_t>(d.branchFactor);
  }
  std::vector<std::vector<bool>> hidden;
  for (const TreeDescription& tree : d.trees)
  {
    std::vector<bool> h(tree.numberOfNodes, false);
    for (std::size_t n = 0, next = 1; n < tree.numberOfNodes; ++n)
    {
      h[n] = h[n] || (tree.masked && tree.masked[n]);
      for (std::size_t c = 0; tree.refinement[n] && c < children; ++c, ++next)
      {
        h[next] = h[n];
      }
    }
    hidden.push_back(std::move(h));
  }
  std::size_t count = 0;
  for (const auto& block : forest.blocks())
  {
    count += hidden[block.tree][block.node] ? 0 : cellsPerBlock;
  }
  return count;
}

class BlockForests : public ::testing::TestWithParam<BlockCase>
{
};

TEST_P(BlockForests, EveryCellReadsItsBlockArraysOrTheMeanOfItsLeaves)
{
  const BlockCase& c = GetParam();
  for (int rank = 0; rank < c.ranks; ++rank)
  {
    BlockForest forest(optionsOf(c, rank));
    ASSERT_GT(forest.blocks().size(), 0u);
    const std::uint64_t before = forest.checksum();
    const ForestCounts counts = validateForest(forest.description());
    EXPECT_EQ(counts.numberOfBlocks, forest.blocks().size());
    vtkSmartPointer<vtkHyperTreeGrid> htg = buildHyperTreeGrid(forest.description());
    EXPECT_EQ(static_cast<std::size_t>(htg->GetNumberOfCells()), counts.totalCells);
    // Blocks masked whole hide their cells; absent parts have no block here.
    EXPECT_EQ(checkEveryCell(htg, forest), unmaskedBlockCells(forest)) << "rank " << rank;

    // The range is the leaves' (ghosts hold NaN, skipped only if never read).
    vtkDataArray* field = htg->GetCellData()->GetArray("f");
    for (int comp = 0; comp < field->GetNumberOfComponents(); ++comp)
    {
      double low = std::numeric_limits<double>::max();
      double high = std::numeric_limits<double>::lowest();
      for (std::size_t b = 0; b < forest.blocks().size(); ++b)
      {
        const int n = forest.options().cellsPerSide;
        const int nj = c.dimension >= 2 ? n : 1;
        const int nk = c.dimension >= 3 ? n : 1;
        for (int k = 0; k < nk; ++k)
          for (int j = 0; j < nj; ++j)
            for (int i = 0; i < n; ++i)
            {
              const double v = forest.stored(b, {{i, j, k}}, comp);
              low = std::min(low, v);
              high = std::max(high, v);
            }
      }
      double range[2];
      field->GetRange(range, comp);
      EXPECT_EQ(range[0], low) << "component " << comp;
      EXPECT_EQ(range[1], high) << "component " << comp;
    }
    EXPECT_EQ(forest.checksum(), before) << "the simulation's block arrays were written";
  }
}

const BlockCase blockCases[] = {
    {"Outermost3D", 3, 2, 4, BlockStorage::PerBlockVariableOutermost, false, false, 1, 0.0},
    {"Innermost3DFloat", 3, 2, 4, BlockStorage::PerBlockVariableInnermost, true, false, 1, 0.0},
    {"OneArray3DShuffled", 3, 2, 4, BlockStorage::OneArray, false, true, 1, 0.0},
    {"Separate3D8", 3, 2, 8, BlockStorage::SeparateComponents, false, false, 1, 0.0},
    {"Outermost2D16", 2, 2, 16, BlockStorage::PerBlockVariableOutermost, false, false, 1, 0.0},
    {"Innermost2DxzPlane", 2, 1, 8, BlockStorage::PerBlockVariableInnermost, false, true, 1, 0.0},
    {"Separate2DFloatMasked", 2, 2, 4, BlockStorage::SeparateComponents, true, false, 1, 0.3},
    {"Outermost3DMasked", 3, 2, 4, BlockStorage::PerBlockVariableOutermost, false, false, 1, 0.3},
    {"OneArray3DThreeRanks", 3, 2, 4, BlockStorage::OneArray, false, false, 3, 0.0},
    {"Outermost2DTwoRanksShuffled", 2, 2, 8, BlockStorage::PerBlockVariableOutermost, false, true,
     2, 0.0},
    {"Ternary2D9", 2, 2, 9, BlockStorage::PerBlockVariableOutermost, false, false, 1, 0.0, 3},
    {"Ternary3D3", 3, 2, 3, BlockStorage::PerBlockVariableInnermost, false, false, 2, 0.0, 3},
};

INSTANTIATE_TEST_SUITE_P(Layouts, BlockForests, ::testing::ValuesIn(blockCases),
                         [](const ::testing::TestParamInfo<BlockCase>& info)
                         { return info.param.name; });

/// The message of the InvalidForest a description raises ("" when it is valid).
std::string problemsOf(const ForestDescription& description)
{
  try
  {
    validateForest(description);
  }
  catch (const InvalidForest& e)
  {
    return e.what();
  }
  return "";
}

TEST(BlockForestValidation, EachMistakeNamedPrecisely)
{
  BlockForest forest(optionsOf(blockCases[0], 0));
  ASSERT_EQ(problemsOf(forest.description()), "");

  ForestDescription wrongSize = forest.description();
  wrongSize.blockCellsPerSide = 12;
  EXPECT_NE(problemsOf(wrongSize).find("blockCellsPerSide must be a power of the branch factor 2 "
                                       "(2, 4, 8, 16, 32, ...), got 12"),
            std::string::npos)
      << problemsOf(wrongSize);

  ForestDescription ordinary = forest.description();
  ordinary.blockCellsPerSide = 0;
  EXPECT_NE(problemsOf(ordinary).find("needs a block forest"), std::string::npos);

  ForestDescription ordinaryWithOrder = forest.description();
  ordinaryWithOrder.blockCellsPerSide = 0;
  std::vector<std::int64_t> order(ordinaryWithOrder.trees[0].numberOfNodes, 0);
  ordinaryWithOrder.trees[0].blockIndex = order.data();
  EXPECT_NE(problemsOf(ordinaryWithOrder).find("a blockIndex needs a block forest"),
            std::string::npos);

  ForestDescription nodeField = forest.description();
  const std::vector<double> values(1000, 0.0);
  nodeField.fields.push_back(FieldDescription::aos("g", values.data(), values.size()));
  EXPECT_NE(problemsOf(nodeField).find("field 1 'g': a block forest's fields are block fields"),
            std::string::npos);

  ForestDescription nullBlock = forest.description();
  std::vector<const void*> table(forest.blocks().size());
  for (std::size_t b = 0; b < table.size(); ++b)
  {
    table[b] = forest.address(b, {{0, 0, 0}}, 0);
  }
  table[1] = nullptr;
  nullBlock.fields[0].blockAddresses = table.data();
  EXPECT_NE(problemsOf(nullBlock).find("blockAddresses of block 1 is null"), std::string::npos)
      << problemsOf(nullBlock);

  ForestDescription fewBlocks = forest.description();
  fewBlocks.fields[0].numberOfBlocks = forest.blocks().size() - 1;
  EXPECT_NE(problemsOf(fewBlocks).find("blocks given but the forest has " +
                                       std::to_string(forest.blocks().size()) + " blocks"),
            std::string::npos);

  ForestDescription tooDeep = forest.description();
  tooDeep.maxLevels = 3; // the trees' own 3 levels, but not their blocks' 2 more
  EXPECT_NE(problemsOf(tooDeep).find("levels of cells inside its blocks"), std::string::npos)
      << problemsOf(tooDeep);

  ForestDescription withSlots = forest.description();
  std::vector<std::vector<std::int64_t>> slots;
  std::int64_t nextSlot = 0;
  for (TreeDescription& tree : withSlots.trees)
  {
    slots.emplace_back(tree.numberOfNodes);
    for (auto& slot : slots.back())
    {
      slot = nextSlot++;
    }
    tree.storageSlots = slots.back().data();
  }
  EXPECT_NE(problemsOf(withSlots).find("storageSlots have no use in a block forest"),
            std::string::npos)
      << problemsOf(withSlots);

  ForestDescription badStride = forest.description();
  badStride.fields[0].blockStrides.cellBytes[1] = 3;
  EXPECT_NE(problemsOf(badStride).find("blockStrides.cellBytes[1] = 3 must be a nonzero multiple"),
            std::string::npos);
}

TEST(BlockForestValidation, BlockIndexMustNumberEveryBlockOnce)
{
  BlockCase shuffled = blockCases[2];
  BlockForest forest(optionsOf(shuffled, 0));
  ForestDescription d = forest.description();
  std::vector<std::vector<std::int64_t>> indices;
  for (const TreeDescription& tree : d.trees)
  {
    indices.emplace_back(tree.blockIndex, tree.blockIndex + tree.numberOfNodes);
  }
  // Two leaves given the same block.
  std::int64_t* first = nullptr;
  for (std::size_t t = 0; t < d.trees.size(); ++t)
  {
    for (std::size_t n = 0; n < indices[t].size(); ++n)
    {
      if (!d.trees[t].refinement[n])
      {
        if (first)
        {
          indices[t][n] = *first;
          t = d.trees.size() - 1;
          break;
        }
        first = &indices[t][n];
      }
    }
  }
  for (std::size_t t = 0; t < d.trees.size(); ++t)
  {
    d.trees[t].blockIndex = indices[t].data();
  }
  EXPECT_NE(problemsOf(d).find("reuses blockIndex"), std::string::npos) << problemsOf(d);
  d.trees[0].blockIndex = nullptr;
  EXPECT_NE(problemsOf(d).find("either every tree has one or none does"), std::string::npos);
}

TEST(BlockForestSteps, ATreeWhoseBlocksMoveToAnotherRankIsRebuilt)
{
  // The same refinement bytes, one more leaf absent: the grid's tree loses a block.
  const double x[3] = {0, 1, 2};
  const double y[2] = {0, 1};
  const double z[1] = {0};
  const std::uint8_t refinement[5] = {1, 0, 0, 0, 0};
  const std::uint8_t before[5] = {0, 0, 0, 1, 1};
  const std::uint8_t after[5] = {0, 0, 1, 1, 1};
  std::vector<double> block(6 * 6, 1.0);
  const double* blocks[2] = {block.data(), block.data()};
  ForestDescription forest;
  forest.dimension = 2;
  forest.maxLevels = 4;
  forest.rootGrid = {x, y, z, 3, 2, 1};
  forest.blockCellsPerSide = 2;
  forest.missingTreesAreElsewhere = true;
  TreeDescription tree;
  tree.refinement = refinement;
  tree.numberOfNodes = 5;
  tree.absent = before;
  forest.trees.push_back(tree);
  forest.fields.push_back(FieldDescription::blocks<double>(
      "f", blocks, 2, BlockStrides::variableOutermost<double>(2, 2, 2)));
  GridBuilder builder;
  EXPECT_EQ(builder.build(forest)->GetNumberOfCells(), 5 + 2 * 4);
  forest.trees[0].absent = after;
  forest.fields[0].numberOfBlocks = 1;
  vtkSmartPointer<vtkHyperTreeGrid> htg = builder.build(forest);
  EXPECT_EQ(htg->GetNumberOfCells(), buildHyperTreeGrid(forest)->GetNumberOfCells());
  EXPECT_EQ(htg->GetNumberOfCells(), 5 + 1 * 4);
}

TEST(BlockForestSteps, ValuesReadInPlaceAndCoarseMeansFollowEachBuild)
{
  BlockForest forest(optionsOf(blockCases[0], 0));
  GridBuilder builder;
  vtkSmartPointer<vtkHyperTreeGrid> htg = builder.build(forest.description());
  EXPECT_EQ(checkEveryCell(htg, forest), unmaskedBlockCells(forest));
  // The simulation advances in place: the grid reads its memory, not a copy.
  const std::array<int, 3> cell{{1, 2, 3}};
  const double before = forest.stored(0, cell, 1);
  double* value = static_cast<double*>(forest.address(0, cell, 1));
  *value = before + 1000.5;
  htg = builder.build(forest.description());
  EXPECT_EQ(builder.lastBuild().treesRebuilt, 0u) << "same trees, nothing rebuilt";
  EXPECT_EQ(checkEveryCell(htg, forest), unmaskedBlockCells(forest));
  // Another forest of blocks (regridded): rebuilt and read right.
  BlockCase other = blockCases[0];
  BlockForestOptions options = optionsOf(other, 0);
  options.shape.seed = 21;
  BlockForest regridded(options);
  htg = builder.build(regridded.description());
  EXPECT_EQ(checkEveryCell(htg, regridded), unmaskedBlockCells(regridded));
}

} // namespace
} // namespace canopy::testing
