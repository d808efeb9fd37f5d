// What a selection asks for, as vtkCanopyExtractSelection reads it: from the
// first node of the vtkSelection on its port 1 (VTK's convention) or else from
// its convenience properties, into one form, checked against the input before
// anything is walked (a bad request is an error message, never a crash), and
// fingerprinted for the mask memo (SelectionMaskMemo.h).
#pragma once

#include "Frustum.h"
#include "HyperTreeAccess.h"
#include "Vec3.h"

#include <vtkType.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

class vtkDataArray;
class vtkHyperTreeGrid;
class vtkSelection;

namespace canopy
{

/// The filter's convenience properties as they are set (vtkCanopyExtractSelection.h
/// documents each); what is selected when no vtkSelection is connected.
struct SelectionProperties
{
  int mode;
  const std::vector<double>& locations; ///< x y z per point
  const std::vector<vtkIdType>& ids;
  const std::string& field;
  int component;
  const double* range;         ///< [low, high]
  const double* box;           ///< xmin, xmax, ymin, ymax, zmin, zmax
  const double* frustumPlanes; ///< 24 values: (a, b, c, d) per plane
  const std::vector<double>& frustumCorners;
  bool invert;
};

struct SelectionSpec
{
  int mode = 0; ///< vtkCanopyExtractSelection::SelectionModes
  std::vector<Vec3> points;
  std::vector<vtkIdType> ids;
  std::string field;
  int component = 0;
  std::array<double, 2> range{{0, 0}};
  std::array<double, 6> box{{0, 0, 0, 0, 0, 0}};
  Frustum frustum;
  /// Select the complement: the Invert property, inverted once more by the
  /// selection node's INVERSE key (as in VTK).
  bool invert = false;
  /// A value range's field in the input (found by the check; nullptr otherwise).
  vtkDataArray* values = nullptr;

  /// A box or a frustum: tested against the cells' boxes.
  bool byRegion() const;
  /// Ids and values read cells by their global index (SelectionMaskMemo::begin).
  bool readsByCellNumber() const;
  /// What a masked selection depends on beside the trees (SelectionMaskMemo):
  /// the grid's kind, the mode and its parameters, and for a value range the
  /// values' array and its modified time (VTK gives each change a later time).
  std::uint64_t fingerprint(const HyperTreeAccess& grid, bool allowMasked) const;
};

/// Reads what `selection` (or, when it is null, `properties`) asks for into
/// `spec` and checks it against `input`: the points finite, a box's bounds in
/// order, a frustum well formed, a value range's field and component present.
/// Returns the problem, as the filter reports it, or an empty string.
std::string readSelectionSpec(const SelectionProperties& properties, vtkSelection* selection,
                              vtkHyperTreeGrid* input, SelectionSpec& spec);

} // namespace canopy
