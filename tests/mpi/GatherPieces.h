// Every rank's output of a filter on rank 0, cell by cell: the cells' points (a
// flat piece's polygon, with the vertices on its edges) and their "Level", as
// one vtkPolyData, so that rank 0 can check the pieces against one another or
// render them as the ranks' composited image would show them.
#pragma once

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <vector>

namespace canopy::testing
{

/// Collective over the global controller: rank 0 gets every rank's cells, in
/// rank order (the others an empty polydata).
inline vtkSmartPointer<vtkPolyData> gatherPieces(vtkPolyData* mine)
{
  // Per cell: its level, its number of points, then x, y, z per point.
  std::vector<double> values;
  vtkDataArray* levels = mine->GetCellData()->GetArray("Level");
  for (vtkIdType c = 0; c < mine->GetNumberOfCells(); ++c)
  {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    mine->GetCellPoints(c, n, ids);
    values.push_back(levels ? levels->GetTuple1(c) : 0.0);
    values.push_back(static_cast<double>(n));
    for (vtkIdType k = 0; k < n; ++k)
    {
      double p[3];
      mine->GetPoint(ids[k], p);
      values.insert(values.end(), p, p + 3);
    }
  }
  vtkMultiProcessController* c = vtkMultiProcessController::GetGlobalController();
  const int ranks = c->GetNumberOfProcesses();
  const vtkIdType length = static_cast<vtkIdType>(values.size());
  std::vector<vtkIdType> lengths(static_cast<std::size_t>(ranks), 0);
  c->Gather(&length, lengths.data(), 1, 0);
  std::vector<vtkIdType> offsets(static_cast<std::size_t>(ranks), 0);
  vtkIdType total = 0;
  for (int r = 0; r < ranks; ++r)
  {
    offsets[static_cast<std::size_t>(r)] = total;
    total += lengths[static_cast<std::size_t>(r)];
  }
  std::vector<double> all(static_cast<std::size_t>(std::max<vtkIdType>(total, 1)));
  double unused = 0;
  c->GatherV(values.empty() ? &unused : values.data(), all.data(), length, lengths.data(),
             offsets.data(), 0);
  auto gathered = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> polys;
  vtkNew<vtkUnsignedCharArray> level;
  level->SetName("Level");
  for (vtkIdType i = 0; c->GetLocalProcessId() == 0 && i + 2 <= total;)
  {
    level->InsertNextValue(static_cast<unsigned char>(all[static_cast<std::size_t>(i)]));
    const auto n = static_cast<vtkIdType>(all[static_cast<std::size_t>(i + 1)]);
    i += 2;
    polys->InsertNextCell(n);
    for (vtkIdType k = 0; k < n; ++k, i += 3)
    {
      polys->InsertCellPoint(points->InsertNextPoint(all.data() + i));
    }
  }
  gathered->SetPoints(points);
  gathered->SetPolys(polys);
  gathered->GetCellData()->AddArray(level);
  return gathered;
}

} // namespace canopy::testing
