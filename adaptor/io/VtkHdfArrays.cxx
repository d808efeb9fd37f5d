// The cell arrays of a VTKHDF step (see VtkHdfArrays.h).
#include "VtkHdfArrays.h"

#include "CellArraySelection.h"
#include "GatherText.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkHyperTreeGrid.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <map>

namespace canopy::io
{
namespace
{

const char* const GhostArray = vtkDataSetAttributes::GhostArrayName();

/// An ArraySpec as it travels between ranks: these fixed fields, then
/// `nameLength` bytes of name.
struct PackedSpec
{
  std::int32_t nameLength = 0;
  std::int32_t type = VTK_DOUBLE;
  std::int32_t components = 1;
};

std::vector<ArraySpec> specsOf(const std::vector<vtkDataArray*>& arrays)
{
  std::vector<ArraySpec> specs;
  for (vtkDataArray* array : arrays)
  {
    specs.push_back({array->GetName(), array->GetDataType(), array->GetNumberOfComponents()});
  }
  return specs;
}

std::string pack(const std::vector<ArraySpec>& specs)
{
  std::string bytes;
  for (const ArraySpec& spec : specs)
  {
    const PackedSpec fields{static_cast<std::int32_t>(spec.name.size()), spec.type,
                            spec.components};
    bytes.append(reinterpret_cast<const char*>(&fields), sizeof(fields));
    bytes += spec.name;
  }
  return bytes;
}

std::vector<ArraySpec> unpack(const std::string& bytes)
{
  std::vector<ArraySpec> specs;
  for (std::size_t at = 0; at + sizeof(PackedSpec) <= bytes.size();)
  {
    PackedSpec fields;
    std::memcpy(&fields, bytes.data() + at, sizeof(fields));
    at += sizeof(fields);
    const auto length = static_cast<std::size_t>(fields.nameLength);
    specs.push_back({bytes.substr(at, length), fields.type, fields.components});
    at += length;
  }
  return specs;
}

} // namespace

hid_t fileTypeOf(int vtkType)
{
  switch (vtkType)
  {
  case VTK_FLOAT:
    return H5T_IEEE_F32LE;
  case VTK_DOUBLE:
    return H5T_IEEE_F64LE;
  case VTK_CHAR:
  case VTK_SIGNED_CHAR:
    return H5T_STD_I8LE;
  case VTK_UNSIGNED_CHAR:
    return H5T_STD_U8LE;
  case VTK_SHORT:
    return H5T_STD_I16LE;
  case VTK_UNSIGNED_SHORT:
    return H5T_STD_U16LE;
  case VTK_INT:
    return H5T_STD_I32LE;
  case VTK_UNSIGNED_INT:
    return H5T_STD_U32LE;
  case VTK_LONG:
    return sizeof(long) == 8 ? H5T_STD_I64LE : H5T_STD_I32LE;
  case VTK_UNSIGNED_LONG:
    return sizeof(long) == 8 ? H5T_STD_U64LE : H5T_STD_U32LE;
  case VTK_LONG_LONG:
  case VTK_ID_TYPE:
    return H5T_STD_I64LE;
  case VTK_UNSIGNED_LONG_LONG:
    return H5T_STD_U64LE;
  default:
    return H5I_INVALID_HID;
  }
}

hid_t memoryTypeOf(int vtkType)
{
  switch (vtkType)
  {
  case VTK_FLOAT:
    return H5T_NATIVE_FLOAT;
  case VTK_DOUBLE:
    return H5T_NATIVE_DOUBLE;
  case VTK_CHAR:
    return H5T_NATIVE_CHAR;
  case VTK_SIGNED_CHAR:
    return H5T_NATIVE_SCHAR;
  case VTK_UNSIGNED_CHAR:
    return H5T_NATIVE_UCHAR;
  case VTK_SHORT:
    return H5T_NATIVE_SHORT;
  case VTK_UNSIGNED_SHORT:
    return H5T_NATIVE_USHORT;
  case VTK_INT:
    return H5T_NATIVE_INT;
  case VTK_UNSIGNED_INT:
    return H5T_NATIVE_UINT;
  case VTK_LONG:
    return H5T_NATIVE_LONG;
  case VTK_UNSIGNED_LONG:
    return H5T_NATIVE_ULONG;
  case VTK_LONG_LONG:
  case VTK_ID_TYPE:
    return H5T_NATIVE_LLONG;
  case VTK_UNSIGNED_LONG_LONG:
    return H5T_NATIVE_ULLONG;
  default:
    return H5I_INVALID_HID;
  }
}

int vtkTypeOf(hid_t type)
{
  const H5T_class_t typeClass = H5Tget_class(type);
  const std::size_t size = H5Tget_size(type);
  if (typeClass == H5T_FLOAT)
  {
    return size == 4 ? VTK_FLOAT : VTK_DOUBLE;
  }
  if (typeClass != H5T_INTEGER)
  {
    return VTK_VOID;
  }
  const bool isSigned = H5Tget_sign(type) == H5T_SGN_2;
  switch (size)
  {
  case 1:
    return isSigned ? VTK_SIGNED_CHAR : VTK_UNSIGNED_CHAR;
  case 2:
    return isSigned ? VTK_SHORT : VTK_UNSIGNED_SHORT;
  case 4:
    return isSigned ? VTK_INT : VTK_UNSIGNED_INT;
  default:
    return isSigned ? VTK_LONG_LONG : VTK_UNSIGNED_LONG_LONG;
  }
}

std::vector<vtkDataArray*> selectStepArrays(vtkHyperTreeGrid* htg,
                                            const std::vector<std::string>& names,
                                            std::vector<std::string>& problems)
{
  std::vector<vtkDataArray*> arrays = selectCellArrays(htg, names, problems);
  if (htg != nullptr && !names.empty())
  {
    vtkDataArray* ghosts = htg->GetCellData()->GetArray(GhostArray);
    if (ghosts != nullptr && std::find(arrays.begin(), arrays.end(), ghosts) == arrays.end())
    {
      arrays.push_back(ghosts);
    }
  }
  for (vtkDataArray* array : arrays)
  {
    const std::string name = array->GetName();
    if (name.find_first_of("/.") != std::string::npos)
    {
      problems.push_back("cell array '" + name + "': VTKHDF names cannot contain '/' or '.'");
    }
    else if (fileTypeOf(array->GetDataType()) < 0)
    {
      problems.push_back("cell array '" + name + "' has a value type VTKHDF cannot store");
    }
  }
  return arrays;
}

AgreedArrays gatherArraySpecs(MPI_Comm communicator, const std::vector<vtkDataArray*>& arrays)
{
  AgreedArrays agreed;
  std::map<std::string, ArraySpec> seen;
  for (const std::string& bytes : gatherTextsToAll(communicator, pack(specsOf(arrays))))
  {
    for (ArraySpec& spec : unpack(bytes))
    {
      const auto known = seen.find(spec.name);
      if (known == seen.end())
      {
        seen[spec.name] = spec;
        agreed.specs.push_back(std::move(spec));
      }
      else if (known->second.type != spec.type || known->second.components != spec.components)
      {
        // Every rank sees every rank's arrays: the first conflict is the same on all.
        agreed.conflict =
            "cell array '" + spec.name + "' differs between ranks in value type or components";
        return agreed;
      }
    }
  }
  return agreed;
}

std::vector<ArraySpec> broadcastArraySpecs(MPI_Comm communicator,
                                           const std::vector<ArraySpec>& specs)
{
  return unpack(broadcastText(communicator, pack(specs)));
}

std::string missingArrays(const std::vector<ArraySpec>& specs,
                          const std::vector<vtkDataArray*>& arrays)
{
  std::string missing;
  for (const ArraySpec& spec : specs)
  {
    const vtkDataArray* found = findArray(arrays, spec.name);
    if (found == nullptr)
    {
      if (spec.name != GhostArray)
      {
        missing += (missing.empty() ? "" : "; ") + ("no cell array '" + spec.name + "'");
      }
    }
    else if (found->GetNumberOfComponents() != spec.components)
    {
      missing +=
          (missing.empty() ? "" : "; ") +
          ("cell array '" + spec.name + "' has " + std::to_string(found->GetNumberOfComponents()) +
           " components, the file " + std::to_string(spec.components));
    }
  }
  return missing;
}

vtkDataArray* findArray(const std::vector<vtkDataArray*>& arrays, const std::string& name)
{
  const auto found = std::find_if(arrays.begin(), arrays.end(),
                                  [&](vtkDataArray* a) { return name == a->GetName(); });
  return found == arrays.end() ? nullptr : *found;
}

} // namespace canopy::io
