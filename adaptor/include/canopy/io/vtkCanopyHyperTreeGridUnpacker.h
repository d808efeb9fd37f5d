/**
 * @class vtkCanopyHyperTreeGridUnpacker
 * @brief The hypertree grids that vtkCanopyHyperTreeGridPacker packed: a
 * multiblock dataset with one vtkHyperTreeGrid block per packed rank piece.
 *
 * For the receiving side of Catalyst Live (docs/insitu.md, "Catalyst Live"):
 * in ParaView, load the Canopy plugin and apply "Canopy Unpack Grid" to the
 * extract of the simulation's grid (Canopy sends it packed) or of its
 * "<channel> (packed)" source. Bytes that are not a sequence of Canopy pieces
 * are refused with an error saying where; a hypertree grid input is passed on
 * as the one block (the same pipeline then works without Live).
 */
#pragma once

#include "CanopyIOModule.h"

#include <vtkMultiBlockDataSetAlgorithm.h>

class CANOPYIO_EXPORT vtkCanopyHyperTreeGridUnpacker : public vtkMultiBlockDataSetAlgorithm
{
public:
  static vtkCanopyHyperTreeGridUnpacker* New();
  vtkTypeMacro(vtkCanopyHyperTreeGridUnpacker, vtkMultiBlockDataSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Pieces unpacked at the last execution.
  unsigned int GetNumberOfPieces() const { return this->NumberOfPieces; }

protected:
  vtkCanopyHyperTreeGridUnpacker() = default;
  ~vtkCanopyHyperTreeGridUnpacker() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputs,
                  vtkInformationVector* outputs) override;

private:
  vtkCanopyHyperTreeGridUnpacker(const vtkCanopyHyperTreeGridUnpacker&) = delete;
  void operator=(const vtkCanopyHyperTreeGridUnpacker&) = delete;

  unsigned int NumberOfPieces = 0;
};
