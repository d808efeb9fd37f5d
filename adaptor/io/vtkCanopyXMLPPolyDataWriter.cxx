#include "vtkCanopyXMLPPolyDataWriter.h"

#include "FailSafeXmlPieceWriters.h"

#include <vtkObjectFactory.h>

vtkStandardNewMacro(vtkCanopyXMLPPolyDataWriter);

void vtkCanopyXMLPPolyDataWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "PieceWriter: canopy::io::FailSafeXmlPolyDataPieceWriter\n";
}

vtkXMLUnstructuredDataWriter* vtkCanopyXMLPPolyDataWriter::CreateUnstructuredPieceWriter()
{
  // The caller (vtkXMLPUnstructuredDataWriter::CreatePieceWriter) owns the result.
  auto* piece = canopy::io::FailSafeXmlPolyDataPieceWriter::New();
  piece->SetInputConnection(this->GetInputConnection(0, 0));
  return piece;
}
