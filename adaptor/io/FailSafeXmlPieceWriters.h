// VTK 9.2's XML piece writers, safe when a write fails (.vtp and .vtu pieces of
// the .pvtp/.pvtu extracts).
//
// When a write fails mid-piece (EIO, a full disk), vtkXMLUnstructuredDataWriter::
// WriteAPiece calls DeletePositionArrays() whatever the data mode; in inline and
// binary modes those arrays were never allocated, so it delete[]s uninitialised
// pointers and the simulation dies (munmap_chunk(): invalid pointer). These
// subclasses free the arrays only when AllocatePositionArrays() made them, so a
// failed piece is an error the pipeline reports, not a crash. Checked by
// insitu.fault.write_errors_mid_piece (EIO in the middle of the surface and
// selection pieces).
#pragma once

#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

namespace canopy::io
{

class FailSafeXmlPolyDataPieceWriter : public vtkXMLPolyDataWriter
{
public:
  static FailSafeXmlPolyDataPieceWriter* New();
  vtkTypeMacro(FailSafeXmlPolyDataPieceWriter, vtkXMLPolyDataWriter);

protected:
  FailSafeXmlPolyDataPieceWriter() = default;
  ~FailSafeXmlPolyDataPieceWriter() override = default;

  void AllocatePositionArrays() override;
  void DeletePositionArrays() override;

private:
  bool PositionArraysAllocated = false;
};

class FailSafeXmlUnstructuredGridPieceWriter : public vtkXMLUnstructuredGridWriter
{
public:
  static FailSafeXmlUnstructuredGridPieceWriter* New();
  vtkTypeMacro(FailSafeXmlUnstructuredGridPieceWriter, vtkXMLUnstructuredGridWriter);

protected:
  FailSafeXmlUnstructuredGridPieceWriter() = default;
  ~FailSafeXmlUnstructuredGridPieceWriter() override = default;

  void AllocatePositionArrays() override;
  void DeletePositionArrays() override;

private:
  bool PositionArraysAllocated = false;
};

} // namespace canopy::io
