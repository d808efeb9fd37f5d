#include "canopy/HtgBuilder.h"

#include "CellSlots.h"
#include "FieldWrapping.h"
#include "LeafRestriction.h"
#include "StorageSlots.h"

#include <vtkBitArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cstring>
#include <optional>

namespace canopy
{
namespace
{

vtkSmartPointer<vtkDoubleArray> borrowCoordinates(const double* coords, std::size_t points)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetArray(const_cast<double*>(coords), static_cast<vtkIdType>(points), 1);
  return array;
}

/// The requested fields, in the forest's order; throws on unknown names.
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

/// All trees' breadth-first descriptors, back to back, without their deepest
/// level (VTK infers it: it is all leaves).
vtkSmartPointer<vtkBitArray> packDescriptors(const ForestDescription& forest,
                                             const ForestLayout& layout)
{
  auto bits = vtkSmartPointer<vtkBitArray>::New();
  bits->SetNumberOfValues(static_cast<vtkIdType>(layout.totalDescriptorBits));
  if (layout.totalDescriptorBits == 0)
  {
    return bits;
  }
  unsigned char* bytes = bits->GetPointer(0);
  std::memset(bytes, 0, (layout.totalDescriptorBits + 7) / 8);
  std::size_t position = 0;
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const std::uint8_t* refinement = forest.trees[t].refinement;
    const std::size_t count = layout.trees[t].descriptorBits;
    for (std::size_t n = 0; n < count; ++n, ++position)
    {
      // vtkBitArray stores the most significant bit first.
      bytes[position >> 3] |=
          static_cast<unsigned char>((refinement[n] != 0) << (7 - (position & 7)));
    }
  }
  return bits;
}

void buildTrees(vtkHyperTreeGrid* htg, const ForestDescription& forest, const ForestLayout& layout)
{
  vtkSmartPointer<vtkBitArray> descriptors = packDescriptors(forest, layout);
  vtkIdType start = 0;
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeDescription& tree = forest.trees[t];
    const TreeLayout& shape = layout.trees[t];
    vtkHyperTree* hyperTree = htg->GetTree(tree.rootIndex, /*create=*/true);
    const auto bits = static_cast<vtkIdType>(shape.descriptorBits);
    hyperTree->BuildFromBreadthFirstOrderDescriptor(descriptors, bits, start);
    start += bits;
    if (layout.anyAbsent)
    {
      // Cells numbered breadth-first; fields read through CellSlots.
      hyperTree->SetGlobalIndexStart(static_cast<vtkIdType>(shape.firstCell));
      continue;
    }
    if (!layout.explicitSlots)
    {
      hyperTree->SetGlobalIndexStart(static_cast<vtkIdType>(shape.firstSlot));
      continue;
    }
    // Size the table once (the last call sizes it), then fill it.
    const auto last = static_cast<vtkIdType>(shape.numberOfNodes - 1);
    hyperTree->SetGlobalIndexFromLocal(last, tree.storageSlots[last]);
    for (vtkIdType n = 0; n < last; ++n)
    {
      hyperTree->SetGlobalIndexFromLocal(n, tree.storageSlots[n]);
    }
  }
}

vtkSmartPointer<vtkBitArray> buildMask(const ForestDescription& forest, const ForestLayout& layout)
{
  auto mask = vtkSmartPointer<vtkBitArray>::New();
  mask->SetName("vtkHyperTreeGridMask");
  mask->SetNumberOfValues(static_cast<vtkIdType>(layout.totalNodes));
  if (layout.totalNodes > 0)
  {
    std::memset(mask->GetPointer(0), 0, (layout.totalNodes + 7) / 8);
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
        mask->SetValue(static_cast<vtkIdType>(cellIndex(layout, tree, shape, n)), 1);
      }
    }
  }
  return mask;
}

/// VTK's ghost array marks absent cells DUPLICATECELL ("another process owns
/// it"): what tells an absent cell from a masked one (see docs/api.md).
vtkSmartPointer<vtkUnsignedCharArray> buildAbsentGhosts(const ForestDescription& forest,
                                                        const ForestLayout& layout)
{
  auto ghosts = vtkSmartPointer<vtkUnsignedCharArray>::New();
  ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
  ghosts->SetNumberOfValues(static_cast<vtkIdType>(layout.totalNodes));
  unsigned char* values = ghosts->GetPointer(0);
  std::memset(values, 0, layout.totalNodes);
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

/// The build itself, from the layout validateForest just computed for `forest`
/// (never a stored one: a layout that no longer matches would be read out of bounds).
vtkSmartPointer<vtkHyperTreeGrid> buildValidated(const ForestDescription& forest,
                                                 const ForestLayout& layout,
                                                 const FieldRequest& request)
{
  const std::vector<const FieldDescription*> fields = selectFields(forest, request);

  auto htg = vtkSmartPointer<vtkHyperTreeGrid>::New();
  const RootGrid& grid = forest.rootGrid;
  // Dimensions before branch factor: the latter derives the number of children from both.
  // VTK derives the dimension (1, 2 or 3) and a 1D or 2D grid's orientation from the
  // point counts: a line of roots needs nothing more.
  htg->SetDimensions(static_cast<unsigned int>(grid.pointsX),
                     static_cast<unsigned int>(grid.pointsY),
                     static_cast<unsigned int>(grid.pointsZ));
  htg->SetBranchFactor(static_cast<unsigned int>(forest.branchFactor));
  htg->SetXCoordinates(borrowCoordinates(grid.x, grid.pointsX));
  htg->SetYCoordinates(borrowCoordinates(grid.y, grid.pointsY));
  htg->SetZCoordinates(borrowCoordinates(grid.z, grid.pointsZ));

  buildTrees(htg, forest, layout);
  if (layout.anyMask || layout.anyAbsent)
  {
    htg->SetMask(buildMask(forest, layout));
  }
  if (layout.anyAbsent)
  {
    htg->GetCellData()->AddArray(buildAbsentGhosts(forest, layout));
  }
  if (forest.missingTreesAreElsewhere)
  {
    // Read by Canopy's filters (HyperTreeAccess::treeElsewhere).
    auto flag = vtkSmartPointer<vtkIntArray>::New();
    flag->SetName("CanopyMissingTreesElsewhere");
    flag->InsertNextValue(1);
    htg->GetFieldData()->AddArray(flag);
  }

  const CellSlots slots = CellSlots::build(forest, layout);
  std::optional<LeafTupleMap> leafMap;
  for (const FieldDescription* field : fields)
  {
    vtkSmartPointer<vtkDataArray> array;
    if (field->centering == Centering::LeavesOnly)
    {
      if (!leafMap)
      {
        leafMap = LeafTupleMap::build(forest, layout, slots);
      }
      array = wrapLeafField(*field, forest, layout, *leafMap);
    }
    else
    {
      array = wrapNodeField(*field, layout, slots);
    }
    htg->GetCellData()->AddArray(array);
  }
  return htg;
}

} // namespace

vtkSmartPointer<vtkHyperTreeGrid> buildHyperTreeGrid(const ForestDescription& forest,
                                                     const FieldRequest& request)
{
  return buildValidated(forest, validateForest(forest), request);
}

} // namespace canopy
