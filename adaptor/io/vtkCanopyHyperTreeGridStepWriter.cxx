#include <canopy/io/vtkCanopyHyperTreeGridStepWriter.h>

#include "ControllerCommunicator.h"
#include <canopy/io/WriteError.h>

#include <vtkDataObject.h>
#include <vtkErrorCode.h>
#include <vtkHyperTreeGrid.h>
#include <vtkInformation.h>
#include <vtkMultiProcessController.h>
#include <vtkObjectFactory.h>

vtkCxxSetObjectMacro(vtkCanopyHyperTreeGridStepWriter, Controller, vtkMultiProcessController);

vtkCanopyHyperTreeGridStepWriter::vtkCanopyHyperTreeGridStepWriter() = default;

vtkCanopyHyperTreeGridStepWriter::~vtkCanopyHyperTreeGridStepWriter()
{
  this->SetController(nullptr);
}

void vtkCanopyHyperTreeGridStepWriter::AddCellArray(const char* name)
{
  if (name != nullptr)
  {
    this->CellArrays.emplace_back(name);
    this->Modified();
  }
}

void vtkCanopyHyperTreeGridStepWriter::ClearCellArrays()
{
  if (!this->CellArrays.empty())
  {
    this->CellArrays.clear();
    this->Modified();
  }
}

int vtkCanopyHyperTreeGridStepWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkHyperTreeGrid");
  return 1;
}

void vtkCanopyHyperTreeGridStepWriter::WriteData()
{
  this->LastError.clear();
  auto* htg = vtkHyperTreeGrid::SafeDownCast(this->GetInputDataObject(0, 0));
  if (this->FileName.empty())
  {
    this->LastError = "no FileName";
    this->SetErrorCode(vtkErrorCode::NoFileNameError);
    vtkErrorMacro(<< this->LastError);
    return;
  }
  // One file per writer and FileName: the subclass knows whether this run
  // already started it.
  if (!this->Opened || this->OpenedFileName != this->FileName)
  {
    this->OpenFile(canopy::io::communicatorOf(this->Controller));
    this->OpenedFileName = this->FileName;
    this->Opened = true;
  }
  double time = this->TimeValue;
  if (htg != nullptr && htg->GetInformation()->Has(vtkDataObject::DATA_TIME_STEP()))
  {
    time = htg->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP());
  }
  try
  {
    this->WriteStep(htg, time);
  }
  catch (const canopy::io::WriteError& error)
  {
    this->LastError = error.what();
    this->SetErrorCode(vtkErrorCode::UserError);
    vtkErrorMacro(<< this->LastError);
  }
}

void vtkCanopyHyperTreeGridStepWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n"
     << indent << "CellArrays: " << this->CellArrays.size() << "\n"
     << indent << "TimeValue: " << this->TimeValue << "\n"
     << indent << "TimeStep: " << this->TimeStep << "\n"
     << indent << "Controller: " << this->Controller << "\n"
     << indent << "NumberOfSteps: " << this->GetNumberOfSteps() << "\n"
     << indent << "LastError: " << this->LastError << "\n";
}
