// Turns one borrowed FieldDescription into a vtkDataArray without copying values.
#pragma once

#include "CellSlots.h"
#include "LeafRestriction.h"
#include "canopy/ForestDescription.h"
#include "canopy/ForestValidation.h"

#include <vtkSmartPointer.h>

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

} // namespace canopy
