#include "FailSafeXmlPieceWriters.h"

#include <vtkObjectFactory.h>

namespace canopy::io
{

vtkStandardNewMacro(FailSafeXmlPolyDataPieceWriter);

void FailSafeXmlPolyDataPieceWriter::AllocatePositionArrays()
{
  this->Superclass::AllocatePositionArrays();
  this->PositionArraysAllocated = true;
}

void FailSafeXmlPolyDataPieceWriter::DeletePositionArrays()
{
  if (this->PositionArraysAllocated)
  {
    this->Superclass::DeletePositionArrays();
    this->PositionArraysAllocated = false; // VTK may ask twice (failure, then footer)
  }
}

vtkStandardNewMacro(FailSafeXmlUnstructuredGridPieceWriter);

void FailSafeXmlUnstructuredGridPieceWriter::AllocatePositionArrays()
{
  this->Superclass::AllocatePositionArrays();
  this->PositionArraysAllocated = true;
}

void FailSafeXmlUnstructuredGridPieceWriter::DeletePositionArrays()
{
  if (this->PositionArraysAllocated)
  {
    this->Superclass::DeletePositionArrays();
    this->PositionArraysAllocated = false;
  }
}

} // namespace canopy::io
