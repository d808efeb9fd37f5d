#include "vtkCanopyXMLPUnstructuredGridWriter.h"

#include "FailSafeXmlPieceWriters.h"

#include <vtkObjectFactory.h>

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
