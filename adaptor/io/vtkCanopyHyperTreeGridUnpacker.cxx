#include <canopy/io/vtkCanopyHyperTreeGridUnpacker.h>

#include "PackedGridFrame.h"
#include <canopy/io/vtkCanopyHyperTreeGridPacker.h>

#include <vtkDataObject.h>
#include <vtkDataSet.h>
#include <vtkFieldData.h>
#include <vtkHyperTreeGrid.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkObjectFactory.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLHyperTreeGridReader.h>

#include <string>

vtkStandardNewMacro(vtkCanopyHyperTreeGridUnpacker);

int vtkCanopyHyperTreeGridUnpacker::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  return 1;
}

int vtkCanopyHyperTreeGridUnpacker::RequestData(vtkInformation*, vtkInformationVector** inputs,
                                                vtkInformationVector* outputs)
{
  namespace packed = canopy::io::packed;
  auto* input = vtkDataObject::GetData(inputs[0], 0);
  auto* output = vtkMultiBlockDataSet::GetData(outputs, 0);
  this->NumberOfPieces = 0;
  if (auto* grid = vtkHyperTreeGrid::SafeDownCast(input))
  {
    // A grid that was never packed (the same pipeline without Live): itself.
    vtkNew<vtkHyperTreeGrid> same;
    same->ShallowCopy(grid);
    output->SetBlock(0, same);
    this->NumberOfPieces = 1;
    return 1;
  }
  auto* bytes = vtkUnsignedCharArray::SafeDownCast(
      input->GetFieldData()->GetArray(vtkCanopyHyperTreeGridPacker::ArrayName()));
  if (!bytes && !input->GetFieldData()->GetNumberOfArrays() &&
      (!vtkDataSet::SafeDownCast(input) || !vtkDataSet::SafeDownCast(input)->GetNumberOfPoints()))
  {
    // Nothing yet (a Live extract before its first delivery): nothing to unpack.
    output->Initialize();
    return 1;
  }
  if (!bytes)
  {
    vtkErrorMacro("the input has no unsigned char field array '"
                  << vtkCanopyHyperTreeGridPacker::ArrayName()
                  << "': it is not the output of vtkCanopyHyperTreeGridPacker");
    return 0;
  }
  const auto* data = bytes->GetPointer(0);
  const auto size = static_cast<std::int64_t>(bytes->GetNumberOfValues());
  std::int64_t at = 0;
  unsigned int block = 0;
  while (at < size)
  {
    const std::int64_t length = size - at >= static_cast<std::int64_t>(packed::HeaderBytes)
                                    ? packed::textLength(data + at)
                                    : -1;
    if (length < 0 || length > size - at - static_cast<std::int64_t>(packed::HeaderBytes))
    {
      vtkErrorMacro("byte " << at << " of " << size
                            << ": not the start of a packed piece (a 'CNPY' header "
                               "and a length within the bytes)");
      output->Initialize();
      return 0;
    }
    const char* text = reinterpret_cast<const char*>(data + at + packed::HeaderBytes);
    vtkNew<vtkXMLHyperTreeGridReader> reader;
    reader->ReadFromInputStringOn();
    reader->SetInputString(std::string(text, static_cast<std::size_t>(length)));
    reader->Update();
    auto* htg = vtkHyperTreeGrid::SafeDownCast(reader->GetOutputDataObject(0));
    if (!htg || reader->GetErrorCode() != 0)
    {
      vtkErrorMacro("piece " << block << " (byte " << at << "): not a readable .htg piece");
      output->Initialize();
      return 0;
    }
    vtkNew<vtkHyperTreeGrid> copy;
    copy->ShallowCopy(htg);
    output->SetBlock(block++, copy);
    at += static_cast<std::int64_t>(packed::HeaderBytes) + length;
  }
  this->NumberOfPieces = block;
  return 1;
}

void vtkCanopyHyperTreeGridUnpacker::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfPieces: " << this->NumberOfPieces << "\n";
}
