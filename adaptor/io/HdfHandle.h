// HDF5 identifiers closed by scope, and the text of HDF5's error stack for
// messages (HDF5 prints nothing itself while a QuietHdfErrors lives).
#pragma once

#include <hdf5.h>

#include <string>
#include <utility>

namespace canopy::io
{

class HdfHandle
{
public:
  using Closer = herr_t (*)(hid_t);
  HdfHandle() = default;
  HdfHandle(hid_t id, Closer closer) : Id(id), Close(closer) {}
  HdfHandle(HdfHandle&& other) noexcept
      : Id(std::exchange(other.Id, H5I_INVALID_HID)), Close(other.Close)
  {
  }
  HdfHandle& operator=(HdfHandle&& other) noexcept
  {
    if (this != &other)
    {
      this->reset();
      this->Id = std::exchange(other.Id, H5I_INVALID_HID);
      this->Close = other.Close;
    }
    return *this;
  }
  HdfHandle(const HdfHandle&) = delete;
  HdfHandle& operator=(const HdfHandle&) = delete;
  ~HdfHandle() { this->reset(); }

  hid_t get() const { return this->Id; }
  bool valid() const { return this->Id >= 0; }
  /// Closes now; false if closing failed (for a file: its last writes).
  bool reset()
  {
    bool ok = true;
    if (this->Id >= 0 && this->Close != nullptr)
    {
      ok = this->Close(this->Id) >= 0;
    }
    this->Id = H5I_INVALID_HID;
    return ok;
  }

private:
  hid_t Id = H5I_INVALID_HID;
  Closer Close = nullptr;
};

inline HdfHandle fileHandle(hid_t id)
{
  return {id, H5Fclose};
}
inline HdfHandle groupHandle(hid_t id)
{
  return {id, H5Gclose};
}
inline HdfHandle datasetHandle(hid_t id)
{
  return {id, H5Dclose};
}
inline HdfHandle spaceHandle(hid_t id)
{
  return {id, H5Sclose};
}
inline HdfHandle propertyHandle(hid_t id)
{
  return {id, H5Pclose};
}
inline HdfHandle attributeHandle(hid_t id)
{
  return {id, H5Aclose};
}
inline HdfHandle typeHandle(hid_t id)
{
  return {id, H5Tclose};
}

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

} // namespace canopy::io
