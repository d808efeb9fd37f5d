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
//
// And VTK's XML writers never see a write that fails when the file is closed:
// what is still in the stream's buffer (all of a small file) is written by the
// stream's destructor, whose failure nobody checks, and a truncated or empty
// file is left as if written. So each file is read back at its end
// (finishedXmlFile) and a truncated one is an error (insitu.writer_faults.*).
#pragma once

#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <string>

namespace canopy::io
{

/// Why the VTK XML file `fileName` is not whole ("" if it is): it must end with
/// the closing tag </VTKFile> (whitespace after it allowed).
std::string unfinishedXmlFile(const std::string& fileName);

/// After `writer` wrote its file (borrowed for the call): removes the file if it
/// is not whole and says why ("" if it is whole, or went to a string).
std::string removeUnfinishedXmlFile(vtkXMLWriterBase* writer);

class FailSafeXmlPolyDataPieceWriter : public vtkXMLPolyDataWriter
{
public:
  static FailSafeXmlPolyDataPieceWriter* New();
  vtkTypeMacro(FailSafeXmlPolyDataPieceWriter, vtkXMLPolyDataWriter);

protected:
  FailSafeXmlPolyDataPieceWriter() = default;
  ~FailSafeXmlPolyDataPieceWriter() override = default;

  int WriteInternal() override;

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

  int WriteInternal() override;

  void AllocatePositionArrays() override;
  void DeletePositionArrays() override;

private:
  bool PositionArraysAllocated = false;
};

} // namespace canopy::io
