// Writes a vtkHyperTreeGrid as a .htg file that ParaView 5.11 reads back
// intact, vector fields included.
//
// VTK 9.2's vtkXMLHyperTreeGridWriter corrupts arrays of more than one
// component in every format version (version 2, the default, writes wrong
// values once trees have more than two levels; version 1 crashes; version 0
// overruns a buffer), and its appended mode corrupts the header. Its reader is
// sound for format 1.0, where each tree carries its own arrays: it places them
// tuple by tuple (format 2.0's reader mixes up values and tuples, so no file
// can carry a vector there). This writer therefore writes format 1.0 itself:
// one <Tree> per hypertree (breadth-first descriptor, cells per level, mask,
// cell data), raw binary appended data, vectors as vectors.
#pragma once

#include "CanopyIOModule.h"

#include <string>
#include <vector>

class vtkHyperTreeGrid;

namespace canopy::io
{

/// Writes `htg` to `fileName` (through a temporary file renamed at the end, so a
/// failed write never leaves a truncated file under that name). `arrays` names
/// the cell arrays to write; empty: every numeric cell array. Returns an empty
/// string on success, otherwise what went wrong.
CANOPYIO_EXPORT std::string writeHtgFile(vtkHyperTreeGrid* htg, const std::string& fileName,
                                         const std::vector<std::string>& arrays = {});

/// The same file's bytes in `text` (replaced; empty on failure), for grids
/// that travel instead of being written (vtkCanopyHyperTreeGridPacker).
/// vtkXMLHyperTreeGridReader reads them with ReadFromInputString. Returns an
/// empty string on success, otherwise what went wrong.
CANOPYIO_EXPORT std::string writeHtgText(vtkHyperTreeGrid* htg, std::string& text,
                                         const std::vector<std::string>& arrays = {});

} // namespace canopy::io
