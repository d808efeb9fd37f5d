/**
 * @class vtkCanopyExtractSelection
 * @brief Extracts cells of a vtkHyperTreeGrid by location, by global id or by
 * value range, as a masked hypertree grid or as an unstructured grid.
 *
 * Input 0: the vtkHyperTreeGrid. Input 1 (optional): a vtkSelection whose first
 * node is LOCATIONS (3-component points), GLOBALIDS or INDICES (cell ids) or
 * THRESHOLDS (one [low, high] pair; the selection list's name is the field, the
 * COMPONENT_NUMBER key the component, -1 for the magnitude). Without input 1 the
 * convenience properties below say what to select.
 *
 * Location rule: cells are half-open [lo, hi) along each axis, the grid's last
 * cell along an axis also owning the upper boundary; a point on a shared face,
 * edge or corner belongs to the cell on its upper side; points outside the
 * domain select nothing. Ids: each global index selects its node, coarse ones
 * included; out-of-range ids and duplicates are ignored and counted. Values:
 * visible leaves with a value within [low, high] (inclusive, never NaN).
 * Masked cells are selectable only with AllowMasked on.
 *
 * PreserveTopology on: a vtkHyperTreeGrid sharing the input's trees and arrays
 * with a new mask leaving visible the selected cells, their ancestors (needed to
 * reach them) and the subtrees of selected coarse cells. Off: a
 * vtkUnstructuredGrid of VTK_QUAD (2D) or VTK_HEXAHEDRON (3D) cells with merged
 * points, the input's cell fields, "OriginalCellId" and "Level".
 */
#pragma once

#include "CanopyFiltersModule.h"

#include <vtkDataObjectAlgorithm.h>

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
    VALUE_RANGE = 2
  };

  ///@{
  /// What the convenience properties select (ignored when input 1 is connected).
  vtkSetClampMacro(SelectionMode, int, LOCATIONS, VALUE_RANGE);
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

protected:
  vtkCanopyExtractSelection();
  ~vtkCanopyExtractSelection() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkCanopyExtractSelection(const vtkCanopyExtractSelection&) = delete;
  void operator=(const vtkCanopyExtractSelection&) = delete;

  int SelectionMode = LOCATIONS;
  std::vector<double> Locations;
  std::vector<vtkIdType> Ids;
  std::string ValueArrayName;
  int ValueComponent = 0;
  double ValueRange[2] = {0, 0};
  bool AllowMasked = false;
  bool PreserveTopology = false;
  vtkIdType LastOutside = 0;
  vtkIdType LastMasked = 0;
  vtkIdType LastOutOfRange = 0;
  vtkIdType LastDuplicates = 0;
};
