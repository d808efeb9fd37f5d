#include <canopy/io/vtkCanopyHyperTreeGridHDFWriter.h>

#include <canopy/io/VtkHdfWriter.h>

#include <vtkObjectFactory.h>

vtkStandardNewMacro(vtkCanopyHyperTreeGridHDFWriter);

vtkCanopyHyperTreeGridHDFWriter::vtkCanopyHyperTreeGridHDFWriter() = default;
vtkCanopyHyperTreeGridHDFWriter::~vtkCanopyHyperTreeGridHDFWriter() = default;

vtkIdType vtkCanopyHyperTreeGridHDFWriter::GetNumberOfSteps() const
{
  return this->Writer ? this->Writer->numberOfSteps() : 0;
}

void vtkCanopyHyperTreeGridHDFWriter::OpenFile(MPI_Comm communicator)
{
  canopy::io::VtkHdfWriterOptions options;
  options.arrays = this->CellArrays;
  options.append = this->Append;
  options.checkFreeSpace = this->CheckFreeSpace;
  this->Writer = std::make_unique<canopy::io::VtkHdfWriter>(communicator, this->FileName, options);
}

void vtkCanopyHyperTreeGridHDFWriter::WriteStep(vtkHyperTreeGrid* htg, double time)
{
  this->Writer->writeStep(htg, this->TimeStep, time);
}

void vtkCanopyHyperTreeGridHDFWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Append: " << this->Append << "\n"
     << indent << "CheckFreeSpace: " << this->CheckFreeSpace << "\n";
}
