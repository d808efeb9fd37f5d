#include "vtkCanopyHyperTreeGridSeriesWriter.h"

#include "ControllerCommunicator.h"
#include "HtgSeriesWriter.h"

#include <vtkDataObject.h>
#include <vtkErrorCode.h>
#include <vtkHyperTreeGrid.h>
#include <vtkInformation.h>
#include <vtkMultiProcessController.h>
#include <vtkObjectFactory.h>

#include <memory>

struct vtkCanopyHyperTreeGridSeriesWriter::Internals
{
  std::unique_ptr<canopy::io::HtgSeriesWriter> Writer;
  std::string FileName; // the series Writer writes
};

vtkStandardNewMacro(vtkCanopyHyperTreeGridSeriesWriter);
vtkCxxSetObjectMacro(vtkCanopyHyperTreeGridSeriesWriter, Controller, vtkMultiProcessController);

vtkCanopyHyperTreeGridSeriesWriter::vtkCanopyHyperTreeGridSeriesWriter() : Internal(new Internals)
{
}

vtkCanopyHyperTreeGridSeriesWriter::~vtkCanopyHyperTreeGridSeriesWriter()
{
  this->SetController(nullptr);
  delete this->Internal;
}

void vtkCanopyHyperTreeGridSeriesWriter::AddCellArray(const char* name)
{
  if (name != nullptr)
  {
    this->CellArrays.emplace_back(name);
    this->Modified();
  }
}

void vtkCanopyHyperTreeGridSeriesWriter::ClearCellArrays()
{
  if (!this->CellArrays.empty())
  {
    this->CellArrays.clear();
    this->Modified();
  }
}

vtkIdType vtkCanopyHyperTreeGridSeriesWriter::GetNumberOfSteps() const
{
  return this->Internal->Writer ? static_cast<vtkIdType>(this->Internal->Writer->numberOfSteps())
                                : 0;
}

int vtkCanopyHyperTreeGridSeriesWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkHyperTreeGrid");
  return 1;
}

void vtkCanopyHyperTreeGridSeriesWriter::WriteData()
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
  if (!this->Internal->Writer || this->Internal->FileName != this->FileName)
  {
    this->Internal->Writer = std::make_unique<canopy::io::HtgSeriesWriter>(
        canopy::io::communicatorOf(this->Controller), this->FileName, this->CellArrays);
    this->Internal->FileName = this->FileName;
  }
  double time = this->TimeValue;
  if (htg != nullptr && htg->GetInformation()->Has(vtkDataObject::DATA_TIME_STEP()))
  {
    time = htg->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP());
  }
  const vtkIdType step = this->TimeStep >= 0 ? this->TimeStep : this->GetNumberOfSteps();
  try
  {
    this->Internal->Writer->writeStep(htg, step, time);
  }
  catch (const canopy::io::WriteError& error)
  {
    this->LastError = error.what();
    this->SetErrorCode(vtkErrorCode::UserError);
    vtkErrorMacro(<< this->LastError);
  }
}

void vtkCanopyHyperTreeGridSeriesWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n"
     << indent << "CellArrays: " << this->CellArrays.size() << "\n"
     << indent << "TimeStep: " << this->TimeStep << "\n"
     << indent << "TimeValue: " << this->TimeValue << "\n"
     << indent << "Controller: " << this->Controller << "\n"
     << indent << "NumberOfSteps: " << this->GetNumberOfSteps() << "\n"
     << indent << "LastError: " << this->LastError << "\n";
}
