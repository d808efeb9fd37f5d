#include <canopy/GridBuilder.h>

#include "ByteHash.h"
#include "GridAssembly.h"
#include "TopologyStamp.h"
#include "ValidatedTrees.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace canopy
{
namespace
{

/// Fingerprints of what a tree's parts of the grid depend on. A missing array
/// hashes to another constant than any present one.
struct TreeKey
{
  std::int64_t root = 0;
  std::size_t nodes = 0;
  std::uint64_t refinement = 0; ///< the vtkHyperTree
  std::uint64_t absent = 0;     ///< with refinement: the tree's layout, ghost marks
  std::uint64_t slots = 0;      ///< the cell -> slot table
  std::uint64_t mask = 0;       ///< the mask

  bool sameTree(const TreeKey& other) const
  {
    return root == other.root && nodes == other.nodes && refinement == other.refinement;
  }
  bool sameShape(const TreeKey& other) const { return sameTree(other) && absent == other.absent; }
  bool sameMarks(const TreeKey& other) const
  {
    return absent == other.absent && mask == other.mask;
  }
};

/// The simulation's revision holds for `forest` against the last build's keys:
/// the same, nonzero, and the same trees (roots, node counts) as then.
bool revisionHolds(const ForestDescription& forest, std::uint64_t lastRevision,
                   const std::vector<TreeKey>& last)
{
  if (forest.revision == 0 || forest.revision != lastRevision || forest.trees.size() != last.size())
  {
    return false;
  }
  for (std::size_t t = 0; t < last.size(); ++t)
  {
    if (forest.trees[t].rootIndex != last[t].root || forest.trees[t].numberOfNodes != last[t].nodes)
    {
      return false;
    }
  }
  return true;
}

/// Whether two descriptions of a field borrow the same memory the same way.
bool sameBorrow(const FieldDescription& a, const FieldDescription& b)
{
  const BlockStrides& x = a.blockStrides;
  const BlockStrides& y = b.blockStrides;
  return a.name == b.name && a.type == b.type && a.components == b.components &&
         a.layout == b.layout && a.centering == b.centering && a.data == b.data &&
         a.componentData == b.componentData && a.tupleStrideBytes == b.tupleStrideBytes &&
         a.tupleAddresses == b.tupleAddresses && a.numberOfTuples == b.numberOfTuples &&
         a.numberOfBlocks == b.numberOfBlocks && x.cellBytes == y.cellBytes &&
         x.componentBytes == y.componentBytes && x.ghostCells == y.ghostCells &&
         a.blockAddresses == b.blockAddresses && a.blockStrideBytes == b.blockStrideBytes &&
         a.componentBlockAddresses == b.componentBlockAddresses;
}

TreeKey keyOf(const TreeDescription& tree)
{
  const std::size_t n = tree.numberOfNodes;
  TreeKey key;
  key.root = tree.rootIndex;
  key.nodes = n;
  key.refinement = hashBytes(tree.refinement, n, 1);
  key.absent = tree.absent ? hashBytes(tree.absent, n, 2) : 0x2545F4914F6CDD1Dull;
  key.slots = tree.storageSlots ? hashBytes(tree.storageSlots, n * sizeof(std::int64_t), 3)
                                : 0x94D049BB133111EBull;
  if (tree.blockIndex)
  {
    // The block order is a block forest's slots: fields read through it.
    key.slots ^= hashBytes(tree.blockIndex, n * sizeof(std::int64_t), 5);
  }
  key.mask = tree.masked ? hashBytes(tree.masked, n, 4) : 0x51ED270B27E4A4F9ull;
  return key;
}

} // namespace

struct GridBuilder::State
{
  std::uint64_t id = newStampBuilder();
  std::uint64_t builds = 0;
  std::uint64_t simulationRevision = 0; ///< ForestDescription::revision at the last build
  std::uint64_t arraysRevision = 0;     ///< the build that last changed mask or ghosts
  std::vector<std::pair<std::uint64_t, std::uint64_t>> treeRevisions; ///< topology, marks
  vtkSmartPointer<vtkHyperTreeGrid> grid;
  int dimension = 0;
  int branchFactor = 0;
  int blockCellsPerSide = 0;
  std::size_t points[3] = {0, 0, 0};
  bool missingTreesAreElsewhere = false;
  std::vector<TreeKey> trees;
  ForestLayout layout; ///< of the last build, for the trees that did not change
  assembly::FieldTables tables;
  /// Fields of the last build with a nonzero valuesRevision, as described then,
  /// and their arrays.
  struct VouchedField
  {
    FieldDescription description;
    vtkSmartPointer<vtkDataArray> array;
  };
  std::vector<VouchedField> vouchedFields;
  Reuse last;
};

GridBuilder::GridBuilder() : Impl(std::make_unique<State>()) {}

GridBuilder::~GridBuilder() = default;

const GridBuilder::Reuse& GridBuilder::lastBuild() const
{
  return Impl->last;
}

void GridBuilder::reset()
{
  Impl = std::make_unique<State>();
}

std::uint64_t GridBuilder::identity() const
{
  return Impl->id;
}

vtkSmartPointer<vtkHyperTreeGrid> GridBuilder::build(const ForestDescription& forest,
                                                     const FieldRequest& request)
{
  State& s = *Impl;
  const std::uint64_t build = s.builds + 1;
  // The simulation's word that nothing changed spares reading every tree's bytes.
  const bool vouched = s.grid && revisionHolds(forest, s.simulationRevision, s.trees);
  std::vector<TreeKey> keys;
  if (vouched)
  {
    keys = s.trees;
  }
  else
  {
    keys.reserve(forest.trees.size());
    for (const TreeDescription& tree : forest.trees)
    {
      keys.push_back(keyOf(tree));
    }
  }
  // Validate first (a malformed description changes nothing kept from before),
  // skipping the per-node checks of trees whose bytes were validated last time.
  ValidatedTrees known;
  known.previous = &s.layout;
  known.unchanged.assign(keys.size(), false);
  const bool sameTrees = s.grid && keys.size() == s.trees.size();
  known.sameSlots = sameTrees;
  for (std::size_t t = 0; sameTrees && t < keys.size(); ++t)
  {
    known.unchanged[t] = keys[t].sameShape(s.trees[t]);
    known.sameSlots = known.sameSlots && keys[t].slots == s.trees[t].slots;
  }
  const ForestLayout layout = layoutForest(forest, &known);
  const auto fields = assembly::selectFields(forest, request);
  const RootGrid& g = forest.rootGrid;
  bool sameShape =
      s.grid && s.dimension == forest.dimension && s.branchFactor == forest.branchFactor &&
      s.blockCellsPerSide == forest.blockCellsPerSide && s.points[0] == g.pointsX &&
      s.points[1] == g.pointsY && s.points[2] == g.pointsZ && s.trees.size() == keys.size();
  for (std::size_t t = 0; sameShape && t < keys.size(); ++t)
  {
    sameShape = s.trees[t].root == keys[t].root;
  }

  Reuse reuse;
  std::vector<bool> rebuild(keys.size(), true);
  if (!sameShape)
  {
    // Another root grid or another set of trees: VTK cannot drop a tree from a grid.
    s.grid = assembly::newGrid(forest);
    s.dimension = forest.dimension;
    s.branchFactor = forest.branchFactor;
    s.blockCellsPerSide = forest.blockCellsPerSide;
    s.points[0] = g.pointsX;
    s.points[1] = g.pointsY;
    s.points[2] = g.pointsZ;
    reuse.newGrid = true;
  }
  // What changed decides what is redone: trees, the topology arrays (mask, ghost
  // marks, trees-elsewhere flag), the tables fields read through.
  bool arraysChanged = !sameShape || s.missingTreesAreElsewhere != forest.missingTreesAreElsewhere;
  bool tablesChanged = !sameShape;
  if (sameShape)
  {
    assembly::setCoordinates(s.grid, g);
    for (std::size_t t = 0; t < keys.size(); ++t)
    {
      const TreeKey& before = s.trees[t];
      // A block forest's tree also grows a block's cells under each present leaf:
      // which leaves are absent shapes it too.
      rebuild[t] =
          forest.blockCellsPerSide != 0 ? !keys[t].sameShape(before) : !keys[t].sameTree(before);
      const bool shape = !keys[t].sameShape(before);
      tablesChanged = tablesChanged || shape || keys[t].slots != before.slots;
      arraysChanged = arraysChanged || shape || keys[t].mask != before.mask;
    }
  }
  for (bool r : rebuild)
  {
    (r ? reuse.treesRebuilt : reuse.treesKept) += 1;
  }
  reuse.revisionTrusted = vouched;
  // What the filters read of this build (TopologyStamp.h): which build last changed
  // each tree's refinement and marks, and the grid's topology arrays.
  std::vector<std::pair<std::uint64_t, std::uint64_t>> revisions(keys.size(), {build, build});
  for (std::size_t t = 0; sameShape && t < keys.size(); ++t)
  {
    revisions[t] = {rebuild[t] ? build : s.treeRevisions[t].first,
                    keys[t].sameMarks(s.trees[t]) ? s.treeRevisions[t].second : build};
  }
  // Keep nothing half-updated if VTK throws: forget the state until done.
  s.trees.clear();
  if (tablesChanged)
  {
    s.tables = assembly::FieldTables();
    // A block forest's trees are built from its index: before the trees.
    s.tables.blocks = assembly::indexBlocks(forest, layout);
  }
  if (reuse.treesRebuilt > 0 || reuse.newGrid)
  {
    // A tree's size moves the cells of the trees after it: every tree's first cell follows.
    assembly::buildTrees(s.grid, forest, layout, rebuild, s.tables.blocks.get());
  }
  if (arraysChanged)
  {
    assembly::setTopologyArrays(s.grid, forest, layout, s.tables.blocks.get());
  }
  // A field the simulation vouches for keeps its array while the topology and
  // its description hold (FieldDescription::valuesRevision); `previous` holds
  // the arrays until they are in the grid again.
  const std::vector<State::VouchedField> previous = std::move(s.vouchedFields);
  s.vouchedFields.clear();
  std::vector<vtkDataArray*> keptArrays(fields.size(), nullptr);
  // The mask too: a leaves-only field's coarse averages are over visible leaves.
  const bool sameTopology = !tablesChanged && !arraysChanged && reuse.treesRebuilt == 0;
  for (std::size_t f = 0; sameTopology && f < fields.size(); ++f)
  {
    for (const State::VouchedField& before : previous)
    {
      if (fields[f]->valuesRevision != 0 &&
          fields[f]->valuesRevision == before.description.valuesRevision &&
          sameBorrow(*fields[f], before.description))
      {
        keptArrays[f] = before.array;
        reuse.fieldsKept += 1;
        break;
      }
    }
  }
  assembly::setFields(s.grid, forest, layout, fields, s.tables, keptArrays);
  for (const FieldDescription* field : fields)
  {
    if (field->valuesRevision != 0)
    {
      s.vouchedFields.push_back({*field, s.grid->GetCellData()->GetArray(field->name.c_str())});
    }
  }
  s.arraysRevision = arraysChanged ? build : s.arraysRevision;
  StampRevisions stamp;
  stamp.builder = s.id;
  stamp.arrays = s.arraysRevision;
  for (std::size_t t = 0; t < keys.size(); ++t)
  {
    stamp.trees[keys[t].root] = revisions[t];
  }
  writeTopologyStamp(s.grid, stamp);
  s.grid->Modified();
  s.trees = std::move(keys);
  s.treeRevisions = std::move(revisions);
  s.layout = layout;
  s.missingTreesAreElsewhere = forest.missingTreesAreElsewhere;
  s.simulationRevision = forest.revision;
  s.builds = build;
  s.last = reuse;
  return s.grid;
}

} // namespace canopy
