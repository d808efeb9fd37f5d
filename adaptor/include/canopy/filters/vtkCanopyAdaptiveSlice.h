/**
 * @class vtkCanopyAdaptiveSlice
 * @brief Axis-aligned slices of a 3D vtkHyperTreeGrid, culled by the view and
 * refined no finer than a pixel.
 *
 * Each plane (x = c, y = c or z = c) is drawn as one quad per node where
 * descent stops: the node's cross-section by the plane, carrying the node's
 * cell values. Only the trees and nodes the plane cuts are entered, and of
 * those only the ones whose cut the view sees (exact separating-axis test);
 * descent stops at leaves or, with LevelOfDetail on, at nodes whose cut projects
 * to at most PixelThreshold pixels. The fields are read in place (gathered into
 * the output's cell data at the drawn nodes only).
 *
 * Face rule: cells are half-open [lo, hi) along the plane's axis, the grid's
 * last cell also owning the upper boundary; a plane on a face shared by two
 * cells cuts the cell on its upper side (the same rule as locations in
 * vtkCanopyExtractSelection), identically on every rank. Planes outside the grid
 * draw nothing. Masked cells and other ranks' parts of split trees are not
 * drawn, and a node with another rank's parts below it is never drawn whole.
 *
 * The view and the shared properties: vtkCanopyViewDependentFilter. With
 * ViewDependent off every cut leaf is drawn.
 *
 * Output: vtkPolyData of flat pieces (normals along +axis), one per node where
 * descent stops: a quad, or a polygon that also carries, in order along its
 * edges, the corners of the smaller cuts meeting them (no pixel holes where a
 * coarse cut meets finer ones; across processes too, through the Controller:
 * the execution is then collective). Double-precision points, the selected
 * input cell fields (all by default), "OriginalCellId" and "Level". Planes in
 * the order x, y, z, each axis in the order added.
 */
#pragma once

#include "CanopyFiltersModule.h"
#include <canopy/filters/vtkCanopyViewDependentFilter.h>

#include <array>
#include <vector>

class CANOPYFILTERS_EXPORT vtkCanopyAdaptiveSlice : public vtkCanopyViewDependentFilter
{
public:
  static vtkCanopyAdaptiveSlice* New();
  vtkTypeMacro(vtkCanopyAdaptiveSlice, vtkCanopyViewDependentFilter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Planes: axis 0 (x), 1 (y) or 2 (z) and the position along it. Checked when
  /// the filter runs (an invalid axis or a position that is not finite is an
  /// error naming the plane).
  void AddPlane(int axis, double position);
  void ClearPlanes();
  int GetNumberOfPlanes() const;
  ///@}

  ///@{
  /// The same per axis, as ParaView's properties XPlanes, YPlanes, ZPlanes set them.
  void AddXPlane(double x) { this->AddPlane(0, x); }
  void AddYPlane(double y) { this->AddPlane(1, y); }
  void AddZPlane(double z) { this->AddPlane(2, z); }
  void ClearXPlanes() { this->ClearAxis(0); }
  void ClearYPlanes() { this->ClearAxis(1); }
  void ClearZPlanes() { this->ClearAxis(2); }
  ///@}

  /// Nodes the last execution examined (what the slices cost: only nodes the
  /// planes cut, and of those only the ones in view, are examined).
  vtkGetMacro(LastVisited, vtkIdType);

protected:
  vtkCanopyAdaptiveSlice();
  ~vtkCanopyAdaptiveSlice() override;

  int ProcessTrees(vtkHyperTreeGrid* input, vtkDataObject* output) override;
  /// One plane normal to `axis` (its cuts are one layer on screen).
  bool OneLayerFacing(vtkHyperTreeGrid* input, int axis) const override;

  /// Per axis, the planes' positions in the order added; an axis outside 0-2
  /// is kept aside so that the error can name it.
  std::array<std::vector<double>, 3> Positions;
  std::vector<int> InvalidAxes;
  vtkIdType LastVisited = 0;

private:
  vtkCanopyAdaptiveSlice(const vtkCanopyAdaptiveSlice&) = delete;
  void operator=(const vtkCanopyAdaptiveSlice&) = delete;
  void ClearAxis(int axis);
};
