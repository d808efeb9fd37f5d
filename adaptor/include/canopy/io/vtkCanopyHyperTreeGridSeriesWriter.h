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
 * (errors: vtkCanopyHyperTreeGridStepWriter) leaves the step out of the
 * series. See canopy::io::HtgSeriesWriter for the C++ API.
 */
#pragma once

#include <canopy/io/vtkCanopyHyperTreeGridStepWriter.h>

#include <memory>

namespace canopy
{
namespace io
{
class HtgSeriesWriter; // the plain C++ writer (VTK\'s wrappers parse this header: no nested
                       // namespace syntax)
}
} // namespace canopy

class CANOPYIO_EXPORT vtkCanopyHyperTreeGridSeriesWriter : public vtkCanopyHyperTreeGridStepWriter
{
public:
  static vtkCanopyHyperTreeGridSeriesWriter* New();
  vtkTypeMacro(vtkCanopyHyperTreeGridSeriesWriter, vtkCanopyHyperTreeGridStepWriter);

  /// Steps in the series so far.
  vtkIdType GetNumberOfSteps() const override;

protected:
  vtkCanopyHyperTreeGridSeriesWriter();
  ~vtkCanopyHyperTreeGridSeriesWriter() override;

  void OpenFile(MPI_Comm communicator) override;
  /// TimeStep names the step's files (-1: the number of steps written before).
  void WriteStep(vtkHyperTreeGrid* htg, double time) override;

private:
  vtkCanopyHyperTreeGridSeriesWriter(const vtkCanopyHyperTreeGridSeriesWriter&) = delete;
  void operator=(const vtkCanopyHyperTreeGridSeriesWriter&) = delete;

  std::unique_ptr<canopy::io::HtgSeriesWriter> Writer;
};
