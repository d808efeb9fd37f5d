// This rank's rows of a VTKHDF step: its piece of the grid (counts, trees,
// descriptors, mask, coordinates) and its cell arrays, given to a RowSink
// (VtkHdfRowTransfer.h) dataset by dataset, in the layout's order.
#pragma once

#include <string>
#include <vector>

class vtkDataArray;
class vtkHyperTreeGrid;

namespace canopy::io
{

class RowSink;
class VtkHdfLayout;
struct HyperTreeGridPiece;
struct StepShape;

/// Gives `sink` the rows of `piece` of `htg` and of its cell `arrays` (all
/// borrowed for the call) for each dataset of `layout` (only its list of
/// datasets is read: no file is needed), sized by this rank's counts in `shape`.
/// The first problem, if any (then the rest is not given).
std::string putPieceRows(RowSink& sink, const VtkHdfLayout& layout, const StepShape& shape,
                         const HyperTreeGridPiece& piece, vtkHyperTreeGrid* htg,
                         const std::vector<vtkDataArray*>& arrays);

} // namespace canopy::io
