#include <canopy/io/vtkCanopyXMLPUnstructuredGridWriter.h>

#include "FailSafeXmlPieceWriters.h"

#include <vtkErrorCode.h>
#include <vtkInformation.h>
#include <vtkMultiProcessController.h>
#include <vtkObjectFactory.h>
#include <vtkStreamingDemandDrivenPipeline.h>

vtkStandardNewMacro(vtkCanopyXMLPUnstructuredGridWriter);

void vtkCanopyXMLPUnstructuredGridWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "PieceWriter: canopy::io::FailSafeXmlUnstructuredGridPieceWriter\n";
}

vtkXMLUnstructuredDataWriter* vtkCanopyXMLPUnstructuredGridWriter::CreateUnstructuredPieceWriter()
{
  // The caller (vtkXMLPUnstructuredDataWriter::CreatePieceWriter) owns the result.
  auto* piece = canopy::io::FailSafeXmlUnstructuredGridPieceWriter::New();
  piece->SetInputConnection(this->GetInputConnection(0, 0));
  return piece;
}

vtkTypeBool vtkCanopyXMLPUnstructuredGridWriter::ProcessRequest(vtkInformation* request,
                                                                vtkInformationVector** inputVector,
                                                                vtkInformationVector* outputVector)
{
  const vtkTypeBool done = this->Superclass::ProcessRequest(request, inputVector, outputVector);
  // The summary: written on rank 0 with the last piece (vtkXMLPDataObjectWriter).
  const bool wroteSummary = done && request->Has(vtkDemandDrivenPipeline::REQUEST_DATA()) &&
                            !request->Has(vtkStreamingDemandDrivenPipeline::CONTINUE_EXECUTING()) &&
                            this->WriteSummaryFile &&
                            (!this->Controller || this->Controller->GetLocalProcessId() == 0);
  const std::string problem = wroteSummary ? canopy::io::removeUnfinishedXmlFile(this) : "";
  if (!problem.empty())
  {
    this->SetErrorCode(vtkErrorCode::OutOfDiskSpaceError);
    vtkErrorMacro(<< problem);
    return 0;
  }
  return done;
}
