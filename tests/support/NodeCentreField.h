// A cell field of a formula at every node's centre (inner, masked and absent nodes
// too), walked with VTK's own geometry cursor: fields for tests that must not share
// Canopy's geometry.
#pragma once

#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkNew.h>

#include <functional>

namespace canopy::testing
{

/// Adds the cell array `name`: f(centre) at every node of `htg`.
inline void addNodeCentreField(vtkHyperTreeGrid* htg, const char* name,
                               const std::function<double(const double*)>& f)
{
  vtkNew<vtkDoubleArray> values;
  values->SetName(name);
  values->SetNumberOfTuples(htg->GetNumberOfCells());
  values->Fill(0);
  std::function<void(vtkHyperTreeGridNonOrientedGeometryCursor*)> walk =
      [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor)
  {
    const double* origin = cursor->GetOrigin();
    const double* size = cursor->GetSize();
    const double centre[3] = {origin[0] + size[0] / 2, origin[1] + size[1] / 2,
                              origin[2] + size[2] / 2};
    values->SetValue(cursor->GetGlobalNodeIndex(), f(centre));
    for (unsigned c = 0; !cursor->IsLeaf() && c < cursor->GetNumberOfChildren(); ++c)
    {
      cursor->ToChild(c);
      walk(cursor);
      cursor->ToParent();
    }
  };
  vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
  htg->InitializeTreeIterator(it);
  vtkIdType index = 0;
  vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> cursor;
  while (it.GetNextTree(index))
  {
    htg->InitializeNonOrientedGeometryCursor(cursor, index);
    walk(cursor);
  }
  htg->GetCellData()->AddArray(values);
}

} // namespace canopy::testing
