// Which cell arrays of a grid a writer writes.
#pragma once

#include <string>
#include <vector>

class vtkDataArray;
class vtkHyperTreeGrid;

namespace canopy::io
{

/// The numeric cell arrays of `htg` named in `names` (empty: all of them), in
/// the grid's order. A name the grid lacks, or an array that is not numeric,
/// is added to `problems`.
std::vector<vtkDataArray*> selectCellArrays(vtkHyperTreeGrid* htg,
                                            const std::vector<std::string>& names,
                                            std::vector<std::string>& problems);

} // namespace canopy::io
