// One component of a cell field, read at a node's global index without copying
// it: double and float arrays through their own memory, any other array through
// VTK's generic accessor (a simulation's strided or indirect array reads in
// place; asking it for a pointer would detach a copy).
#pragma once

#include <vtkAOSDataArrayTemplate.h>
#include <vtkDataArray.h>

#include <limits>

namespace canopy
{

class ContourField
{
public:
  ContourField() = default;
  /// `array` is borrowed: it must outlive the reader. `component` < its components.
  ContourField(vtkDataArray* array, int component)
      : Array(array), Components(array->GetNumberOfComponents()), Component(component)
  {
    if (auto* d = vtkArrayDownCast<vtkAOSDataArrayTemplate<double>>(array))
    {
      Doubles = d->GetPointer(0);
    }
    else if (auto* f = vtkArrayDownCast<vtkAOSDataArrayTemplate<float>>(array))
    {
      Floats = f->GetPointer(0);
    }
  }

  /// Ids from `localCells` on are other ranks' leaves (ContourGhosts.h):
  /// `ghostValues` (borrowed; must outlive the reader), id - localCells.
  void setGhosts(vtkIdType localCells, const double* ghostValues)
  {
    LocalCells = localCells;
    GhostValues = ghostValues;
  }

  double operator()(vtkIdType cell) const
  {
    if (cell >= LocalCells)
    {
      return GhostValues[cell - LocalCells];
    }
    const vtkIdType at = cell * Components + Component;
    if (Doubles)
    {
      return Doubles[at];
    }
    if (Floats)
    {
      return static_cast<double>(Floats[at]);
    }
    return Array->GetComponent(cell, Component);
  }

  vtkDataArray* array() const { return Array; }

private:
  vtkDataArray* Array = nullptr;
  const double* Doubles = nullptr;
  const float* Floats = nullptr;
  vtkIdType Components = 1;
  int Component = 0;
  vtkIdType LocalCells = std::numeric_limits<vtkIdType>::max();
  const double* GhostValues = nullptr;
};

} // namespace canopy
