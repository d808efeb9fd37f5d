// A small HDF5 layer for Canopy's writers: identifiers closed by scope, the
// calls on files, growing datasets and attributes the VTKHDF writer makes, and
// the text of HDF5's error stack for messages (HDF5 prints nothing itself while
// a QuietHdfErrors lives). Functions report failure by an invalid handle or
// false; hdfErrorText() then says why.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace canopy::io
{

/// Owns an HDF5 identifier and closes it with `Close` (H5Fclose, H5Dclose, ...).
template <herr_t (*Close)(hid_t)>
class HdfId
{
public:
  HdfId() = default;
  /// Takes `id` over (a negative id, HDF5's failure, is held as invalid).
  explicit HdfId(hid_t id) : Id(id) {}
  HdfId(HdfId&& other) noexcept : Id(std::exchange(other.Id, H5I_INVALID_HID)) {}
  HdfId& operator=(HdfId&& other) noexcept
  {
    if (this != &other)
    {
      this->reset();
      this->Id = std::exchange(other.Id, H5I_INVALID_HID);
    }
    return *this;
  }
  HdfId(const HdfId&) = delete;
  HdfId& operator=(const HdfId&) = delete;
  ~HdfId() { this->reset(); }

  /// The identifier, still owned by this handle.
  hid_t get() const { return this->Id; }
  bool valid() const { return this->Id >= 0; }
  /// Closes now; false if closing failed (for a file: its last writes).
  bool reset()
  {
    const bool ok = this->Id < 0 || Close(this->Id) >= 0;
    this->Id = H5I_INVALID_HID;
    return ok;
  }

private:
  hid_t Id = H5I_INVALID_HID;
};

using HdfFile = HdfId<H5Fclose>;
using HdfGroup = HdfId<H5Gclose>;
using HdfDataset = HdfId<H5Dclose>;
using HdfSpace = HdfId<H5Sclose>;
using HdfProperties = HdfId<H5Pclose>;
using HdfAttribute = HdfId<H5Aclose>;
using HdfType = HdfId<H5Tclose>;

/// Silences HDF5's automatic error printing for its lifetime (the writer
/// reports errors itself, with rank and step).
class QuietHdfErrors
{
public:
  QuietHdfErrors()
  {
    H5Eget_auto2(H5E_DEFAULT, &this->Function, &this->Data);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietHdfErrors() { H5Eset_auto2(H5E_DEFAULT, this->Function, this->Data); }
  QuietHdfErrors(const QuietHdfErrors&) = delete;
  QuietHdfErrors& operator=(const QuietHdfErrors&) = delete;

private:
  H5E_auto2_t Function = nullptr;
  void* Data = nullptr;
};

/// The innermost messages of HDF5's current error stack ("" if empty), then clears it.
std::string hdfErrorText();

// ---- files and groups ------------------------------------------------------------------

/// `path` is relative to `location` (a file or group; borrowed for the call).
HdfGroup createGroup(hid_t location, const std::string& path);
HdfGroup openGroup(hid_t location, const std::string& path);
/// The names of the links in `group` (borrowed), in name order.
std::vector<std::string> linkNames(hid_t group);

// ---- datasets that grow by rows ------------------------------------------------------------

/// A new empty dataset of rows of `columns` values (1: a 1D dataset) of
/// `fileType`, unlimited in rows, stored in chunks of `chunkRows` rows. Its values
/// are never filled in: every row is written.
HdfDataset createGrowingDataset(hid_t location, const std::string& path, hid_t fileType,
                                int columns, hsize_t chunkRows);
HdfDataset openDataset(hid_t location, const std::string& path);
/// Rows of `dataset` (borrowed), -1 on error.
std::int64_t rowsOf(hid_t dataset);
/// Values per row of `dataset`: 1 for a 1D dataset, -1 on error or for a scalar.
int columnsOf(hid_t dataset);
/// Resizes `dataset` to `rows` rows of `columns` values.
bool setRows(hid_t dataset, std::int64_t rows, int columns);
/// Writes `rows` rows of `columns` values from `values` (of `memoryType`) at row
/// `first` of `dataset`.
bool writeRows(hid_t dataset, int columns, std::int64_t first, std::int64_t rows, hid_t memoryType,
               const void* values);
/// Reads `rows` values of the 1D `dataset` from row `first` into `values`.
bool readRows(hid_t dataset, std::int64_t first, std::int64_t rows, hid_t memoryType, void* values);

// ---- attributes --------------------------------------------------------------------------

/// Writes `count` values (0: a scalar) of `memoryType` from `values` to the
/// attribute `name` of `object`, creating it as `fileType` if it is not there.
bool writeAttribute(hid_t object, const char* name, hid_t fileType, hid_t memoryType, hsize_t count,
                    const void* values);
/// Creates the attribute `name` of `object` as a fixed-length string, as VTK's
/// own writer stores its Type.
bool writeStringAttribute(hid_t object, const char* name, const std::string& value);
bool readAttribute(hid_t object, const char* name, hid_t memoryType, void* values);
/// The fixed-length string attribute `name` of `object`; none if it is missing
/// or not such a string.
std::optional<std::string> readStringAttribute(hid_t object, const char* name);

} // namespace canopy::io
