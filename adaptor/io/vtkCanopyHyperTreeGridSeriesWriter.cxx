#include <canopy/io/vtkCanopyHyperTreeGridSeriesWriter.h>

#include <canopy/io/HtgSeriesWriter.h>

#include <vtkObjectFactory.h>

vtkStandardNewMacro(vtkCanopyHyperTreeGridSeriesWriter);

vtkCanopyHyperTreeGridSeriesWriter::vtkCanopyHyperTreeGridSeriesWriter() = default;
vtkCanopyHyperTreeGridSeriesWriter::~vtkCanopyHyperTreeGridSeriesWriter() = default;

vtkIdType vtkCanopyHyperTreeGridSeriesWriter::GetNumberOfSteps() const
{
  return this->Writer ? static_cast<vtkIdType>(this->Writer->numberOfSteps()) : 0;
}

void vtkCanopyHyperTreeGridSeriesWriter::OpenFile(MPI_Comm communicator)
{
  this->Writer =
      std::make_unique<canopy::io::HtgSeriesWriter>(communicator, this->FileName, this->CellArrays);
}

void vtkCanopyHyperTreeGridSeriesWriter::WriteStep(vtkHyperTreeGrid* htg, double time)
{
  const vtkIdType step = this->TimeStep >= 0 ? this->TimeStep : this->GetNumberOfSteps();
  this->Writer->writeStep(htg, step, time);
}
