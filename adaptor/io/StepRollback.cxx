// One step's writes to an HDF5 file, undoable (see StepRollback.h): the state
// of a step, and the HDF5 virtual file driver that routes the file's I/O
// through it.
#include "StepRollback.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <new>

namespace canopy::io
{
namespace
{

std::string errorText(int error)
{
  return std::strerror(error);
}

/// Writes all of `size` bytes at `offset`; false with errno set if the disk refused.
bool writeAll(int descriptor, const unsigned char* bytes, std::size_t size, std::uint64_t offset)
{
  while (size > 0)
  {
    const ssize_t written = ::pwrite(descriptor, bytes, size, static_cast<off_t>(offset));
    if (written < 0 && errno == EINTR)
    {
      continue;
    }
    if (written <= 0)
    {
      if (written == 0)
      {
        errno = EIO;
      }
      return false;
    }
    bytes += written;
    size -= static_cast<std::size_t>(written);
    offset += static_cast<std::uint64_t>(written);
  }
  return true;
}

/// Reads `size` bytes at `offset`, zeros past the end of the file; false with errno set.
bool readAll(int descriptor, unsigned char* bytes, std::size_t size, std::uint64_t offset)
{
  while (size > 0)
  {
    const ssize_t got = ::pread(descriptor, bytes, size, static_cast<off_t>(offset));
    if (got < 0 && errno == EINTR)
    {
      continue;
    }
    if (got < 0)
    {
      return false;
    }
    if (got == 0)
    {
      std::memset(bytes, 0, size);
      return true;
    }
    bytes += got;
    size -= static_cast<std::size_t>(got);
    offset += static_cast<std::uint64_t>(got);
  }
  return true;
}

// ---- the HDF5 driver ----------------------------------------------------------------------

/// What a file access property list carries to the driver's open.
struct DriverInfo
{
  StepRollback* owner;
};

/// An open file as HDF5 holds it; `base` first, as HDF5 requires.
struct RollbackFile
{
  H5FD_t base;
  StepRollback* owner;
  int descriptor;
  haddr_t endOfAddress;
  dev_t device;
  ino_t inode;
};

constexpr haddr_t MaximumAddress = (static_cast<haddr_t>(1) << 62) - 1;

void pushError(hid_t minor, const std::string& text)
{
  H5Epush2(H5E_DEFAULT, __FILE__, "StepRollback", __LINE__, H5E_ERR_CLS, H5E_VFL, minor, "%s",
           text.c_str());
}

H5FD_t* openFile(const char* name, unsigned flags, hid_t access, haddr_t maxAddress)
{
  const auto* info = static_cast<const DriverInfo*>(H5Pget_driver_info(access));
  if (info == nullptr || info->owner == nullptr || maxAddress == 0)
  {
    pushError(H5E_CANTOPENFILE, "the step rollback driver was not given its state");
    return nullptr;
  }
  int mode = (flags & H5F_ACC_RDWR) ? O_RDWR : O_RDONLY;
  mode |= (flags & H5F_ACC_TRUNC) ? O_TRUNC : 0;
  mode |= (flags & H5F_ACC_CREAT) ? O_CREAT : 0;
  mode |= (flags & H5F_ACC_EXCL) ? O_EXCL : 0;
  struct stat before;
  const bool existed = ::stat(name, &before) == 0;
  const int descriptor = ::open(name, mode | O_CLOEXEC, 0666);
  struct stat after;
  if (descriptor < 0 || ::fstat(descriptor, &after) != 0)
  {
    const int error = errno;
    if (descriptor >= 0)
    {
      ::close(descriptor);
    }
    pushError(H5E_CANTOPENFILE, errorText(error));
    return nullptr;
  }
  auto* file = new (std::nothrow) RollbackFile();
  if (file == nullptr)
  {
    ::close(descriptor);
    pushError(H5E_CANTOPENFILE, "out of memory");
    return nullptr;
  }
  file->owner = info->owner;
  file->descriptor = descriptor;
  file->device = after.st_dev;
  file->inode = after.st_ino;
  file->owner->opened(descriptor, after.st_size, !existed || (flags & H5F_ACC_TRUNC) != 0);
  return &file->base;
}

RollbackFile* fileOf(H5FD_t* file)
{
  return reinterpret_cast<RollbackFile*>(file);
}
const RollbackFile* fileOf(const H5FD_t* file)
{
  return reinterpret_cast<const RollbackFile*>(file);
}

herr_t closeFile(H5FD_t* handle)
{
  RollbackFile* file = fileOf(handle);
  file->owner->closing();
  delete file;
  return 0;
}

int compareFiles(const H5FD_t* a, const H5FD_t* b)
{
  const RollbackFile* x = fileOf(a);
  const RollbackFile* y = fileOf(b);
  if (x->device != y->device)
  {
    return x->device < y->device ? -1 : 1;
  }
  if (x->inode != y->inode)
  {
    return x->inode < y->inode ? -1 : 1;
  }
  return 0;
}

herr_t queryFeatures(const H5FD_t*, unsigned long* flags)
{
  // As HDF5's own POSIX driver: small metadata and raw data gathered into larger I/O.
  *flags = H5FD_FEAT_AGGREGATE_METADATA | H5FD_FEAT_ACCUMULATE_METADATA | H5FD_FEAT_DATA_SIEVE |
           H5FD_FEAT_AGGREGATE_SMALLDATA;
  return 0;
}

haddr_t endOfAddress(const H5FD_t* file, H5FD_mem_t)
{
  return fileOf(file)->endOfAddress;
}

herr_t setEndOfAddress(H5FD_t* file, H5FD_mem_t, haddr_t address)
{
  fileOf(file)->endOfAddress = address;
  return 0;
}

haddr_t endOfFile(const H5FD_t* file, H5FD_mem_t)
{
  return fileOf(file)->owner->endOfFile();
}

herr_t handleOf(H5FD_t* file, hid_t, void** handle)
{
  *handle = &fileOf(file)->descriptor;
  return 0;
}

herr_t readFile(H5FD_t* file, H5FD_mem_t, hid_t, haddr_t address, size_t size, void* buffer)
{
  if (!fileOf(file)->owner->read(address, size, buffer))
  {
    pushError(H5E_READERROR, errorText(errno));
    return -1;
  }
  return 0;
}

herr_t writeFile(H5FD_t* file, H5FD_mem_t, hid_t, haddr_t address, size_t size, const void* buffer)
{
  // Never a failure for HDF5 (the owner records it): HDF5 1.10 cannot recover from one.
  fileOf(file)->owner->write(address, size, buffer);
  return 0;
}

herr_t flushFile(H5FD_t*, hid_t, hbool_t)
{
  return 0;
}

herr_t truncateFile(H5FD_t* file, hid_t, hbool_t)
{
  RollbackFile* f = fileOf(file);
  if (f->owner->endOfFile() != f->endOfAddress)
  {
    f->owner->truncate(f->endOfAddress);
  }
  return 0;
}

const H5FD_class_t RollbackDriver = {"canopy_step_rollback",
                                     MaximumAddress,
                                     H5F_CLOSE_WEAK,
                                     nullptr, // terminate
                                     nullptr, // sb_size
                                     nullptr, // sb_encode
                                     nullptr, // sb_decode
                                     sizeof(DriverInfo),
                                     nullptr, // fapl_get
                                     nullptr, // fapl_copy: HDF5 copies the bytes
                                     nullptr, // fapl_free
                                     0,
                                     nullptr, // dxpl_copy
                                     nullptr, // dxpl_free
                                     openFile,
                                     closeFile,
                                     compareFiles,
                                     queryFeatures,
                                     nullptr, // get_type_map
                                     nullptr, // alloc: HDF5 allocates from the end of address
                                     nullptr, // free
                                     endOfAddress,
                                     setEndOfAddress,
                                     endOfFile,
                                     handleOf,
                                     readFile,
                                     writeFile,
                                     flushFile,
                                     truncateFile,
                                     nullptr, // lock
                                     nullptr, // unlock
                                     H5FD_FLMAP_DICHOTOMY};

hid_t driverId()
{
  static const hid_t id = H5FDregister(&RollbackDriver);
  return id;
}

} // namespace

StepRollback::StepRollback(std::string path) : Path(std::move(path)) {}

StepRollback::~StepRollback()
{
  if (this->Descriptor >= 0)
  {
    ::close(this->Descriptor);
  }
  if (this->Owed)
  {
    this->putBack(); // a last try; nobody is left to tell if it fails
  }
}

std::string StepRollback::begin()
{
  if (this->Owed)
  {
    const std::string problem = this->putBack();
    if (!problem.empty())
    {
      return "an earlier failed step is still to be undone in " + this->Path + ": " + problem;
    }
  }
  struct stat st;
  this->BaseSize = ::stat(this->Path.c_str(), &st) == 0 ? st.st_size : 0;
  this->Created = false;
  this->Touched = false;
  this->End = 0;
  this->Failure.clear();
  this->Saved.clear();
  this->InMemory.clear();
  return {};
}

hid_t StepRollback::fileAccess()
{
  const hid_t access = H5Pcreate(H5P_FILE_ACCESS);
  const DriverInfo info{this};
  if (access < 0 || driverId() < 0 || H5Pset_driver(access, driverId(), &info) < 0)
  {
    if (access >= 0)
    {
      H5Pclose(access);
    }
    return H5I_INVALID_HID;
  }
  return access;
}

void StepRollback::opened(int descriptor, std::int64_t size, bool created)
{
  // HDF5 may open a file twice while creating it (first without truncating).
  this->Descriptor = descriptor;
  this->Touched = true;
  this->End = static_cast<std::uint64_t>(size);
  if (created)
  {
    this->Created = true;
    this->Saved.clear();
  }
}

void StepRollback::fail(const std::string& what, int error)
{
  if (this->Failure.empty())
  {
    this->Failure = what + ": " + errorText(error);
  }
}

StepRollback::Page StepRollback::pageFromDisk(std::uint64_t page) const
{
  Page bytes(PageSize, 0);
  if (this->Descriptor >= 0 && !readAll(this->Descriptor, bytes.data(), PageSize, page * PageSize))
  {
    std::fill(bytes.begin(), bytes.end(), 0);
  }
  return bytes;
}

bool StepRollback::keepOriginals(std::uint64_t address, std::size_t size)
{
  if (this->Created || size == 0)
  {
    return true;
  }
  const auto base = static_cast<std::uint64_t>(this->BaseSize);
  const std::uint64_t last = std::min(address + size, base);
  for (std::uint64_t page = address / PageSize; page * PageSize < last; ++page)
  {
    if (this->Saved.count(page) != 0)
    {
      continue;
    }
    Page bytes(PageSize, 0);
    if (!readAll(this->Descriptor, bytes.data(), PageSize, page * PageSize))
    {
      this->fail("reading the file's earlier bytes at offset " + std::to_string(page * PageSize),
                 errno);
      return false;
    }
    this->Saved.emplace(page, std::move(bytes));
  }
  return true;
}

void StepRollback::remember(std::uint64_t address, std::size_t size, const void* buffer)
{
  const auto* bytes = static_cast<const unsigned char*>(buffer);
  std::uint64_t at = address;
  const std::uint64_t end = address + size;
  while (at < end)
  {
    const std::uint64_t page = at / PageSize;
    auto found = this->InMemory.find(page);
    if (found == this->InMemory.end())
    {
      found = this->InMemory.emplace(page, this->pageFromDisk(page)).first;
    }
    const std::uint64_t within = at - page * PageSize;
    const std::uint64_t count = std::min<std::uint64_t>(PageSize - within, end - at);
    std::memcpy(found->second.data() + within, bytes + (at - address), count);
    at += count;
  }
  this->End = std::max(this->End, end);
}

bool StepRollback::write(std::uint64_t address, std::size_t size, const void* buffer)
{
  if (this->failed() || !this->keepOriginals(address, size))
  {
    this->remember(address, size, buffer);
    return false;
  }
  if (!writeAll(this->Descriptor, static_cast<const unsigned char*>(buffer), size, address))
  {
    this->fail("writing " + std::to_string(size) + " bytes at offset " + std::to_string(address),
               errno);
    // Part of it may be on the disk: memory holds all of it for later reads.
    this->remember(address, size, buffer);
    return false;
  }
  this->End = std::max(this->End, address + size);
  return true;
}

bool StepRollback::read(std::uint64_t address, std::size_t size, void* buffer) const
{
  auto* bytes = static_cast<unsigned char*>(buffer);
  if (this->InMemory.empty())
  {
    return readAll(this->Descriptor, bytes, size, address);
  }
  std::uint64_t at = address;
  const std::uint64_t end = address + size;
  while (at < end)
  {
    const std::uint64_t page = at / PageSize;
    const std::uint64_t within = at - page * PageSize;
    const std::uint64_t count = std::min<std::uint64_t>(PageSize - within, end - at);
    const auto found = this->InMemory.find(page);
    if (found != this->InMemory.end())
    {
      std::memcpy(bytes + (at - address), found->second.data() + within, count);
    }
    else if (!readAll(this->Descriptor, bytes + (at - address), count, at))
    {
      return false;
    }
    at += count;
  }
  return true;
}

bool StepRollback::truncate(std::uint64_t size)
{
  // HDF5 cuts the file where its space ends, which freeing the last blocks can
  // move below the step's start: those bytes are kept first.
  const auto base = static_cast<std::uint64_t>(this->BaseSize);
  if (!this->failed() && size < base && !this->keepOriginals(size, base - size))
  {
    this->End = size;
    return false;
  }
  if (!this->failed() && ::ftruncate(this->Descriptor, static_cast<off_t>(size)) != 0)
  {
    this->fail("setting the file's size to " + std::to_string(size), errno);
  }
  this->End = size;
  return !this->failed();
}

void StepRollback::closing()
{
  if (this->Descriptor >= 0 && ::close(this->Descriptor) != 0)
  {
    this->fail("closing the file", errno);
  }
  this->Descriptor = -1;
}

std::string StepRollback::keep()
{
  if (!this->failed())
  {
    const int descriptor = ::open(this->Path.c_str(), O_RDONLY | O_CLOEXEC);
    if (descriptor < 0 || ::fsync(descriptor) != 0)
    {
      this->fail("making the step durable (fsync)", errno);
    }
    if (descriptor >= 0)
    {
      ::close(descriptor);
    }
  }
  if (this->failed())
  {
    const std::string undone = this->undo();
    return this->Failure + (undone.empty() ? "" : "; undoing the step: " + undone);
  }
  this->Saved.clear();
  return {};
}

std::string StepRollback::undo()
{
  this->Owed = true;
  return this->putBack();
}

std::string StepRollback::putBack()
{
  this->InMemory.clear();
  if (!this->Touched)
  {
    this->Owed = false; // the step never opened the file
    return {};
  }
  if (this->Created)
  {
    if (::unlink(this->Path.c_str()) != 0 && errno != ENOENT)
    {
      return "removing the file the step created: " + errorText(errno);
    }
    this->Owed = false;
    return {};
  }
  const int descriptor = ::open(this->Path.c_str(), O_WRONLY | O_CLOEXEC);
  if (descriptor < 0)
  {
    return "opening the file: " + errorText(errno);
  }
  std::string problem;
  const auto base = static_cast<std::uint64_t>(this->BaseSize);
  for (const auto& [page, bytes] : this->Saved)
  {
    const std::uint64_t at = page * PageSize;
    const std::size_t count =
        static_cast<std::size_t>(std::min<std::uint64_t>(PageSize, base - at));
    if (!writeAll(descriptor, bytes.data(), count, at))
    {
      problem = "writing back " + std::to_string(count) + " bytes at offset " + std::to_string(at) +
                ": " + errorText(errno);
      break;
    }
  }
  if (problem.empty() && ::ftruncate(descriptor, static_cast<off_t>(base)) != 0)
  {
    problem = "cutting the file back to " + std::to_string(base) + " bytes: " + errorText(errno);
  }
  if (problem.empty() && ::fsync(descriptor) != 0)
  {
    problem = "making the undo durable (fsync): " + errorText(errno);
  }
  if (::close(descriptor) != 0 && problem.empty())
  {
    problem = "closing the file: " + errorText(errno);
  }
  if (problem.empty())
  {
    this->Saved.clear();
    this->Owed = false;
  }
  return problem;
}

} // namespace canopy::io
