/**
 * @class vtkCanopyExtractSelection
 * @brief Extracts cells of a vtkHyperTreeGrid by location, by global id, by
 * value range, by box or by frustum, as a masked hypertree grid or as an
 * unstructured grid.
 *
 * Input 0: the vtkHyperTreeGrid. Input 1 (optional): a vtkSelection whose first
 * node is LOCATIONS (3-component points), GLOBALIDS or INDICES (cell ids),
 * THRESHOLDS (one [low, high] pair; the selection list's name is the field, the
 * COMPONENT_NUMBER key the component, -1 for the magnitude) or FRUSTUM (eight
 * corners x, y, z, w, 32 values, as ParaView's "select cells on" and
 * vtkExtractSelectedFrustum give them; w is ignored, as VTK does). Without input 1
 * the convenience properties below say what to select.
 *
 * Location rule: cells are half-open [lo, hi) along each axis, the grid's last
 * cell along an axis also owning the upper boundary; a point on a shared face,
 * edge or corner belongs to the cell on its upper side; points outside the
 * domain select nothing. Ids: each global index selects its node, coarse ones
 * included; out-of-range ids and duplicates are ignored and counted. Values:
 * visible leaves with a value within [low, high] (inclusive, never NaN).
 *
 * Box and frustum: the visible leaves whose closed box shares a part of positive
 * measure with the closed region, measured in the grid's own dimension: volume
 * in 3D, area in 2D, length in 1D. A leaf touching the region only along a face,
 * edge or corner is not selected, nor is anything by a region without volume. A
 * box ignores its extent along the flat axes of a 2D or 1D grid (as locations
 * do); a frustum is cut by the plane of a 2D grid or the line of a 1D grid, and a
 * leaf is selected when it overlaps that section with positive area or length.
 * Box bounds are compared exactly with the cells' bounds; frustum overlap is an
 * exact separating-axis test in floating point. Subtrees that do not overlap the
 * region are never descended: the cost is proportional to what overlaps it
 * (GetLastVisited).
 *
 * Masked cells are selectable only with AllowMasked on. Absent cells (parts of
 * split trees other ranks own: masked and marked DUPLICATECELL) never are.
 *
 * Invert (or the selection node's INVERSE key, as VTK's vtkExtractSelection
 * reads it): select instead the selectable leaves that are neither selected nor
 * below a selected cell. A box with Invert cuts that box away (an octant removed
 * to look inside); two filters chained (a value range, then an inverted box)
 * select their intersection.
 *
 * PreserveTopology on: a vtkHyperTreeGrid sharing the input's trees and arrays
 * with a new mask leaving visible the selected cells, their ancestors (needed to
 * reach them) and the subtrees of selected coarse cells. Off: a
 * vtkUnstructuredGrid of VTK_LINE (1D), VTK_QUAD (2D) or VTK_HEXAHEDRON (3D)
 * cells with merged points, the input's cell fields, "OriginalCellId" and
 * "Level". Grids of any dimension (1, 2, 3) and any axis-aligned orientation.
 * With PreserveTopology the filter keeps its last mask tree by tree and redoes
 * only the trees whose topology, mask or ghost marks, root box or selection
 * changed (GetLastKeptTrees, GetLastRecomputedNodes); a box or frustum that
 * misses or holds a tree whole (no masked cell in it) marks it without a walk.
 *
 * An execution reports its progress a few times (UpdateProgress) and checks
 * once per tree whether it was aborted (AbortExecute, CheckAbort): aborted, it
 * leaves an empty output.
 */
#pragma once

#include "CanopyFiltersModule.h"

#include <vtkDataObjectAlgorithm.h>

#include <memory>
#include <string>
#include <vector>

class CANOPYFILTERS_EXPORT vtkCanopyExtractSelection : public vtkDataObjectAlgorithm
{
public:
  static vtkCanopyExtractSelection* New();
  vtkTypeMacro(vtkCanopyExtractSelection, vtkDataObjectAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum SelectionModes
  {
    LOCATIONS = 0,
    IDS = 1,
    VALUE_RANGE = 2,
    BOX = 3,
    FRUSTUM = 4
  };

  ///@{
  /// What the convenience properties select (ignored when input 1 is connected).
  vtkSetClampMacro(SelectionMode, int, LOCATIONS, FRUSTUM);
  vtkGetMacro(SelectionMode, int);
  ///@}

  ///@{
  void AddLocation(double x, double y, double z);
  void ClearLocations();
  void AddId(vtkIdType id);
  void ClearIds();
  ///@}

  ///@{
  /// Value range: field name, component (-1: magnitude), inclusive bounds.
  vtkSetStdStringFromCharMacro(ValueArrayName);
  vtkGetCharFromStdStringMacro(ValueArrayName);
  vtkSetMacro(ValueComponent, int);
  vtkGetMacro(ValueComponent, int);
  vtkSetVector2Macro(ValueRange, double);
  vtkGetVector2Macro(ValueRange, double);
  ///@}

  ///@{
  /// BOX: [xmin, xmax, ymin, ymax, zmin, zmax], closed; min <= max on every axis,
  /// infinite bounds allowed, NaN not.
  vtkSetVector6Macro(Box, double);
  vtkGetVector6Macro(Box, double);
  ///@}

  ///@{
  /// FRUSTUM from six planes: (a, b, c, d) each, inside where a x + b y + c z + d
  /// >= 0, as vtkCamera::GetFrustumPlanes returns them and vtkPlanes::SetFrustumPlanes
  /// takes them. Used unless eight corners are given.
  void SetFrustumPlanes(const double planes[24]);
  const double* GetFrustumPlanes() const VTK_SIZEHINT(24) { return this->FrustumPlanes; }
  ///@}

  ///@{
  /// FRUSTUM from eight corners in vtkSelectionNode::FRUSTUM's order (near lower
  /// left, far lower left, near upper left, far upper left, near lower right, far
  /// lower right, near upper right, far upper right). With exactly eight corners
  /// they define the frustum (FrustumPlanes is then ignored); with none,
  /// FrustumPlanes does; any other count is an error.
  void AddFrustumCorner(double x, double y, double z);
  void ClearFrustumCorners();
  ///@}

  ///@{
  /// Select the complement instead (see above). A selection input's INVERSE key
  /// inverts once more.
  vtkSetMacro(Invert, bool);
  vtkGetMacro(Invert, bool);
  vtkBooleanMacro(Invert, bool);
  ///@}

  ///@{
  vtkSetMacro(AllowMasked, bool);
  vtkGetMacro(AllowMasked, bool);
  vtkBooleanMacro(AllowMasked, bool);
  vtkSetMacro(PreserveTopology, bool);
  vtkGetMacro(PreserveTopology, bool);
  vtkBooleanMacro(PreserveTopology, bool);
  ///@}

  /// What the last execution ignored: points outside, masked hits, ids out of
  /// range, duplicates.
  vtkGetMacro(LastOutside, vtkIdType);
  vtkGetMacro(LastMasked, vtkIdType);
  vtkGetMacro(LastOutOfRange, vtkIdType);
  vtkGetMacro(LastDuplicates, vtkIdType);
  /// Nodes the last BOX or FRUSTUM selection examined: the roots and the children
  /// of the coarse nodes that overlap the region (what the selection cost).
  vtkGetMacro(LastVisited, vtkIdType);
  /// With PreserveTopology: the trees whose part of the mask the last execution
  /// kept from the one before (their topology, mask and ghost marks, root box
  /// and the selection unchanged), and the nodes whose part it computed anew.
  /// A selected region rebuilt every step costs the trees that changed.
  vtkGetMacro(LastKeptTrees, vtkIdType);
  vtkGetMacro(LastRecomputedNodes, vtkIdType);
  /// Bounds of the cells the last execution selected on this process (xmin, xmax,
  /// ymin, ymax, zmin, zmax; min > max when none): what a camera frames to show
  /// the selected region.
  vtkGetVector6Macro(LastSelectedBounds, double);

protected:
  vtkCanopyExtractSelection();
  ~vtkCanopyExtractSelection() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int SelectionMode = LOCATIONS;
  std::vector<double> Locations;
  std::vector<vtkIdType> Ids;
  std::string ValueArrayName;
  int ValueComponent = 0;
  double ValueRange[2] = {0, 0};
  double Box[6] = {0, 0, 0, 0, 0, 0};
  double FrustumPlanes[24] = {};
  std::vector<double> FrustumCorners;
  bool Invert = false;
  bool AllowMasked = false;
  bool PreserveTopology = false;
  vtkIdType LastOutside = 0;
  vtkIdType LastMasked = 0;
  vtkIdType LastOutOfRange = 0;
  vtkIdType LastDuplicates = 0;
  vtkIdType LastVisited = 0;
  vtkIdType LastKeptTrees = 0;
  vtkIdType LastRecomputedNodes = 0;
  double LastSelectedBounds[6] = {1, -1, 1, -1, 1, -1};

private:
  vtkCanopyExtractSelection(const vtkCanopyExtractSelection&) = delete;
  void operator=(const vtkCanopyExtractSelection&) = delete;

  /// The Last* values as before any selection (what a failed execution leaves).
  void ResetLastReport();

  /// What the filter keeps between executions: the input's topology as read, the
  /// last mask (vtkCanopyExtractSelection.cxx).
  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};
