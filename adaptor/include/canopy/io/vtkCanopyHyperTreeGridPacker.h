/**
 * @class vtkCanopyHyperTreeGridPacker
 * @brief A hypertree grid as bytes that any VTK 9.2 channel can move: every
 * rank's piece in the .htg format, gathered on rank 0 into one byte array.
 *
 * VTK 9.2 cannot send a vtkHyperTreeGrid through a socket or MPI
 * (vtkCommunicator::Send: "Cannot send vtkHyperTreeGrid"), so Catalyst Live
 * cannot deliver one. This filter's output can be sent: on rank 0 a vtkPolyData
 * of one point whose field array "CanopyPackedGrid" holds the bytes of every
 * rank's piece; on other ranks an empty vtkPolyData (which ParaView's merge of
 * the ranks' pieces skips). vtkCanopyHyperTreeGridUnpacker turns the bytes back
 * into hypertree grids.
 *
 * Each piece is framed as "CNPY" + its length (8 bytes, little endian) + the
 * bytes of the .htg file Canopy's writer would write for it (canopy::io::
 * writeHtgText: VTK 9.2's own writer corrupts vector arrays). A piece that
 * cannot be written is left out with an error. Collective over Controller's
 * ranks.
 */
#pragma once

#include "CanopyIOModule.h"

#include <vtkPolyDataAlgorithm.h>

class vtkMultiProcessController;

class CANOPYIO_EXPORT vtkCanopyHyperTreeGridPacker : public vtkPolyDataAlgorithm
{
public:
  static vtkCanopyHyperTreeGridPacker* New();
  vtkTypeMacro(vtkCanopyHyperTreeGridPacker, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The name of the output's byte array (field data).
  static const char* ArrayName() { return "CanopyPackedGrid"; }

  ///@{
  /// The ranks that pack together (unset: the global controller, Catalyst's).
  virtual void SetController(vtkMultiProcessController*);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  ///@}

  /// Bytes of this rank's framed piece at the last execution.
  vtkIdType GetLocalBytes() const { return this->LocalBytes; }
  /// Bytes of all pieces at the last execution (rank 0; 0 elsewhere).
  vtkIdType GetTotalBytes() const { return this->TotalBytes; }

protected:
  vtkCanopyHyperTreeGridPacker();
  ~vtkCanopyHyperTreeGridPacker() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputs,
                  vtkInformationVector* outputs) override;

  vtkMultiProcessController* Controller = nullptr;

private:
  vtkCanopyHyperTreeGridPacker(const vtkCanopyHyperTreeGridPacker&) = delete;
  void operator=(const vtkCanopyHyperTreeGridPacker&) = delete;

  vtkIdType LocalBytes = 0;
  vtkIdType TotalBytes = 0;
};
