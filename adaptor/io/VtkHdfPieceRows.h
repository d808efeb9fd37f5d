// This rank's rows of a VTKHDF step: its piece of the grid (counts, trees,
// descriptors, mask, coordinates) and its cell arrays, written into the
// datasets of the layout at the rank's place within the step.
#pragma once

#include <string>
#include <vector>

class vtkDataArray;
class vtkHyperTreeGrid;

namespace canopy::io
{

class VtkHdfLayout;
struct HyperTreeGridPiece;
struct StepShape;

/// Writes `piece` of `htg` and its cell `arrays` (all borrowed for the call)
/// into the datasets of `layout`, open and grown by the step of `shape`.
/// Independent I/O: each rank writes its own rows. The first problem, if any.
std::string writePieceRows(VtkHdfLayout& layout, const StepShape& shape,
                           const HyperTreeGridPiece& piece, vtkHyperTreeGrid* htg,
                           const std::vector<vtkDataArray*>& arrays);

} // namespace canopy::io
