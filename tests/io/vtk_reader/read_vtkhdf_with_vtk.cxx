// Opens a VTKHDF hypertree-grid file with VTK's vtkHDFReader, as current
// ParaView does, and prints what it read as JSON, one line per step: each
// piece's trees, cells, leaves and masked cells, its cell arrays, and every
// tree's values node by node (local index order), so that a checker can
// compare them with what the simulation wrote. Exit code 1 when VTK reports an
// error or the file does not read as hypertree grids.
#include <vtkBitArray.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkHDFReader.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkNew.h>
#include <vtkOutputWindow.h>
#include <vtkPartitionedDataSet.h>
#include <vtkSmartPointer.h>

#include <cmath>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace
{

/// Counts VTK's error and warning events instead of letting them pass unseen.
class MessageCounter : public vtkCommand
{
public:
  static MessageCounter* New() { return new MessageCounter; }
  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    ++this->Count;
    std::cerr << (event == vtkCommand::ErrorEvent ? "VTK error: " : "VTK warning: ")
              << (data ? static_cast<const char*>(data) : "") << "\n";
  }
  int Count = 0;
};

std::string number(double value)
{
  if (std::isnan(value))
    return "\"nan\"";
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

void printPiece(vtkHyperTreeGrid* htg, std::ostream& out)
{
  vtkBitArray* mask = htg->HasMask() ? htg->GetMask() : nullptr;
  vtkIdType masked = 0;
  for (vtkIdType i = 0; mask && i < mask->GetNumberOfTuples(); ++i)
    masked += mask->GetValue(i);
  out << "{\"trees\": " << htg->GetMaxNumberOfTrees() << ", \"cells\": " << htg->GetNumberOfCells()
      << ", \"leaves\": " << htg->GetNumberOfLeaves() << ", \"masked\": " << masked
      << ", \"arrays\": {";
  vtkCellData* cd = htg->GetCellData();
  for (int a = 0; a < cd->GetNumberOfArrays(); ++a)
    out << (a ? ", " : "") << "\"" << cd->GetArrayName(a)
        << "\": " << cd->GetArray(a)->GetNumberOfComponents();
  out << "}, \"values\": {";
  // Per tree (by root index) and field: the values of local nodes 0, 1, ...
  bool firstTree = true;
  vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
  htg->InitializeTreeIterator(it);
  vtkIdType root = 0;
  while (vtkHyperTree* tree = it.GetNextTree(root))
  {
    out << (firstTree ? "" : ", ") << "\"" << root << "\": {";
    firstTree = false;
    for (int a = 0; a < cd->GetNumberOfArrays(); ++a)
    {
      vtkDataArray* array = cd->GetArray(a);
      if (!array)
        continue;
      out << (a ? ", " : "") << "\"" << array->GetName() << "\": [";
      for (vtkIdType node = 0; node < tree->GetNumberOfVertices(); ++node)
      {
        const vtkIdType cell = tree->GetGlobalIndexFromLocal(node);
        out << (node ? ", " : "") << "[";
        for (int c = 0; c < array->GetNumberOfComponents(); ++c)
          out << (c ? ", " : "") << number(array->GetComponent(cell, c));
        out << "]";
      }
      out << "]";
    }
    out << "}";
  }
  out << "}}";
}

} // namespace

int main(int argc, char** argv)
{
  if (argc != 2)
  {
    std::cerr << "usage: read_vtkhdf_with_vtk FILE.vtkhdf\n";
    return 2;
  }
  vtkOutputWindow::GetInstance()->PromptUserOff();
  vtkNew<MessageCounter> messages;
  vtkNew<vtkHDFReader> reader;
  reader->AddObserver(vtkCommand::ErrorEvent, messages);
  reader->AddObserver(vtkCommand::WarningEvent, messages);
  reader->SetFileName(argv[1]);
  reader->UpdateInformation();
  const vtkIdType steps = reader->GetNumberOfSteps();
  for (vtkIdType step = 0; step < steps; ++step)
  {
    reader->SetStep(step);
    reader->Update();
    vtkDataObject* data = reader->GetOutputDataObject(0);
    std::vector<vtkHyperTreeGrid*> pieces;
    if (auto* htg = vtkHyperTreeGrid::SafeDownCast(data))
      pieces.push_back(htg);
    else if (auto* partitioned = vtkPartitionedDataSet::SafeDownCast(data))
      for (unsigned int p = 0; p < partitioned->GetNumberOfPartitions(); ++p)
        pieces.push_back(vtkHyperTreeGrid::SafeDownCast(partitioned->GetPartitionAsDataObject(p)));
    std::cout << "{\"step\": " << step << ", \"steps\": " << steps
              << ", \"time\": " << number(reader->GetTimeValue()) << ", \"output\": \""
              << (data ? data->GetClassName() : "none") << "\", \"pieces\": [";
    for (std::size_t p = 0; p < pieces.size(); ++p)
    {
      std::cout << (p ? ", " : "");
      if (pieces[p])
        printPiece(pieces[p], std::cout);
      else
        std::cout << "null";
    }
    std::cout << "]}\n";
  }
  std::cerr << steps << " step(s) read, " << messages->Count << " VTK error(s)/warning(s)\n";
  return messages->Count == 0 && steps > 0 ? 0 : 1;
}
