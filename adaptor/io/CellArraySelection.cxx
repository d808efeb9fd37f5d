#include "CellArraySelection.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>

#include <algorithm>

namespace canopy::io
{

std::vector<vtkDataArray*> selectCellArrays(vtkHyperTreeGrid* htg,
                                            const std::vector<std::string>& names,
                                            std::vector<std::string>& problems)
{
  std::vector<vtkDataArray*> selected;
  if (htg == nullptr)
  {
    return selected;
  }
  vtkCellData* cells = htg->GetCellData();
  for (const std::string& name : names)
  {
    if (cells->GetAbstractArray(name.c_str()) == nullptr)
    {
      problems.push_back("the grid has no cell array '" + name + "'");
    }
    else if (cells->GetArray(name.c_str()) == nullptr)
    {
      problems.push_back("cell array '" + name + "' is not numeric");
    }
  }
  for (int a = 0; a < cells->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = cells->GetArray(a);
    if (array == nullptr || array->GetName() == nullptr || array->GetDataType() == VTK_BIT)
    {
      continue;
    }
    if (names.empty() || std::find(names.begin(), names.end(), array->GetName()) != names.end())
    {
      selected.push_back(array);
    }
  }
  return selected;
}

} // namespace canopy::io
