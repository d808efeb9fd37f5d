#include "FailSafeXmlPieceWriters.h"

#include <vtkErrorCode.h>
#include <vtkObjectFactory.h>

#include <cctype>
#include <cstdio>
#include <fstream>

namespace canopy::io
{
std::string unfinishedXmlFile(const std::string& fileName)
{
  std::ifstream in(fileName, std::ios::binary | std::ios::ate);
  if (!in)
  {
    return "cannot read the file back";
  }
  const std::streamoff size = in.tellg();
  const std::string closing = "</VTKFile>";
  const std::streamoff tail = std::min<std::streamoff>(size, 64);
  std::string end(static_cast<std::size_t>(tail), '\0');
  in.seekg(size - tail);
  in.read(end.data(), tail);
  while (!end.empty() && std::isspace(static_cast<unsigned char>(end.back())))
  {
    end.pop_back();
  }
  if (!in || end.size() < closing.size() ||
      end.compare(end.size() - closing.size(), closing.size(), closing) != 0)
  {
    return "not written whole (" + std::to_string(size) + " bytes, no closing </VTKFile>)";
  }
  return {};
}

std::string removeUnfinishedXmlFile(vtkXMLWriterBase* writer)
{
  const char* fileName = writer->GetFileName();
  if (writer->GetWriteToOutputString() || fileName == nullptr)
  {
    return {};
  }
  const std::string problem = unfinishedXmlFile(fileName);
  if (problem.empty())
  {
    return {};
  }
  std::remove(fileName);
  return std::string(fileName) + ": " + problem + "; the file is removed";
}

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

int FailSafeXmlPolyDataPieceWriter::WriteInternal()
{
  if (!this->Superclass::WriteInternal())
  {
    return 0;
  }
  const std::string problem = removeUnfinishedXmlFile(this);
  if (!problem.empty())
  {
    this->SetErrorCode(vtkErrorCode::OutOfDiskSpaceError);
    vtkErrorMacro(<< problem);
    return 0;
  }
  return 1;
}

vtkStandardNewMacro(FailSafeXmlUnstructuredGridPieceWriter);

int FailSafeXmlUnstructuredGridPieceWriter::WriteInternal()
{
  if (!this->Superclass::WriteInternal())
  {
    return 0;
  }
  const std::string problem = removeUnfinishedXmlFile(this);
  if (!problem.empty())
  {
    this->SetErrorCode(vtkErrorCode::OutOfDiskSpaceError);
    vtkErrorMacro(<< problem);
    return 0;
  }
  return 1;
}

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
