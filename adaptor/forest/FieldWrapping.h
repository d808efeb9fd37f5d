// Turns one borrowed FieldDescription into a vtkDataArray without copying values.
#pragma once

#include "BlockCells.h"
#include "CellSlots.h"
#include "LeafRestriction.h"
#include <canopy/ForestDescription.h>
#include <canopy/ForestValidation.h>

#include <vtkSmartPointer.h>

#include <memory>

class vtkDataArray;

namespace canopy
{

/// EveryNode field: wraps it in place, one tuple per cell (absent cells read a
/// fill value through `slots`).
vtkSmartPointer<vtkDataArray> wrapNodeField(const FieldDescription& field,
                                            const ForestLayout& layout, const CellSlots& slots);

/// LeavesOnly field: borrows the leaf tuples, owns the coarse averages.
vtkSmartPointer<vtkDataArray> wrapLeafField(const FieldDescription& field,
                                            const ForestDescription& forest,
                                            const ForestLayout& layout, const LeafTupleMap& map);

/// Block field (block forests): read from the blocks through `blocks`, coarse
/// values computed when read (BlockField.h).
vtkSmartPointer<vtkDataArray> wrapBlockField(const FieldDescription& field,
                                             std::shared_ptr<const BlockCells> blocks);

} // namespace canopy
