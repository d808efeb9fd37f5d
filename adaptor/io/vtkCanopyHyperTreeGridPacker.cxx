#include <canopy/io/vtkCanopyHyperTreeGridPacker.h>

#include "PackedGridFrame.h"
#include <canopy/io/HtgFileWriter.h>

#include <vtkCellArray.h>
#include <vtkFieldData.h>
#include <vtkHyperTreeGrid.h>
#include <vtkInformation.h>
#include <vtkMultiProcessController.h>
#include <vtkObjectFactory.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <cstring>
#include <string>

vtkStandardNewMacro(vtkCanopyHyperTreeGridPacker);
vtkCxxSetObjectMacro(vtkCanopyHyperTreeGridPacker, Controller, vtkMultiProcessController);

vtkCanopyHyperTreeGridPacker::vtkCanopyHyperTreeGridPacker() = default;

vtkCanopyHyperTreeGridPacker::~vtkCanopyHyperTreeGridPacker()
{
  this->SetController(nullptr);
}

int vtkCanopyHyperTreeGridPacker::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkHyperTreeGrid");
  return 1;
}

int vtkCanopyHyperTreeGridPacker::RequestData(vtkInformation*, vtkInformationVector** inputs,
                                              vtkInformationVector* outputs)
{
  auto* htg = vtkHyperTreeGrid::GetData(inputs[0], 0);
  auto* output = vtkPolyData::GetData(outputs, 0);
  output->Initialize();
  std::string framed;
  if (htg)
  {
    // Canopy's .htg writer: VTK 9.2's corrupts vector arrays, and its output
    // read back is not the same grid (PackedGridTest).
    std::string text;
    const std::string problem = canopy::io::writeHtgText(htg, text);
    if (problem.empty())
    {
      framed = canopy::io::packed::frame(text);
    }
    else
    {
      // Still gathered below with the other ranks (collective), without this piece.
      vtkErrorMacro("this rank's piece cannot be packed: " << problem);
    }
  }
  this->LocalBytes = static_cast<vtkIdType>(framed.size());
  vtkNew<vtkUnsignedCharArray> local;
  local->SetNumberOfValues(this->LocalBytes);
  if (this->LocalBytes > 0)
  {
    std::memcpy(local->GetPointer(0), framed.data(), framed.size());
  }

  auto* controller =
      this->Controller ? this->Controller : vtkMultiProcessController::GetGlobalController();
  const bool parallel = controller && controller->GetNumberOfProcesses() > 1;
  const bool root = !controller || controller->GetLocalProcessId() == 0;
  vtkNew<vtkUnsignedCharArray> all;
  if (parallel)
  {
    controller->GatherV(local, all, 0);
  }
  vtkUnsignedCharArray* bytes = parallel ? all.GetPointer() : local.GetPointer();
  this->TotalBytes = root ? bytes->GetNumberOfValues() : 0;
  if (!root)
  {
    return 1;
  }
  // One point, so that ParaView's merge of the ranks' outputs keeps this one.
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(0.0, 0.0, 0.0);
  output->SetPoints(points);
  vtkNew<vtkCellArray> vertices;
  vertices->InsertNextCell(1);
  vertices->InsertCellPoint(0);
  output->SetVerts(vertices);
  bytes->SetName(ArrayName());
  output->GetFieldData()->AddArray(bytes);
  return 1;
}

void vtkCanopyHyperTreeGridPacker::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Controller: " << this->Controller << "\n"
     << indent << "LocalBytes: " << this->LocalBytes << "\n"
     << indent << "TotalBytes: " << this->TotalBytes << "\n";
}
