#include "vtkCanopyHyperTreeGridHDFWriter.h"

#include "ControllerCommunicator.h"
#include "VtkHdfWriter.h"

#include <vtkDataObject.h>
#include <vtkErrorCode.h>
#include <vtkHyperTreeGrid.h>
#include <vtkInformation.h>
#include <vtkMultiProcessController.h>
#include <vtkObjectFactory.h>

#include <memory>

struct vtkCanopyHyperTreeGridHDFWriter::Internals
{
  std::unique_ptr<canopy::io::VtkHdfWriter> Writer;
  std::string FileName; // the file Writer writes
};

vtkStandardNewMacro(vtkCanopyHyperTreeGridHDFWriter);
vtkCxxSetObjectMacro(vtkCanopyHyperTreeGridHDFWriter, Controller, vtkMultiProcessController);

vtkCanopyHyperTreeGridHDFWriter::vtkCanopyHyperTreeGridHDFWriter() : Internal(new Internals) {}

vtkCanopyHyperTreeGridHDFWriter::~vtkCanopyHyperTreeGridHDFWriter()
{
  this->SetController(nullptr);
  delete this->Internal;
}

void vtkCanopyHyperTreeGridHDFWriter::AddCellArray(const char* name)
{
  if (name != nullptr)
  {
    this->CellArrays.emplace_back(name);
    this->Modified();
  }
}

void vtkCanopyHyperTreeGridHDFWriter::ClearCellArrays()
{
  if (!this->CellArrays.empty())
  {
    this->CellArrays.clear();
    this->Modified();
  }
}

vtkIdType vtkCanopyHyperTreeGridHDFWriter::GetNumberOfSteps() const
{
  return this->Internal->Writer ? this->Internal->Writer->numberOfSteps() : 0;
}

int vtkCanopyHyperTreeGridHDFWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkHyperTreeGrid");
  return 1;
}

void vtkCanopyHyperTreeGridHDFWriter::WriteData()
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
  // One writer per file: it knows whether this run already started the file.
  if (!this->Internal->Writer || this->Internal->FileName != this->FileName)
  {
    canopy::io::VtkHdfWriterOptions options;
    options.arrays = this->CellArrays;
    options.append = this->Append;
    options.checkFreeSpace = this->CheckFreeSpace;
    this->Internal->Writer = std::make_unique<canopy::io::VtkHdfWriter>(
        canopy::io::communicatorOf(this->Controller), this->FileName, options);
    this->Internal->FileName = this->FileName;
  }
  double time = this->TimeValue;
  if (htg != nullptr && htg->GetInformation()->Has(vtkDataObject::DATA_TIME_STEP()))
  {
    time = htg->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP());
  }
  try
  {
    this->Internal->Writer->writeStep(htg, this->TimeStep, time);
  }
  catch (const canopy::io::WriteError& error)
  {
    this->LastError = error.what();
    this->SetErrorCode(vtkErrorCode::UserError);
    vtkErrorMacro(<< this->LastError);
  }
}

void vtkCanopyHyperTreeGridHDFWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n"
     << indent << "CellArrays: " << this->CellArrays.size() << "\n"
     << indent << "Append: " << this->Append << "\n"
     << indent << "CheckFreeSpace: " << this->CheckFreeSpace << "\n"
     << indent << "TimeValue: " << this->TimeValue << "\n"
     << indent << "TimeStep: " << this->TimeStep << "\n"
     << indent << "Controller: " << this->Controller << "\n"
     << indent << "NumberOfSteps: " << this->GetNumberOfSteps() << "\n"
     << indent << "LastError: " << this->LastError << "\n";
}
