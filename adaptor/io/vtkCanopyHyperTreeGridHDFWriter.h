/**
 * @class vtkCanopyHyperTreeGridHDFWriter
 * @brief Appends a vtkHyperTreeGrid to a VTKHDF file, one step per Write(),
 * every MPI rank its own piece.
 *
 * The file follows VTK's VTKHDF HyperTreeGrid layout (version 2.4) with a
 * temporal "Steps" group; VTK 9.5+ and ParaView 6 open it with vtkHDFReader.
 * Ranks write through HDF5's MPI-IO on the communicator of Controller (unset:
 * vtkMultiProcessController::GetGlobalController(), which is Catalyst's). The
 * first Write() of a writer replaces the file unless Append is on; each later
 * Write() adds a step. The step's time is the input's DATA_TIME_STEP, else
 * TimeValue. A failed Write() returns 0 on every rank with the same
 * LastError (every rank's problem); the file then keeps its earlier steps.
 * See canopy::io::VtkHdfWriter for the C++ API without a pipeline.
 */
#pragma once

#include "CanopyIOModule.h"

#include <vtkWriter.h>

#include <string>
#include <vector>

class vtkMultiProcessController;

class CANOPYIO_EXPORT vtkCanopyHyperTreeGridHDFWriter : public vtkWriter
{
public:
  static vtkCanopyHyperTreeGridHDFWriter* New();
  vtkTypeMacro(vtkCanopyHyperTreeGridHDFWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The .vtkhdf file. Changing it starts a new file at the next Write().
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

  ///@{
  /// Cell arrays to write; none listed: every numeric cell array (fixed by the first step).
  void AddCellArray(const char* name);
  void ClearCellArrays();
  ///@}

  ///@{
  /// Continue an existing file rather than replace it at the first Write().
  vtkSetMacro(Append, bool);
  vtkGetMacro(Append, bool);
  vtkBooleanMacro(Append, bool);
  ///@}

  ///@{
  /// Refuse a step that will not fit in the free space before touching the file
  /// (on by default; see canopy::io::VtkHdfWriterOptions::checkFreeSpace).
  vtkSetMacro(CheckFreeSpace, bool);
  vtkGetMacro(CheckFreeSpace, bool);
  vtkBooleanMacro(CheckFreeSpace, bool);
  ///@}

  ///@{
  /// The step's time when the input carries none; the simulation's step number
  /// (only for messages; -1: none).
  vtkSetMacro(TimeValue, double);
  vtkGetMacro(TimeValue, double);
  vtkSetMacro(TimeStep, vtkIdType);
  vtkGetMacro(TimeStep, vtkIdType);
  ///@}

  ///@{
  /// The ranks that write together (unset: the global controller).
  virtual void SetController(vtkMultiProcessController*);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  ///@}

  /// Why the last Write() failed, the same on every rank ("" after a success).
  const char* GetLastError() const { return this->LastError.c_str(); }
  /// Steps in the file after the last successful Write().
  vtkIdType GetNumberOfSteps() const;

protected:
  vtkCanopyHyperTreeGridHDFWriter();
  ~vtkCanopyHyperTreeGridHDFWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  void WriteData() override;

  std::string FileName;
  std::vector<std::string> CellArrays;
  bool Append = false;
  bool CheckFreeSpace = true;
  double TimeValue = 0.0;
  vtkIdType TimeStep = -1;
  vtkMultiProcessController* Controller = nullptr;
  std::string LastError;

private:
  vtkCanopyHyperTreeGridHDFWriter(const vtkCanopyHyperTreeGridHDFWriter&) = delete;
  void operator=(const vtkCanopyHyperTreeGridHDFWriter&) = delete;

  struct Internals;
  Internals* Internal;
};
