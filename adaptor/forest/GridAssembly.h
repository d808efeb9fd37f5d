// The steps that turn a validated forest description into a vtkHyperTreeGrid,
// shared by the one-shot build (buildHyperTreeGrid) and the step-to-step builder
// that rebuilds only what changed (GridBuilder). Every function takes the
// layout layoutForest just computed for the same description.
#pragma once

#include "BlockCells.h"
#include "CellSlots.h"
#include "ForestLayout.h"
#include "LeafRestriction.h"
#include <canopy/ForestDescription.h>
#include <canopy/HtgBuilder.h>

#include <vtkSmartPointer.h>

#include <memory>
#include <optional>
#include <vector>

class vtkBitArray;
class vtkDataArray;
class vtkHyperTreeGrid;
class vtkUnsignedCharArray;

namespace canopy::assembly
{

/// Field-data flag (a one-value integer array) saying that root cells without a
/// tree have it on another rank; Canopy's filters read it under the same name.
inline constexpr const char* missingTreesElsewhereName = "CanopyMissingTreesElsewhere";

/// An empty grid with the forest's root grid (coordinates borrowed).
vtkSmartPointer<vtkHyperTreeGrid> newGrid(const ForestDescription& forest);
/// Borrows the root coordinates again (the simulation may have moved them).
void setCoordinates(vtkHyperTreeGrid* htg, const RootGrid& grid);

/// The index of a block forest's cells (BlockCells.h), null for other forests.
std::shared_ptr<const BlockCells> indexBlocks(const ForestDescription& forest,
                                              const ForestLayout& layout);

/// (Re)builds the trees marked in `rebuild` (one flag per forest tree) from their
/// refinement bytes (in a block forest, with `blocks`' cells below each block
/// root), each as a new tree object, and sets every tree's first cell.
void buildTrees(vtkHyperTreeGrid* htg, const ForestDescription& forest, const ForestLayout& layout,
                const std::vector<bool>& rebuild, const BlockCells* blocks);

/// The mask (masked and absent cells), the absent cells' ghost marks and the
/// trees-elsewhere flag, replacing any earlier ones. `blocks`: as buildTrees.
void setTopologyArrays(vtkHyperTreeGrid* htg, const ForestDescription& forest,
                       const ForestLayout& layout, const BlockCells* blocks);
vtkSmartPointer<vtkBitArray> buildMask(const ForestDescription& forest, const ForestLayout& layout,
                                       const BlockCells* blocks);
vtkSmartPointer<vtkUnsignedCharArray> buildAbsentGhosts(const ForestDescription& forest,
                                                        const ForestLayout& layout,
                                                        const BlockCells* blocks);

/// The requested fields, in the forest's order; throws InvalidForest on unknown names.
std::vector<const FieldDescription*> selectFields(const ForestDescription& forest,
                                                  const FieldRequest& request);

/// Tables the fields read through; they depend on the topology only, so a grid
/// whose topology did not change keeps them. Built on first use.
struct FieldTables
{
  std::optional<CellSlots> slots;
  std::optional<LeafTupleMap> leaves;
  std::shared_ptr<const BlockCells> blocks; ///< block forests: no table per cell
};

/// Replaces the grid's fields by `fields`, wrapped in place (leaves-only ones get
/// their coarse averages computed now), or, where `kept[i]` is not null, by that
/// array (the same object, as it was: its values are vouched unchanged). `kept`
/// is empty or has one entry per field.
void setFields(vtkHyperTreeGrid* htg, const ForestDescription& forest, const ForestLayout& layout,
               const std::vector<const FieldDescription*>& fields, FieldTables& tables,
               const std::vector<vtkDataArray*>& kept = {});

} // namespace canopy::assembly
