// The selection's output with PreserveTopology off: the selected nodes as cells
// of a vtkUnstructuredGrid (VTK_LINE in 1D, VTK_QUAD in 2D, VTK_HEXAHEDRON in
// 3D) with merged points, the input's cell fields, "OriginalCellId" and "Level".
#pragma once

#include "CellSelection.h"
#include "HyperTreeAccess.h"

#include <array>
#include <vector>

class vtkHyperTreeGrid;
class vtkUnstructuredGrid;

namespace canopy
{

/// Writes `nodes` (in order) into `output` (initialized first), their fields
/// gathered from `input`'s cell data.
void writeSelectedCells(const HyperTreeAccess& grid, const CellSelection& selection,
                        const std::vector<SelectedNode>& nodes, vtkHyperTreeGrid* input,
                        vtkUnstructuredGrid* output);

/// Bounds of the nodes' boxes: xmin, xmax, ymin, ymax, zmin, zmax (min > max
/// when there are none).
std::array<double, 6> boundsOf(const CellSelection& selection,
                               const std::vector<SelectedNode>& nodes);

} // namespace canopy
