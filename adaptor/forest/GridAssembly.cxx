#include "GridAssembly.h"

#include "PureMask.h"

#include "FieldWrapping.h"

#include <vtkBitArray.h>
#include <vtkCellData.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridScales.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cstring>
#include <memory>

namespace canopy::assembly
{
namespace
{

vtkSmartPointer<vtkDoubleArray> borrowCoordinates(const double* coords, std::size_t points)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetArray(const_cast<double*>(coords), static_cast<vtkIdType>(points), 1);
  return array;
}

} // namespace

std::vector<const FieldDescription*> selectFields(const ForestDescription& forest,
                                                  const FieldRequest& request)
{
  std::vector<const FieldDescription*> selected;
  if (request.includesAll())
  {
    for (const auto& field : forest.fields)
    {
      selected.push_back(&field);
    }
    return selected;
  }
  std::vector<std::string> unknown;
  for (const auto& name : request.names())
  {
    const auto it = std::find_if(forest.fields.begin(), forest.fields.end(),
                                 [&](const FieldDescription& f) { return f.name == name; });
    if (it == forest.fields.end())
    {
      unknown.push_back("requested field '" + name + "' is not in the forest description");
    }
  }
  if (!unknown.empty())
  {
    throw InvalidForest(std::move(unknown));
  }
  for (const auto& field : forest.fields)
  {
    if (std::find(request.names().begin(), request.names().end(), field.name) !=
        request.names().end())
    {
      selected.push_back(&field);
    }
  }
  return selected;
}

namespace
{

/// Where a tree's descriptor starts in the packed bits: each tree's starts on a
/// byte, so that a vtkBitArray can read it in place from its first bit.
std::size_t alignedBits(std::size_t bits)
{
  return (bits + 7) / 8 * 8;
}

/// The breadth-first descriptors of the trees to build, each from a byte
/// boundary, without their deepest level (VTK infers it: it is all leaves).
std::vector<unsigned char> packDescriptors(const ForestDescription& forest,
                                           const ForestLayout& layout,
                                           const std::vector<bool>& rebuild,
                                           const BlockCells* blocks)
{
  std::size_t total = 0;
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    total += rebuild[t] ? alignedBits(layout.trees[t].descriptorBits) : 0;
  }
  std::vector<unsigned char> bytes(total / 8, 0);
  std::size_t position = 0;
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    if (!rebuild[t])
    {
      continue;
    }
    const std::size_t count = layout.trees[t].descriptorBits;
    if (blocks)
    {
      blocks->writeDescriptor(layout.trees[t].firstCell, count, bytes.data(), position);
    }
    else
    {
      const std::uint8_t* refinement = forest.trees[t].refinement;
      for (std::size_t n = 0; n < count; ++n)
      {
        // vtkBitArray stores the most significant bit first.
        const std::size_t bit = position + n;
        bytes[bit >> 3] |= static_cast<unsigned char>((refinement[n] != 0) << (7 - (bit & 7)));
      }
    }
    position += alignedBits(count);
  }
  return bytes;
}

} // namespace

std::shared_ptr<const BlockCells> indexBlocks(const ForestDescription& forest,
                                              const ForestLayout& layout)
{
  if (forest.blockCellsPerSide == 0)
  {
    return nullptr;
  }
  return std::make_shared<const BlockCells>(BlockCells::build(forest, layout));
}

void buildTrees(vtkHyperTreeGrid* htg, const ForestDescription& forest, const ForestLayout& layout,
                const std::vector<bool>& rebuild, const BlockCells* blocks)
{
  std::vector<unsigned char> descriptors = packDescriptors(forest, layout, rebuild, blocks);
  // Each tree's bits read in place (not owned: SetArray's save flag).
  vtkNew<vtkBitArray> treeBits;
  std::size_t position = 0;
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeLayout& shape = layout.trees[t];
    if (rebuild[t])
    {
      // A new tree object: a grid shallow-copied from an earlier step keeps its own.
      vtkSmartPointer<vtkHyperTree> hyperTree = vtkSmartPointer<vtkHyperTree>::Take(
          vtkHyperTree::CreateInstance(static_cast<unsigned char>(forest.branchFactor),
                                       static_cast<unsigned char>(forest.dimension)));
      // VTK's reader entry point: the child table allocated once at its size
      // (BuildFromBreadthFirstOrderDescriptor grows it bit by bit, twice the
      // time and up to twice the memory; the same trees, BlockForestBenchmark).
      if (shape.descriptorBits == 0)
      {
        hyperTree->InitializeForReader(1, 1, 1, nullptr, nullptr, nullptr); // a single leaf
      }
      else
      {
        treeBits->SetArray(descriptors.data() + position / 8,
                           static_cast<vtkIdType>(shape.descriptorBits), 1);
        hyperTree->InitializeForReader(shape.levels, static_cast<vtkIdType>(shape.cells),
                                       static_cast<vtkIdType>(shape.cells - shape.descriptorBits),
                                       treeBits, nullptr, nullptr);
      }
      position += alignedBits(shape.descriptorBits);
      const vtkIdType root = forest.trees[t].rootIndex;
      htg->SetTree(root, hyperTree);
      // As vtkHyperTreeGrid::GetTree(create) does: cursors read the tree's scales.
      double origin[3];
      double size[3];
      htg->GetLevelZeroOriginAndSizeFromIndex(root, origin, size);
      hyperTree->SetScales(
          std::make_shared<vtkHyperTreeGridScales>(static_cast<double>(forest.branchFactor), size));
    }
    // Cells breadth-first, tree by tree; fields map cells to slots (CellSlots).
    htg->GetTree(forest.trees[t].rootIndex)
        ->SetGlobalIndexStart(static_cast<vtkIdType>(shape.firstCell));
  }
}

namespace
{

vtkSmartPointer<vtkBitArray> zeroBits(std::size_t count)
{
  auto bits = vtkSmartPointer<vtkBitArray>::New();
  bits->SetNumberOfValues(static_cast<vtkIdType>(count));
  if (count > 0)
  {
    std::memset(bits->GetPointer(0), 0, (count + 7) / 8);
  }
  return bits;
}

/// A block forest's pure mask: described nodes only (no cell inside a block is
/// masked), in reverse forest numbering (children after their parents).
vtkSmartPointer<vtkBitArray> buildBlockPureMask(const BlockCells& blocks, std::size_t cells)
{
  vtkSmartPointer<vtkBitArray> pure = zeroBits(cells);
  std::vector<unsigned char> marked(blocks.numberOfNodes(), 0);
  for (std::size_t node = blocks.numberOfNodes(); node-- > 0;)
  {
    bool here = blocks.isMasked(node) || blocks.isAbsent(node);
    const std::int64_t first = blocks.firstChildOfNode(node);
    for (std::size_t c = 0; !here && first >= 0 && c < blocks.childrenPerNode(); ++c)
    {
      here = marked[static_cast<std::size_t>(first) + c] != 0;
    }
    marked[node] = here;
    if (here)
    {
      pure->SetValue(static_cast<vtkIdType>(blocks.cellOfNode(node)), 1);
    }
  }
  return pure;
}

} // namespace

/// VTK's pure mask (PureMask.h) of the built mask: per tree, breadth-first
/// nodes in reverse (children after their parents), a node marked when masked
/// or, refined, when a child is.
vtkSmartPointer<vtkBitArray> buildPureMask(const ForestDescription& forest,
                                           const ForestLayout& layout, vtkBitArray* mask)
{
  vtkSmartPointer<vtkBitArray> pure = zeroBits(layout.totalNodes);
  std::size_t children = 1;
  for (int d = 0; d < forest.dimension; ++d)
  {
    children *= static_cast<std::size_t>(forest.branchFactor);
  }
  std::vector<std::size_t> firstChild;
  std::vector<unsigned char> marked;
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeDescription& tree = forest.trees[t];
    const TreeLayout& shape = layout.trees[t];
    firstChild.assign(shape.numberOfNodes, 0);
    for (std::size_t n = 0, next = 1; n < shape.numberOfNodes; ++n)
    {
      if (tree.refinement[n] && !isAbsent(tree, n))
      {
        firstChild[n] = next;
        next += children;
      }
    }
    marked.assign(shape.numberOfNodes, 0);
    for (std::size_t n = shape.numberOfNodes; n-- > 0;)
    {
      const auto cell = static_cast<vtkIdType>(cellIndex(shape, n));
      bool here = mask->GetValue(cell) != 0;
      for (std::size_t c = 0; !here && firstChild[n] && c < children; ++c)
      {
        here = marked[firstChild[n] + c] != 0;
      }
      marked[n] = here;
      if (here)
      {
        pure->SetValue(cell, 1);
      }
    }
  }
  return pure;
}

vtkSmartPointer<vtkBitArray> buildMask(const ForestDescription& forest, const ForestLayout& layout,
                                       const BlockCells* blocks)
{
  vtkSmartPointer<vtkBitArray> mask = zeroBits(layout.totalCells);
  mask->SetName("vtkHyperTreeGridMask");
  if (blocks)
  {
    // Blocks are masked whole, at their root: VTK hides a masked node's subtree.
    for (std::size_t node = 0; node < blocks->numberOfNodes(); ++node)
    {
      if (blocks->isMasked(node) || blocks->isAbsent(node))
      {
        mask->SetValue(static_cast<vtkIdType>(blocks->cellOfNode(node)), 1);
      }
    }
    return mask;
  }
  // Absent cells are masked too: every filter skips them, as it skips holes.
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeDescription& tree = forest.trees[t];
    if (!tree.masked && !tree.absent)
    {
      continue;
    }
    const TreeLayout& shape = layout.trees[t];
    for (std::size_t n = 0; n < shape.numberOfNodes; ++n)
    {
      if ((tree.masked && tree.masked[n]) || isAbsent(tree, n))
      {
        mask->SetValue(static_cast<vtkIdType>(cellIndex(shape, n)), 1);
      }
    }
  }
  return mask;
}

/// VTK's ghost array marks absent cells DUPLICATECELL ("another process owns
/// it"): what tells an absent cell from a masked one (see docs/api.md).
vtkSmartPointer<vtkUnsignedCharArray> buildAbsentGhosts(const ForestDescription& forest,
                                                        const ForestLayout& layout,
                                                        const BlockCells* blocks)
{
  auto ghosts = vtkSmartPointer<vtkUnsignedCharArray>::New();
  ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
  ghosts->SetNumberOfValues(static_cast<vtkIdType>(layout.totalCells));
  unsigned char* values = ghosts->GetPointer(0);
  std::memset(values, 0, layout.totalCells);
  if (blocks)
  {
    for (std::size_t node = 0; node < blocks->numberOfNodes(); ++node)
    {
      if (blocks->isAbsent(node))
      {
        values[blocks->cellOfNode(node)] = vtkDataSetAttributes::DUPLICATECELL;
      }
    }
    return ghosts;
  }
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeDescription& tree = forest.trees[t];
    const TreeLayout& shape = layout.trees[t];
    for (std::size_t n = 0; tree.absent && n < shape.numberOfNodes; ++n)
    {
      if (tree.absent[n])
      {
        values[shape.firstCell + n] = vtkDataSetAttributes::DUPLICATECELL;
      }
    }
  }
  return ghosts;
}

vtkSmartPointer<vtkHyperTreeGrid> newGrid(const ForestDescription& forest)
{
  auto htg = vtkSmartPointer<vtkHyperTreeGrid>::New();
  const RootGrid& grid = forest.rootGrid;
  // Dimensions before branch factor: the latter derives the number of children from both.
  // VTK derives the dimension (1, 2 or 3) and a 1D or 2D grid's orientation from the
  // point counts: a line of roots needs nothing more.
  htg->SetDimensions(static_cast<unsigned int>(grid.pointsX),
                     static_cast<unsigned int>(grid.pointsY),
                     static_cast<unsigned int>(grid.pointsZ));
  htg->SetBranchFactor(static_cast<unsigned int>(forest.branchFactor));
  setCoordinates(htg, grid);
  return htg;
}

void setCoordinates(vtkHyperTreeGrid* htg, const RootGrid& grid)
{
  htg->SetXCoordinates(borrowCoordinates(grid.x, grid.pointsX));
  htg->SetYCoordinates(borrowCoordinates(grid.y, grid.pointsY));
  htg->SetZCoordinates(borrowCoordinates(grid.z, grid.pointsZ));
}

void setTopologyArrays(vtkHyperTreeGrid* htg, const ForestDescription& forest,
                       const ForestLayout& layout, const BlockCells* blocks)
{
  if (layout.anyMask || layout.anyAbsent)
  {
    vtkSmartPointer<vtkBitArray> mask = buildMask(forest, layout, blocks);
    htg->SetMask(mask);
    // What ShallowCopy (and ParaView after every filter) would have VTK compute
    // with a cursor walk over every node.
    setPureMask(htg, blocks ? buildBlockPureMask(*blocks, layout.totalCells)
                            : buildPureMask(forest, layout, mask));
  }
  else
  {
    htg->SetMask(nullptr);
  }
  vtkCellData* cells = htg->GetCellData();
  cells->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  if (layout.anyAbsent)
  {
    cells->AddArray(buildAbsentGhosts(forest, layout, blocks));
  }
  htg->GetFieldData()->RemoveArray(missingTreesElsewhereName);
  if (forest.missingTreesAreElsewhere)
  {
    // Read by Canopy's filters (HyperTreeAccess::treeElsewhere).
    auto flag = vtkSmartPointer<vtkIntArray>::New();
    flag->SetName(missingTreesElsewhereName);
    flag->InsertNextValue(1);
    htg->GetFieldData()->AddArray(flag);
  }
}

void setFields(vtkHyperTreeGrid* htg, const ForestDescription& forest, const ForestLayout& layout,
               const std::vector<const FieldDescription*>& fields, FieldTables& tables,
               const std::vector<vtkDataArray*>& kept)
{
  auto keptAt = [&kept](std::size_t f) { return f < kept.size() ? kept[f] : nullptr; };
  vtkCellData* cells = htg->GetCellData();
  // Replace the previous step's fields (the ghost array is topology, kept).
  for (int a = cells->GetNumberOfArrays(); a-- > 0;)
  {
    const char* name = cells->GetArrayName(a);
    if (!name || std::strcmp(name, vtkDataSetAttributes::GhostArrayName()) != 0)
    {
      cells->RemoveArray(a);
    }
  }
  if (forest.blockCellsPerSide != 0)
  {
    if (!tables.blocks)
    {
      tables.blocks = indexBlocks(forest, layout);
    }
    for (std::size_t f = 0; f < fields.size(); ++f)
    {
      if (vtkDataArray* same = keptAt(f))
      {
        cells->AddArray(same);
        continue;
      }
      cells->AddArray(wrapBlockField(*fields[f], tables.blocks));
    }
    return;
  }
  if (!tables.slots)
  {
    tables.slots = CellSlots::build(forest, layout);
  }
  for (std::size_t f = 0; f < fields.size(); ++f)
  {
    const FieldDescription* field = fields[f];
    if (vtkDataArray* same = keptAt(f))
    {
      cells->AddArray(same);
      continue;
    }
    vtkSmartPointer<vtkDataArray> array;
    if (field->centering == Centering::LeavesOnly)
    {
      if (!tables.leaves)
      {
        tables.leaves = LeafTupleMap::build(forest, layout, *tables.slots);
      }
      array = wrapLeafField(*field, forest, layout, *tables.leaves);
    }
    else
    {
      array = wrapNodeField(*field, layout, *tables.slots);
    }
    cells->AddArray(array);
  }
}

} // namespace canopy::assembly
