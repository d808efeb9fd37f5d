#include "HtgFileWriter.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkXMLHyperTreeGridWriter.h>

#include <vector>

namespace canopy::tools
{

std::string componentArrayName(const std::string& name, int component, int components)
{
  static const char* xyz[] = {"X", "Y", "Z"};
  if (components <= 3)
  {
    return name + "_" + xyz[component];
  }
  return name + "_" + std::to_string(component);
}

std::string writeHtgFile(vtkHyperTreeGrid* htg, const std::string& fileName)
{
  if (htg == nullptr)
  {
    return "no grid to write";
  }
  vtkNew<vtkHyperTreeGrid> copy;
  copy->ShallowCopy(htg);
  vtkCellData* cells = copy->GetCellData();
  std::vector<vtkSmartPointer<vtkDataArray>> vectors;
  for (int a = 0; a < cells->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = cells->GetArray(a);
    if (array && array->GetNumberOfComponents() > 1)
    {
      vectors.emplace_back(array);
    }
  }
  for (const auto& vector : vectors)
  {
    const std::string name = vector->GetName() ? vector->GetName() : "array";
    const int components = vector->GetNumberOfComponents();
    const vtkIdType tuples = vector->GetNumberOfTuples();
    cells->RemoveArray(name.c_str());
    for (int c = 0; c < components; ++c)
    {
      vtkSmartPointer<vtkDataArray> scalar =
          vtkSmartPointer<vtkDataArray>::Take(vtkDataArray::CreateDataArray(vector->GetDataType()));
      scalar->SetName(componentArrayName(name, c, components).c_str());
      scalar->SetNumberOfComponents(1);
      scalar->SetNumberOfTuples(tuples);
      scalar->CopyComponent(0, vector, c);
      cells->AddArray(scalar);
    }
  }
  vtkNew<vtkXMLHyperTreeGridWriter> writer;
  writer->SetInputData(copy);
  writer->SetFileName(fileName.c_str());
  writer->SetDataModeToBinary();
  if (writer->Write() != 1)
  {
    return "vtkXMLHyperTreeGridWriter could not write " + fileName;
  }
  return {};
}

} // namespace canopy::tools
