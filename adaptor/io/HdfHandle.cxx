// A small HDF5 layer for Canopy's writers (see HdfHandle.h).
#include "HdfHandle.h"

namespace canopy::io
{
namespace
{

herr_t collect(unsigned int, const H5E_error2_t* error, void* data)
{
  auto* messages = static_cast<std::vector<std::string>*>(data);
  if (error->desc != nullptr && *error->desc != '\0')
  {
    messages->emplace_back(error->desc);
  }
  return 0;
}

/// The extent of `dataset`, one size per dimension (none on error).
std::vector<hsize_t> extentOf(hid_t dataset)
{
  HdfSpace space{H5Dget_space(dataset)};
  const int rank = space.valid() ? H5Sget_simple_extent_ndims(space.get()) : -1;
  if (rank < 0)
  {
    return {};
  }
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank), 0);
  if (H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr) < 0)
  {
    return {};
  }
  return dims;
}

} // namespace

std::string hdfErrorText()
{
  std::vector<std::string> messages;
  // Downward: from the API call to the innermost cause (e.g. the system's error).
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, collect, &messages);
  H5Eclear2(H5E_DEFAULT);
  if (messages.empty())
  {
    return {};
  }
  std::string text = messages.back();
  if (messages.size() > 1 && messages[messages.size() - 2] != text)
  {
    text = messages[messages.size() - 2] + ": " + text;
  }
  return text;
}

HdfGroup createGroup(hid_t location, const std::string& path)
{
  return HdfGroup{H5Gcreate2(location, path.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT)};
}

HdfGroup openGroup(hid_t location, const std::string& path)
{
  return HdfGroup{H5Gopen2(location, path.c_str(), H5P_DEFAULT)};
}

std::vector<std::string> linkNames(hid_t group)
{
  std::vector<std::string> names;
  H5Literate(
      group, H5_INDEX_NAME, H5_ITER_INC, nullptr,
      [](hid_t, const char* name, const H5L_info_t*, void* data)
      {
        static_cast<std::vector<std::string>*>(data)->emplace_back(name);
        return herr_t(0);
      },
      &names);
  return names;
}

HdfDataset createGrowingDataset(hid_t location, const std::string& path, hid_t fileType,
                                int columns, hsize_t chunkRows)
{
  const int rank = columns > 1 ? 2 : 1;
  const hsize_t dims[2] = {0, static_cast<hsize_t>(columns)};
  const hsize_t maxDims[2] = {H5S_UNLIMITED, static_cast<hsize_t>(columns)};
  const hsize_t chunk[2] = {chunkRows, static_cast<hsize_t>(columns)};
  HdfSpace space{H5Screate_simple(rank, dims, maxDims)};
  HdfProperties properties{H5Pcreate(H5P_DATASET_CREATE)};
  H5Pset_chunk(properties.get(), rank, chunk);
  // Every value is written: no fill pass over new chunks.
  H5Pset_fill_time(properties.get(), H5D_FILL_TIME_NEVER);
  return HdfDataset{H5Dcreate2(location, path.c_str(), fileType, space.get(), H5P_DEFAULT,
                               properties.get(), H5P_DEFAULT)};
}

HdfDataset openDataset(hid_t location, const std::string& path)
{
  return HdfDataset{H5Dopen2(location, path.c_str(), H5P_DEFAULT)};
}

std::int64_t rowsOf(hid_t dataset)
{
  const std::vector<hsize_t> dims = extentOf(dataset);
  return dims.empty() ? -1 : static_cast<std::int64_t>(dims[0]);
}

int columnsOf(hid_t dataset)
{
  const std::vector<hsize_t> dims = extentOf(dataset);
  if (dims.empty())
  {
    return -1;
  }
  return dims.size() > 1 ? static_cast<int>(dims[1]) : 1;
}

bool setRows(hid_t dataset, std::int64_t rows, int columns)
{
  const hsize_t dims[2] = {static_cast<hsize_t>(rows), static_cast<hsize_t>(columns)};
  return H5Dset_extent(dataset, dims) >= 0;
}

bool writeRows(hid_t dataset, int columns, std::int64_t first, std::int64_t rows, hid_t memoryType,
               const void* values)
{
  if (rows == 0)
  {
    return true;
  }
  HdfSpace space{H5Dget_space(dataset)};
  const hsize_t start[2] = {static_cast<hsize_t>(first), 0};
  const hsize_t count[2] = {static_cast<hsize_t>(rows), static_cast<hsize_t>(columns)};
  HdfSpace memory{H5Screate_simple(columns > 1 ? 2 : 1, count, nullptr)};
  return H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr) >= 0 &&
         H5Dwrite(dataset, memoryType, memory.get(), space.get(), H5P_DEFAULT, values) >= 0;
}

bool readRows(hid_t dataset, std::int64_t first, std::int64_t rows, hid_t memoryType, void* values)
{
  if (rows == 0)
  {
    return true;
  }
  HdfSpace space{H5Dget_space(dataset)};
  const hsize_t start = static_cast<hsize_t>(first), count = static_cast<hsize_t>(rows);
  HdfSpace memory{H5Screate_simple(1, &count, nullptr)};
  return space.valid() && memory.valid() &&
         H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, &start, nullptr, &count, nullptr) >= 0 &&
         H5Dread(dataset, memoryType, memory.get(), space.get(), H5P_DEFAULT, values) >= 0;
}

bool writeAttribute(hid_t object, const char* name, hid_t fileType, hid_t memoryType, hsize_t count,
                    const void* values)
{
  HdfSpace space{count == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &count, nullptr)};
  HdfAttribute attribute{
      H5Aexists(object, name) > 0
          ? H5Aopen(object, name, H5P_DEFAULT)
          : H5Acreate2(object, name, fileType, space.get(), H5P_DEFAULT, H5P_DEFAULT)};
  return attribute.valid() && H5Awrite(attribute.get(), memoryType, values) >= 0;
}

bool writeStringAttribute(hid_t object, const char* name, const std::string& value)
{
  HdfType type{H5Tcopy(H5T_C_S1)};
  H5Tset_size(type.get(), value.size());
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  HdfSpace space{H5Screate(H5S_SCALAR)};
  HdfAttribute attribute{
      H5Acreate2(object, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT)};
  return attribute.valid() && H5Awrite(attribute.get(), type.get(), value.data()) >= 0;
}

bool readAttribute(hid_t object, const char* name, hid_t memoryType, void* values)
{
  HdfAttribute attribute{H5Aopen(object, name, H5P_DEFAULT)};
  return attribute.valid() && H5Aread(attribute.get(), memoryType, values) >= 0;
}

std::optional<std::string> readStringAttribute(hid_t object, const char* name)
{
  if (H5Aexists(object, name) <= 0)
  {
    return std::nullopt;
  }
  HdfAttribute attribute{H5Aopen(object, name, H5P_DEFAULT)};
  HdfType type{H5Aget_type(attribute.get())};
  if (!type.valid() || H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()))
  {
    return std::nullopt;
  }
  std::string value(H5Tget_size(type.get()), '\0');
  if (H5Aread(attribute.get(), type.get(), value.data()) < 0)
  {
    return std::nullopt;
  }
  return std::string(value.c_str()); // without the padding
}

} // namespace canopy::io
