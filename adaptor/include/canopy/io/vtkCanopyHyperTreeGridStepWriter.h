/**
 * @class vtkCanopyHyperTreeGridStepWriter
 * @brief What Canopy's hypertree-grid writers share: one step per Write(),
 * every MPI rank its own piece, a failure reported the same on every rank.
 *
 * Subclasses (vtkCanopyHyperTreeGridHDFWriter, vtkCanopyHyperTreeGridSeriesWriter)
 * open their file or series once per FileName and write each step. The step's
 * time is the input's DATA_TIME_STEP, else TimeValue. A failed Write() sets
 * LastError on every rank to the same text (every rank's problem) and the
 * error code to vtkErrorCode::UserError; earlier steps stay readable.
 */
#pragma once

#include "CanopyIOModule.h"

#include <vtkWriter.h>

#include <mpi.h>

#include <string>
#include <vector>

class vtkHyperTreeGrid;
class vtkMultiProcessController;

class CANOPYIO_EXPORT vtkCanopyHyperTreeGridStepWriter : public vtkWriter
{
public:
  vtkTypeMacro(vtkCanopyHyperTreeGridStepWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file (or series index) written. Changing it starts anew at the next Write().
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

  ///@{
  /// Cell arrays to write; none listed: every numeric cell array (fixed by the first step).
  void AddCellArray(const char* name);
  void ClearCellArrays();
  ///@}

  ///@{
  /// The step's time when the input carries none; the simulation's step number
  /// (-1: none).
  vtkSetMacro(TimeValue, double);
  vtkGetMacro(TimeValue, double);
  vtkSetMacro(TimeStep, vtkIdType);
  vtkGetMacro(TimeStep, vtkIdType);
  ///@}

  ///@{
  /// The ranks that write together (unset: the global controller, which is Catalyst's).
  virtual void SetController(vtkMultiProcessController*);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  ///@}

  /// Why the last Write() failed, the same on every rank ("" after a success).
  const char* GetLastError() const { return this->LastError.c_str(); }
  /// Steps written after the last successful Write().
  virtual vtkIdType GetNumberOfSteps() const = 0;

protected:
  vtkCanopyHyperTreeGridStepWriter();
  ~vtkCanopyHyperTreeGridStepWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  void WriteData() final;

  /// Starts writing FileName on `communicator` (called at the first Write() and
  /// whenever FileName changed since).
  virtual void OpenFile(MPI_Comm communicator) = 0;
  /// Writes one step (collective); throws canopy::io::WriteError, the same on every rank.
  virtual void WriteStep(vtkHyperTreeGrid* htg, double time) = 0;

  std::string FileName;
  std::vector<std::string> CellArrays;
  double TimeValue = 0.0;
  vtkIdType TimeStep = -1;
  vtkMultiProcessController* Controller = nullptr;
  std::string LastError;

private:
  vtkCanopyHyperTreeGridStepWriter(const vtkCanopyHyperTreeGridStepWriter&) = delete;
  void operator=(const vtkCanopyHyperTreeGridStepWriter&) = delete;

  std::string OpenedFileName; ///< the FileName OpenFile() was last called for
  bool Opened = false;
};
