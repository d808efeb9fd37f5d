/**
 * @class vtkCanopyHyperTreeGridSeriesWriter
 * @brief Writes a vtkHyperTreeGrid time series that ParaView 5.11 opens:
 * per step one .htg piece per MPI rank and a .vtm listing them, and a .pvd of
 * every step written so far.
 *
 * FileName is the .pvd; step TimeStep goes to <name>_<step>.vtm and
 * <name>_<step>/<name>_<step>_<rank>.htg next to it (<step>: 6 digits; -1:
 * the number of steps written before). Vector fields are kept (VTK 9.2's own
 * .htg writer loses them, see canopy/io/HtgFileWriter.h). A failed Write()
 * returns 0 on every rank with the same LastError; the step is then not in
 * the series. See canopy::io::HtgSeriesWriter for the C++ API.
 */
#pragma once

#include "CanopyIOModule.h"

#include <vtkWriter.h>

#include <string>
#include <vector>

class vtkMultiProcessController;

class CANOPYIO_EXPORT vtkCanopyHyperTreeGridSeriesWriter : public vtkWriter
{
public:
  static vtkCanopyHyperTreeGridSeriesWriter* New();
  vtkTypeMacro(vtkCanopyHyperTreeGridSeriesWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The series' .pvd file. Changing it starts a new series at the next Write().
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

  ///@{
  /// Cell arrays to write; none listed: every numeric cell array.
  void AddCellArray(const char* name);
  void ClearCellArrays();
  ///@}

  ///@{
  /// The step's number (names its files) and its time when the input carries none.
  vtkSetMacro(TimeStep, vtkIdType);
  vtkGetMacro(TimeStep, vtkIdType);
  vtkSetMacro(TimeValue, double);
  vtkGetMacro(TimeValue, double);
  ///@}

  ///@{
  /// The ranks that write together (unset: the global controller).
  virtual void SetController(vtkMultiProcessController*);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  ///@}

  /// Why the last Write() failed, the same on every rank ("" after a success).
  const char* GetLastError() const { return this->LastError.c_str(); }
  /// Steps in the series so far.
  vtkIdType GetNumberOfSteps() const;

protected:
  vtkCanopyHyperTreeGridSeriesWriter();
  ~vtkCanopyHyperTreeGridSeriesWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  void WriteData() override;

  std::string FileName;
  std::vector<std::string> CellArrays;
  vtkIdType TimeStep = -1;
  double TimeValue = 0.0;
  vtkMultiProcessController* Controller = nullptr;
  std::string LastError;

private:
  vtkCanopyHyperTreeGridSeriesWriter(const vtkCanopyHyperTreeGridSeriesWriter&) = delete;
  void operator=(const vtkCanopyHyperTreeGridSeriesWriter&) = delete;

  struct Internals;
  Internals* Internal;
};
