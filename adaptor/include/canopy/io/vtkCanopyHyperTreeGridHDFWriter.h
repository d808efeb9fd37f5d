/**
 * @class vtkCanopyHyperTreeGridHDFWriter
 * @brief Appends a vtkHyperTreeGrid to a VTKHDF file, one step per Write(),
 * every MPI rank its own piece.
 *
 * The file follows VTK's VTKHDF HyperTreeGrid layout (version 2.4) with a
 * temporal "Steps" group; VTK 9.5+ and ParaView 6 open it with vtkHDFReader.
 * Each rank of the communicator of Controller (unset:
 * vtkMultiProcessController::GetGlobalController(), which is Catalyst's) adds its
 * piece; rank 0 writes the file. The first Write() of a writer replaces the file
 * unless Append is on; each later Write() adds a step (time, errors:
 * vtkCanopyHyperTreeGridStepWriter); a failed Write() leaves the file byte for
 * byte as it was before.
 * See canopy::io::VtkHdfWriter for the C++ API without a pipeline.
 */
#pragma once

#include <canopy/io/vtkCanopyHyperTreeGridStepWriter.h>

#include <memory>

namespace canopy
{
namespace io
{
class VtkHdfWriter; // the plain C++ writer (VTK\'s wrappers parse this header: no nested namespace
                    // syntax)
}
} // namespace canopy

class CANOPYIO_EXPORT vtkCanopyHyperTreeGridHDFWriter : public vtkCanopyHyperTreeGridStepWriter
{
public:
  static vtkCanopyHyperTreeGridHDFWriter* New();
  vtkTypeMacro(vtkCanopyHyperTreeGridHDFWriter, vtkCanopyHyperTreeGridStepWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

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

  /// Steps in the file after the last successful Write().
  vtkIdType GetNumberOfSteps() const override;

protected:
  vtkCanopyHyperTreeGridHDFWriter();
  ~vtkCanopyHyperTreeGridHDFWriter() override;

  void OpenFile(MPI_Comm communicator) override;
  /// TimeStep only names the step in messages.
  void WriteStep(vtkHyperTreeGrid* htg, double time) override;

  bool Append = false;
  bool CheckFreeSpace = true;

private:
  vtkCanopyHyperTreeGridHDFWriter(const vtkCanopyHyperTreeGridHDFWriter&) = delete;
  void operator=(const vtkCanopyHyperTreeGridHDFWriter&) = delete;

  std::unique_ptr<canopy::io::VtkHdfWriter> Writer;
};
