/**
 * @class vtkCanopyXMLPUnstructuredGridWriter
 * @brief vtkXMLPUnstructuredGridWriter (.pvtu and a .vtu piece per rank) whose pieces
 * survive a failed write: the step's error is reported, the simulation goes on.
 *
 * VTK 9.2's piece writer frees arrays it never allocated when a write fails in
 * the middle of a piece (see FailSafeXmlPieceWriters.h); this writer gives every
 * piece to a writer that does not. Everything else is vtkXMLPUnstructuredGridWriter's.
 * The shipped pipelines use it through the "CanopyVTU" extractor
 * (adaptor/plugin/CanopyWriters.xml).
 */
#pragma once

#include "CanopyIOModule.h" // for export macro

#include <vtkXMLPUnstructuredGridWriter.h>

class CANOPYIO_EXPORT vtkCanopyXMLPUnstructuredGridWriter : public vtkXMLPUnstructuredGridWriter
{
public:
  static vtkCanopyXMLPUnstructuredGridWriter* New();
  vtkTypeMacro(vtkCanopyXMLPUnstructuredGridWriter, vtkXMLPUnstructuredGridWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;
  /// The pieces and summary, then the summary read back on the rank that wrote
  /// it: a summary not written whole is an error (see FailSafeXmlPieceWriters.h).
  vtkTypeBool ProcessRequest(vtkInformation* request, vtkInformationVector** inputVector,
                             vtkInformationVector* outputVector) override;

protected:
  vtkCanopyXMLPUnstructuredGridWriter() = default;
  ~vtkCanopyXMLPUnstructuredGridWriter() override = default;

  vtkXMLUnstructuredDataWriter* CreateUnstructuredPieceWriter() override;

private:
  vtkCanopyXMLPUnstructuredGridWriter(const vtkCanopyXMLPUnstructuredGridWriter&) = delete;
  void operator=(const vtkCanopyXMLPUnstructuredGridWriter&) = delete;
};
