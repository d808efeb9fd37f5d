// The selection's output with PreserveTopology on: the input's structure,
// trees, cell and field data, shared, with another mask (SelectionMask.h).
#pragma once

class vtkBitArray;
class vtkHyperTreeGrid;

namespace canopy
{

/// Makes `output` the input's grid with `mask` (and VTK's pure mask `pure`,
/// PureMask.h). Not ShallowCopy: in VTK 9.2 it also asks the input for its
/// "pure mask", a cursor walk over every node whenever the input has a mask (a
/// chained selection's does), which cost more than the selection itself.
void shareWithMask(vtkHyperTreeGrid* input, vtkHyperTreeGrid* output, vtkBitArray* mask,
                   vtkBitArray* pure);

} // namespace canopy
