// Writes a vtkHyperTreeGrid as a .htg file that ParaView 5.11 reads back intact.
//
// VTK 9.2's vtkXMLHyperTreeGridWriter mishandles multi-component cell arrays in
// every format version it offers: version 2 (the default) writes wrong values
// once trees have more than two levels, version 1 crashes, and version 0 writes
// past the end of its buffer. Appended data mode also corrupts the file header.
// Scalar arrays round-trip correctly, so this writer splits each vector array
// into one scalar array per component (velocity -> velocity_X, velocity_Y,
// velocity_Z, ParaView's component names) and uses inline binary data. The split
// copies values for the file only; the grid itself is not modified.
#pragma once

#include <string>

class vtkHyperTreeGrid;

namespace canopy::tools
{

/// Writes `htg` to `fileName`. Returns an empty string on success, otherwise
/// what went wrong.
std::string writeHtgFile(vtkHyperTreeGrid* htg, const std::string& fileName);

/// The name the file gives component `component` of a `components`-wide array.
std::string componentArrayName(const std::string& name, int component, int components);

} // namespace canopy::tools
