// One step's writes to an HDF5 file, kept undoable byte for byte, through a
// file driver of Canopy's own (an HDF5 virtual file driver over POSIX I/O).
//
// Why: HDF5 cannot take back a step that failed half-way. Its own way out
// (shrinking datasets, closing) writes metadata again on the disk that just
// failed, and a failed close leaves HDF5 1.10 unable to release the file; in
// parallel, a metadata write failing on some ranks only hangs every rank in the
// cache's sync point (docs/testing.md). So the file is written by one process,
// and the driver never lets HDF5 see a failure:
// - before it overwrites a page the file had when the step began, it keeps the
//   page's bytes (the step's undo); what lies beyond the old end is new;
// - the first write that fails is recorded (failure()), and from then on writes
//   go to memory (later reads see them) so HDF5 finishes and closes normally;
// - after H5Fclose, keep() makes the step durable (fsync) and undo() puts the
//   kept pages back and cuts the file to its old size (or removes a file the
//   step created). An undo the disk refuses is retried at the next begin(),
//   before anything else is written.
// Tested by StepRollback.* (tests/unit) and, with writes failing under HDF5 at
// each kind of write, by insitu.vtkhdf.fault_* (docs/testing.md).
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace canopy::io
{

class StepRollback
{
public:
  /// `path`: the file this rollback guards; each step opens it through fileAccess().
  explicit StepRollback(std::string path);
  ~StepRollback();
  StepRollback(const StepRollback&) = delete;
  StepRollback& operator=(const StepRollback&) = delete;

  /// Starts a step: first finishes an undo an earlier step still owes. "" or
  /// why the file cannot be written now (then nothing was touched).
  std::string begin();
  /// A file access property list (owned by the caller: H5Pclose it) that opens
  /// or creates the file through this rollback's driver. Valid between begin()
  /// and keep()/undo().
  hid_t fileAccess();

  /// Whether a write of this step failed (then the step's data is in memory
  /// only), and how: "writing 4096 bytes at offset 81920: Input/output error".
  bool failed() const { return !this->Failure.empty(); }
  const std::string& failure() const { return this->Failure; }

  /// After H5Fclose: makes the step's writes durable (fsync), forgets the
  /// undo. "" or why not (the step is then undone as well).
  std::string keep();
  /// After H5Fclose (or if the file was never opened): puts the file back as
  /// it was at begin(). "" or why not (retried at the next begin()).
  std::string undo();
  /// Whether an undo is still owed to the file.
  bool undoOwed() const { return this->Owed; }

  /// Bytes of the file's earlier content this step has kept for its undo.
  std::size_t keptBytes() const { return this->Saved.size() * PageSize; }

  // ---- for the driver (StepRollback.cxx) ----
  static constexpr std::size_t PageSize = 4096;
  /// The file was opened: `descriptor` (borrowed until closed), its size when
  /// opened, and whether opening emptied or made it (then undo removes it).
  void opened(int descriptor, std::int64_t size, bool created);
  bool write(std::uint64_t address, std::size_t size, const void* buffer);
  bool read(std::uint64_t address, std::size_t size, void* buffer) const;
  bool truncate(std::uint64_t size);
  void closing();
  std::uint64_t endOfFile() const { return this->End; }

private:
  using Page = std::vector<unsigned char>;
  bool keepOriginals(std::uint64_t address, std::size_t size);
  void remember(std::uint64_t address, std::size_t size, const void* buffer);
  void fail(const std::string& what, int error);
  Page pageFromDisk(std::uint64_t page) const;
  std::string putBack();

  std::string Path;
  int Descriptor = -1;
  std::int64_t BaseSize = 0; ///< the file's size at begin()
  bool Created = false;      ///< the step made or emptied the file
  bool Touched = false;      ///< the step opened the file
  bool Owed = false;         ///< an undo is due (failed or not yet done)
  std::uint64_t End = 0;     ///< the file's size as HDF5 sees it
  std::string Failure;
  std::map<std::uint64_t, Page> Saved;    ///< page -> its bytes at begin()
  std::map<std::uint64_t, Page> InMemory; ///< after a failure: page -> what HDF5 wrote
};

} // namespace canopy::io
