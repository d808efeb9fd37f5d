// Copies the cell values of selected cells into a new array: the one place the
// filters turn "these global ids" into output cell data.
#pragma once

#include <vtkSmartPointer.h>
#include <vtkType.h>

class vtkDataArray;

namespace canopy
{

/// Fills `out` (a fresh array of the source's type when null) with the tuples
/// of `source` at `ids`, in order, and names it like the source. Contiguous
/// (AoS) sources are copied tuple by tuple with memcpy, in parallel; other
/// arrays through their own GetTuples (typed for SoA and for Canopy's
/// simulation arrays).
vtkSmartPointer<vtkDataArray> gatherTuples(vtkDataArray* source, const vtkIdType* ids,
                                           vtkIdType count,
                                           vtkSmartPointer<vtkDataArray> out = nullptr);

} // namespace canopy
