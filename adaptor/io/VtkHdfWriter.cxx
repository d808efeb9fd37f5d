#include "VtkHdfWriter.h"

#include "CellArrayBlocks.h"
#include "CellArraySelection.h"
#include "HdfHandle.h"
#include "HyperTreeGridPiece.h"
#include "RankAgreement.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkHyperTreeGrid.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <map>
#include <numeric>
#include <sstream>

namespace canopy::io
{
namespace
{

// VTKHDF 2.4 is the first version with the HyperTreeGrid layout.
constexpr std::int64_t FormatVersion[2] = {2, 4};
const char* const GhostArray = vtkDataSetAttributes::GhostArrayName();

/// A cell array of the file: name, VTK value type, components.
struct ArraySpec
{
  std::string name;
  int type = VTK_DOUBLE;
  int components = 1;
};

/// What a dataset of the series grows by each step, per piece.
enum class Kind
{
  PerPiece,        // NumberOfTrees, NumberOfCells, NumberOfDepths, DescriptorsSize
  PerTree,         // TreeIds, DepthPerTree
  PerDepth,        // NumberOfCellsPerTreeDepth
  DescriptorBytes, // Descriptors: each piece from a new byte
  MaskBytes,       // Mask: likewise
  Coordinate,      // X/Y/ZCoordinates: one copy of the axis per piece
  PerCell          // CellData/<name>
};

/// Sizes of everything a step adds, over all ranks, and this rank's offsets within it.
struct StepShape
{
  int pieces = 1;
  int rank = 0;
  std::vector<std::int64_t> trees, cells, depths, descriptorBits;
  std::array<std::int64_t, 3> dimensions = {1, 1, 1};
  std::int64_t dataBytes = 0; // the step's data, all ranks

  static std::int64_t bytes(std::int64_t bits) { return (bits + 7) / 8; }
  /// Rows a dataset of `kind` grows by (axis: the coordinate axis).
  std::int64_t total(Kind kind, int axis = 0) const
  {
    return this->prefix(kind, this->pieces, axis);
  }
  /// Rows of the ranks before `rank`: where this rank writes within the step.
  std::int64_t prefix(Kind kind, int rank, int axis = 0) const
  {
    std::int64_t sum = 0;
    for (int r = 0; r < rank; ++r)
    {
      sum += this->rows(kind, r, axis);
    }
    return sum;
  }
  std::int64_t rows(Kind kind, int r, int axis = 0) const
  {
    const auto i = static_cast<std::size_t>(r);
    switch (kind)
    {
    case Kind::PerPiece:
      return 1;
    case Kind::PerTree:
      return this->trees[i];
    case Kind::PerDepth:
      return this->depths[i];
    case Kind::DescriptorBytes:
      return bytes(this->descriptorBits[i]);
    case Kind::MaskBytes:
      return bytes(this->cells[i]);
    case Kind::Coordinate:
      return this->dimensions[static_cast<std::size_t>(axis)];
    case Kind::PerCell:
      return this->cells[i];
    }
    return 0;
  }
};

/// A growing dataset of /VTKHDF and its Steps offsets dataset.
struct Series
{
  std::string path;    // under /VTKHDF
  std::string offsets; // under /VTKHDF/Steps ("" for the per-piece metadata)
  Kind kind;
  int axis = 0;
  hid_t fileType;
  int columns = 1;
  HdfHandle dataset;
  std::int64_t committed = 0; // rows holding the file's steps
};

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

/// The VTK type of a dataset's values, from its HDF5 type (for a file written earlier).
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

std::string describe(const ArraySpec& spec)
{
  return spec.name + "\t" + std::to_string(spec.type) + "\t" + std::to_string(spec.components);
}

/// Chunk rows for a dataset: about `target` bytes, at least `minimum` rows, and
/// no larger than the first step needs (small runs make small files).
hsize_t chunkRows(std::int64_t firstStepRows, std::size_t rowBytes, std::size_t target,
                  hsize_t minimum)
{
  const hsize_t byTarget = std::max<hsize_t>(1, target / std::max<std::size_t>(1, rowBytes));
  const hsize_t wanted = std::max<hsize_t>(minimum, static_cast<hsize_t>(firstStepRows));
  return std::max<hsize_t>(1, std::min(wanted, std::max(minimum, byTarget)));
}

/// Why a step of `bytes` bytes will not fit where `file` goes ("" if it will):
/// the data, 5 % for chunks a step leaves partly filled, 2 MiB for metadata.
std::string freeSpaceProblem(const std::string& file, std::int64_t bytes)
{
  std::filesystem::path folder = std::filesystem::path(file).parent_path();
  std::error_code error;
  const std::filesystem::space_info space =
      std::filesystem::space(folder.empty() ? "." : folder, error);
  if (error)
  {
    return {}; // not knowable here: the write itself will tell
  }
  const std::int64_t needed = bytes + bytes / 20 + (std::int64_t(2) << 20);
  if (static_cast<std::uintmax_t>(needed) <= space.available)
  {
    return {};
  }
  std::ostringstream text;
  text << "not enough free space in " << (folder.empty() ? "." : folder.string())
       << ": the step needs about " << (needed >> 10) << " KiB, " << (space.available >> 10)
       << " KiB are free";
  return text.str();
}

/// The writer's state for one step: the open file and its growing datasets.
class StepFile
{
public:
  StepFile(MPI_Comm communicator, const std::string& name) : Communicator(communicator), Name(name)
  {
  }

  std::string open(bool create)
  {
    HdfHandle access = propertyHandle(H5Pcreate(H5P_FILE_ACCESS));
    if (this->Communicator != MPI_COMM_NULL)
    {
      H5Pset_fapl_mpio(access.get(), this->Communicator, MPI_INFO_NULL);
      // Metadata read once and broadcast, written collectively: fewer small I/Os.
      H5Pset_all_coll_metadata_ops(access.get(), true);
      H5Pset_coll_metadata_write(access.get(), true);
    }
    this->File =
        fileHandle(create ? H5Fcreate(this->Name.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get())
                          : H5Fopen(this->Name.c_str(), H5F_ACC_RDWR, access.get()));
    if (!this->File.valid())
    {
      return std::string(create ? "cannot create " : "cannot open ") + this->Name + ": " +
             hdfErrorText();
    }
    return {};
  }

  hid_t file() const { return this->File.get(); }
  bool close() { return this->File.reset(); }

private:
  MPI_Comm Communicator;
  std::string Name;
  HdfHandle File;
};

/// Reads `count` int64 values of a 1D dataset from `first` (false on error).
bool readInt64(hid_t dataset, std::int64_t first, std::int64_t count, std::int64_t* values)
{
  if (count == 0)
  {
    return true;
  }
  HdfHandle space = spaceHandle(H5Dget_space(dataset));
  const hsize_t start = static_cast<hsize_t>(first), rows = static_cast<hsize_t>(count);
  HdfHandle memory = spaceHandle(H5Screate_simple(1, &rows, nullptr));
  return space.valid() && memory.valid() &&
         H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, &start, nullptr, &rows, nullptr) >= 0 &&
         H5Dread(dataset, H5T_NATIVE_INT64, memory.get(), space.get(), H5P_DEFAULT, values) >= 0;
}

std::int64_t currentRows(hid_t dataset)
{
  HdfHandle space = spaceHandle(H5Dget_space(dataset));
  hsize_t dims[2] = {0, 0};
  if (!space.valid() || H5Sget_simple_extent_dims(space.get(), dims, nullptr) < 0)
  {
    return -1;
  }
  return static_cast<std::int64_t>(dims[0]);
}

} // namespace

struct VtkHdfWriter::Implementation
{
  MPI_Comm Communicator;
  std::string FileName;
  VtkHdfWriterOptions Options;
  bool Started = false; // a step of this run reached the file (later steps append)
  std::int64_t Steps = 0;

  // ---- per step --------------------------------------------------------------------------
  std::vector<Series> Data;    // /VTKHDF datasets, CellData included
  std::vector<Series> Offsets; // /VTKHDF/Steps datasets (Values, PartOffsets, ...)
  std::vector<ArraySpec> Arrays;

  std::string where(std::int64_t step, double time) const
  {
    std::ostringstream text;
    text << "VTKHDF extract " << this->FileName << ": step ";
    if (step >= 0)
    {
      text << step << " ";
    }
    text << "(time " << time << ") not written";
    return text.str();
  }

  // Throws the same WriteError on every rank when any rank has a problem.
  void agree(const std::string& localProblem, const std::string& context, StepFile* file)
  {
    const std::string problems = gatherProblems(this->Communicator, localProblem);
    if (problems.empty())
    {
      return;
    }
    std::string restore;
    if (file != nullptr)
    {
      restore = this->rollBack(*file);
    }
    throw WriteError(context + ": " + problems +
                     (restore.empty() ? "" : "; restoring the earlier steps: " + restore));
  }

  /// Shrinks every dataset back to the rows of the file's steps and closes the
  /// file. Collective. Returns what went wrong, if anything.
  std::string rollBack(StepFile& file)
  {
    std::string local;
    for (std::vector<Series>* group : {&this->Data, &this->Offsets})
    {
      for (Series& series : *group)
      {
        if (!series.dataset.valid())
        {
          continue;
        }
        hsize_t dims[2] = {static_cast<hsize_t>(series.committed),
                           static_cast<hsize_t>(series.columns)};
        if (H5Dset_extent(series.dataset.get(), dims) < 0 && local.empty())
        {
          local = series.path + ": " + hdfErrorText();
        }
        series.dataset.reset();
      }
    }
    if (!file.close() && local.empty())
    {
      local = "closing: " + hdfErrorText();
    }
    return gatherProblems(this->Communicator, local);
  }

  // ---- layout ----------------------------------------------------------------------------
  void declareSeries(const std::vector<ArraySpec>& arrays)
  {
    this->Data.clear();
    this->Offsets.clear();
    auto add = [this](std::string path, std::string offsets, Kind kind, hid_t type, int columns = 1,
                      int axis = 0) {
      this->Data.push_back({std::move(path), std::move(offsets), kind, axis, type, columns, {}, 0});
    };
    add("NumberOfTrees", "", Kind::PerPiece, H5T_STD_I64LE);
    add("NumberOfCells", "", Kind::PerPiece, H5T_STD_I64LE);
    add("NumberOfDepths", "", Kind::PerPiece, H5T_STD_I64LE);
    add("DescriptorsSize", "", Kind::PerPiece, H5T_STD_I64LE);
    add("TreeIds", "TreeIdsOffsets", Kind::PerTree, H5T_STD_I64LE);
    add("DepthPerTree", "DepthPerTreeOffsets", Kind::PerTree, H5T_STD_I64LE);
    add("NumberOfCellsPerTreeDepth", "NumberOfCellsPerTreeDepthOffsets", Kind::PerDepth,
        H5T_STD_I64LE);
    add("Descriptors", "DescriptorsOffsets", Kind::DescriptorBytes, H5T_STD_U8LE);
    add("Mask", "MaskOffsets", Kind::MaskBytes, H5T_STD_U8LE);
    add("XCoordinates", "XCoordinatesOffsets", Kind::Coordinate, H5T_IEEE_F64LE, 1, 0);
    add("YCoordinates", "YCoordinatesOffsets", Kind::Coordinate, H5T_IEEE_F64LE, 1, 1);
    add("ZCoordinates", "ZCoordinatesOffsets", Kind::Coordinate, H5T_IEEE_F64LE, 1, 2);
    for (const ArraySpec& spec : arrays)
    {
      add("CellData/" + spec.name, "CellDataOffsets/" + spec.name, Kind::PerCell,
          fileTypeOf(spec.type), spec.components);
    }
    auto step = [this](std::string path, hid_t type) {
      this->Offsets.push_back({std::move(path), "", Kind::PerPiece, 0, type, 1, {}, 0});
    };
    step("Values", H5T_IEEE_F64LE);
    step("PartOffsets", H5T_STD_I64LE);
    step("NumberOfParts", H5T_STD_I64LE);
    for (const Series& series : this->Data)
    {
      if (!series.offsets.empty())
      {
        step(series.offsets, H5T_STD_I64LE);
      }
    }
  }

  /// Creates the file's groups, attributes and empty datasets. Collective.
  std::string create(hid_t file, vtkHyperTreeGrid* htg, const StepShape& shape)
  {
    HdfHandle root = groupHandle(H5Gcreate2(file, "VTKHDF", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
    if (!root.valid())
    {
      return "cannot create /VTKHDF: " + hdfErrorText();
    }
    const std::int64_t branchFactor = htg != nullptr ? htg->GetBranchFactor() : 2;
    const int dimensions[3] = {static_cast<int>(shape.dimensions[0]),
                               static_cast<int>(shape.dimensions[1]),
                               static_cast<int>(shape.dimensions[2])};
    const int transposed = htg != nullptr && htg->GetTransposedRootIndexing() ? 1 : 0;
    if (!writeAttribute(root.get(), "Version", H5T_STD_I64LE, H5T_NATIVE_INT64, 2, FormatVersion) ||
        !writeStringAttribute(root.get(), "Type", "HyperTreeGrid") ||
        !writeAttribute(root.get(), "BranchFactor", H5T_STD_I64LE, H5T_NATIVE_INT64, 0,
                        &branchFactor) ||
        !writeAttribute(root.get(), "Dimensions", H5T_STD_I32LE, H5T_NATIVE_INT, 3, dimensions) ||
        !writeAttribute(root.get(), "TransposedRootIndexing", H5T_STD_I32LE, H5T_NATIVE_INT, 0,
                        &transposed))
    {
      return "cannot write the attributes of /VTKHDF: " + hdfErrorText();
    }
    for (const char* group : {"VTKHDF/CellData", "VTKHDF/Steps", "VTKHDF/Steps/CellDataOffsets"})
    {
      HdfHandle created =
          groupHandle(H5Gcreate2(file, group, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
      if (!created.valid())
      {
        return std::string("cannot create /") + group + ": " + hdfErrorText();
      }
    }
    const std::int64_t noSteps = 0;
    HdfHandle steps = groupHandle(H5Gopen2(file, "VTKHDF/Steps", H5P_DEFAULT));
    if (!writeAttribute(steps.get(), "NSteps", H5T_STD_I64LE, H5T_NATIVE_INT64, 0, &noSteps))
    {
      return "cannot write /VTKHDF/Steps/NSteps: " + hdfErrorText();
    }
    for (Series& series : this->Data)
    {
      const std::size_t valueBytes = H5Tget_size(series.fileType);
      const std::size_t rowBytes = valueBytes * static_cast<std::size_t>(series.columns);
      hsize_t chunk = 0;
      switch (series.kind)
      {
      case Kind::PerPiece:
        chunk = chunkRows(shape.pieces, rowBytes, 1 << 12, 64);
        break;
      case Kind::PerTree:
      case Kind::PerDepth:
        chunk = chunkRows(shape.total(series.kind), rowBytes, 1 << 20, 256);
        break;
      case Kind::Coordinate:
        chunk = chunkRows(shape.total(series.kind, series.axis), rowBytes, 1 << 16, 64);
        break;
      default:
        chunk = chunkRows(shape.total(series.kind), rowBytes, 1 << 20, 1024);
        break;
      }
      series.dataset =
          createDataset(file, "VTKHDF/" + series.path, series.fileType, series.columns, chunk);
      if (!series.dataset.valid())
      {
        return "cannot create /VTKHDF/" + series.path + ": " + hdfErrorText();
      }
    }
    for (Series& series : this->Offsets)
    {
      series.dataset = createDataset(file, "VTKHDF/Steps/" + series.path, series.fileType, 1, 64);
      if (!series.dataset.valid())
      {
        return "cannot create /VTKHDF/Steps/" + series.path + ": " + hdfErrorText();
      }
    }
    return {};
  }

  static HdfHandle createDataset(hid_t file, const std::string& path, hid_t type, int columns,
                                 hsize_t chunkRows)
  {
    const int rank = columns > 1 ? 2 : 1;
    const hsize_t dims[2] = {0, static_cast<hsize_t>(columns)};
    const hsize_t maxDims[2] = {H5S_UNLIMITED, static_cast<hsize_t>(columns)};
    const hsize_t chunk[2] = {chunkRows, static_cast<hsize_t>(columns)};
    HdfHandle space = spaceHandle(H5Screate_simple(rank, dims, maxDims));
    HdfHandle properties = propertyHandle(H5Pcreate(H5P_DATASET_CREATE));
    H5Pset_chunk(properties.get(), rank, chunk);
    // Every value is written: no fill pass over new chunks.
    H5Pset_fill_time(properties.get(), H5D_FILL_TIME_NEVER);
    return datasetHandle(H5Dcreate2(file, path.c_str(), type, space.get(), H5P_DEFAULT,
                                    properties.get(), H5P_DEFAULT));
  }

  static bool writeAttribute(hid_t object, const char* name, hid_t fileType, hid_t memoryType,
                             hsize_t count, const void* values)
  {
    HdfHandle space =
        spaceHandle(count == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &count, nullptr));
    HdfHandle attribute = attributeHandle(
        H5Aexists(object, name) > 0
            ? H5Aopen(object, name, H5P_DEFAULT)
            : H5Acreate2(object, name, fileType, space.get(), H5P_DEFAULT, H5P_DEFAULT));
    return attribute.valid() && H5Awrite(attribute.get(), memoryType, values) >= 0;
  }

  static bool writeStringAttribute(hid_t object, const char* name, const std::string& value)
  {
    // Fixed length, as VTK's own writer stores Type.
    HdfHandle type = typeHandle(H5Tcopy(H5T_C_S1));
    H5Tset_size(type.get(), value.size());
    H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
    HdfHandle space = spaceHandle(H5Screate(H5S_SCALAR));
    HdfHandle attribute = attributeHandle(
        H5Acreate2(object, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT));
    return attribute.valid() && H5Awrite(attribute.get(), type.get(), value.data()) >= 0;
  }

  /// Opens a file written before: checks it holds this grid's kind, reads its
  /// arrays and how many rows of each dataset its steps hold.
  std::string reopen(hid_t file, const StepShape& shape, std::int64_t branchFactor)
  {
    HdfHandle root = groupHandle(H5Gopen2(file, "VTKHDF", H5P_DEFAULT));
    if (!root.valid())
    {
      return "no /VTKHDF group (not a VTKHDF file)";
    }
    if (!hasType(root.get(), "HyperTreeGrid"))
    {
      return "/VTKHDF is not of Type HyperTreeGrid";
    }
    std::int64_t fileBranchFactor = 0;
    int fileDimensions[3] = {0, 0, 0};
    if (!readAttribute(root.get(), "BranchFactor", H5T_NATIVE_INT64, &fileBranchFactor) ||
        !readAttribute(root.get(), "Dimensions", H5T_NATIVE_INT, fileDimensions))
    {
      return "cannot read BranchFactor and Dimensions: " + hdfErrorText();
    }
    if (fileBranchFactor != branchFactor || fileDimensions[0] != shape.dimensions[0] ||
        fileDimensions[1] != shape.dimensions[1] || fileDimensions[2] != shape.dimensions[2])
    {
      std::ostringstream text;
      text << "the file holds a grid of branch factor " << fileBranchFactor << " and dimensions "
           << fileDimensions[0] << "x" << fileDimensions[1] << "x" << fileDimensions[2]
           << ", this one has " << branchFactor << " and " << shape.dimensions[0] << "x"
           << shape.dimensions[1] << "x" << shape.dimensions[2];
      return text.str();
    }
    // The file's arrays decide what is written.
    std::vector<ArraySpec> arrays;
    HdfHandle cellData = groupHandle(H5Gopen2(file, "VTKHDF/CellData", H5P_DEFAULT));
    if (!cellData.valid())
    {
      return "no /VTKHDF/CellData group";
    }
    std::vector<std::string> names;
    H5Literate(
        cellData.get(), H5_INDEX_NAME, H5_ITER_INC, nullptr,
        [](hid_t, const char* name, const H5L_info_t*, void* data)
        {
          static_cast<std::vector<std::string>*>(data)->emplace_back(name);
          return herr_t(0);
        },
        &names);
    for (const std::string& name : names)
    {
      HdfHandle dataset = datasetHandle(H5Dopen2(cellData.get(), name.c_str(), H5P_DEFAULT));
      HdfHandle type = typeHandle(H5Dget_type(dataset.get()));
      HdfHandle space = spaceHandle(H5Dget_space(dataset.get()));
      hsize_t dims[2] = {0, 1};
      const int rank = H5Sget_simple_extent_dims(space.get(), dims, nullptr);
      if (!dataset.valid() || rank < 1)
      {
        return "cannot open /VTKHDF/CellData/" + name;
      }
      arrays.push_back({name, vtkTypeOf(type.get()), rank > 1 ? static_cast<int>(dims[1]) : 1});
    }
    this->Arrays = arrays;
    this->declareSeries(arrays);
    for (Series& series : this->Data)
    {
      series.dataset =
          datasetHandle(H5Dopen2(file, ("VTKHDF/" + series.path).c_str(), H5P_DEFAULT));
      if (!series.dataset.valid())
      {
        return "cannot open /VTKHDF/" + series.path + ": " + hdfErrorText();
      }
    }
    for (Series& series : this->Offsets)
    {
      series.dataset =
          datasetHandle(H5Dopen2(file, ("VTKHDF/Steps/" + series.path).c_str(), H5P_DEFAULT));
      if (!series.dataset.valid())
      {
        return "cannot open /VTKHDF/Steps/" + series.path + ": " + hdfErrorText();
      }
    }
    HdfHandle steps = groupHandle(H5Gopen2(file, "VTKHDF/Steps", H5P_DEFAULT));
    std::int64_t nSteps = 0;
    if (!readAttribute(steps.get(), "NSteps", H5T_NATIVE_INT64, &nSteps) || nSteps < 0)
    {
      return "cannot read /VTKHDF/Steps/NSteps: " + hdfErrorText();
    }
    this->Steps = nSteps;
    return this->readCommittedRows();
  }

  /// How many rows of each dataset the file's steps use: the last step's offsets
  /// plus what its pieces hold. Rows beyond (a step that failed or was cut short)
  /// are dropped before the next step is added.
  std::string readCommittedRows()
  {
    for (Series& series : this->Offsets)
    {
      series.committed = this->Steps;
    }
    if (this->Steps == 0)
    {
      for (Series& series : this->Data)
      {
        series.committed = 0;
      }
      return {};
    }
    const std::int64_t last = this->Steps - 1;
    auto offset = [&](const std::string& name, std::int64_t& value)
    {
      for (const Series& series : this->Offsets)
      {
        if (series.path == name)
        {
          return readInt64(series.dataset.get(), last, 1, &value);
        }
      }
      return false;
    };
    std::int64_t partOffset = 0, parts = 0;
    if (!offset("PartOffsets", partOffset) || !offset("NumberOfParts", parts) || parts < 0)
    {
      return "cannot read the last step's PartOffsets and NumberOfParts";
    }
    StepShape lastStep;
    lastStep.pieces = static_cast<int>(parts);
    std::vector<std::int64_t>* perPiece[4] = {&lastStep.trees, &lastStep.cells, &lastStep.depths,
                                              &lastStep.descriptorBits};
    for (int i = 0; i < 4; ++i)
    {
      perPiece[i]->resize(static_cast<std::size_t>(parts));
      if (!readInt64(this->Data[static_cast<std::size_t>(i)].dataset.get(), partOffset, parts,
                     perPiece[i]->data()))
      {
        return "cannot read the last step's " + this->Data[static_cast<std::size_t>(i)].path;
      }
    }
    for (Series& series : this->Data)
    {
      if (series.kind == Kind::PerPiece)
      {
        series.committed = partOffset + parts;
        continue;
      }
      std::int64_t start = 0;
      if (!offset(series.offsets, start))
      {
        return "cannot read Steps/" + series.offsets;
      }
      // (Coordinates: one copy of the axis per piece, of the file's Dimensions,
      // which reopen() found equal to this grid's.)
      lastStep.dimensions = this->Dimensions;
      series.committed = start + lastStep.total(series.kind, series.axis);
    }
    return {};
  }

  static bool hasType(hid_t object, const std::string& expected)
  {
    if (H5Aexists(object, "Type") <= 0)
    {
      return false;
    }
    HdfHandle attribute = attributeHandle(H5Aopen(object, "Type", H5P_DEFAULT));
    HdfHandle type = typeHandle(H5Aget_type(attribute.get()));
    if (!type.valid() || H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()))
    {
      return false;
    }
    std::string value(H5Tget_size(type.get()), '\0');
    if (H5Aread(attribute.get(), type.get(), value.data()) < 0)
    {
      return false;
    }
    value = value.c_str();
    return value == expected;
  }

  static bool readAttribute(hid_t object, const char* name, hid_t memoryType, void* values)
  {
    HdfHandle attribute = attributeHandle(H5Aopen(object, name, H5P_DEFAULT));
    return attribute.valid() && H5Aread(attribute.get(), memoryType, values) >= 0;
  }

  std::array<std::int64_t, 3> Dimensions = {1, 1, 1};

  // ---- one step --------------------------------------------------------------------------
  /// Grows every dataset by the step's rows. Collective (same sizes on every rank).
  std::string extend(std::vector<Series>& group, const StepShape& shape, bool steps)
  {
    for (Series& series : group)
    {
      const std::int64_t rows =
          series.committed + (steps ? 1 : shape.total(series.kind, series.axis));
      hsize_t dims[2] = {static_cast<hsize_t>(rows), static_cast<hsize_t>(series.columns)};
      if (H5Dset_extent(series.dataset.get(), dims) < 0)
      {
        return "cannot extend " + series.path + ": " + hdfErrorText();
      }
    }
    return {};
  }

  /// Writes `rows` rows at `first` from `values` (independent I/O: ranks write
  /// their own rows, in any number of calls).
  static std::string writeRows(const Series& series, std::int64_t first, std::int64_t rows,
                               hid_t memoryType, const void* values)
  {
    if (rows == 0)
    {
      return {};
    }
    HdfHandle space = spaceHandle(H5Dget_space(series.dataset.get()));
    const hsize_t start[2] = {static_cast<hsize_t>(first), 0};
    const hsize_t count[2] = {static_cast<hsize_t>(rows), static_cast<hsize_t>(series.columns)};
    const int rank = series.columns > 1 ? 2 : 1;
    HdfHandle memory = spaceHandle(H5Screate_simple(rank, count, nullptr));
    if (H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr) < 0 ||
        H5Dwrite(series.dataset.get(), memoryType, memory.get(), space.get(), H5P_DEFAULT, values) <
            0)
    {
      return "cannot write " + series.path + ": " + hdfErrorText();
    }
    return {};
  }

  std::string writePiece(const StepShape& shape, const HyperTreeGridPiece& piece,
                         vtkHyperTreeGrid* htg, const std::vector<vtkDataArray*>& arrays)
  {
    const int r = shape.rank;
    const std::int64_t perPiece[4] = {piece.numberOfTrees(), piece.numberOfCells,
                                      piece.numberOfDepths(), piece.descriptors.size()};
    std::size_t next = 0;
    for (Series& series : this->Data)
    {
      const std::int64_t first = series.committed + shape.prefix(series.kind, r, series.axis);
      std::string problem;
      switch (series.kind)
      {
      case Kind::PerPiece:
        problem = writeRows(series, first, 1, H5T_NATIVE_INT64, &perPiece[next++]);
        break;
      case Kind::PerTree:
        problem =
            writeRows(series, first, piece.numberOfTrees(), H5T_NATIVE_INT64,
                      series.path == "TreeIds" ? piece.treeIds.data() : piece.depthPerTree.data());
        break;
      case Kind::PerDepth:
        problem = writeRows(series, first, piece.numberOfDepths(), H5T_NATIVE_INT64,
                            piece.cellsPerTreeDepth.data());
        break;
      case Kind::DescriptorBytes:
        problem = writeRows(series, first, StepShape::bytes(piece.descriptors.size()),
                            H5T_NATIVE_UCHAR, piece.descriptors.bytes().data());
        break;
      case Kind::MaskBytes:
        problem = writeRows(series, first, StepShape::bytes(piece.numberOfCells), H5T_NATIVE_UCHAR,
                            piece.leafMask.bytes().data());
        break;
      case Kind::Coordinate:
        problem = this->writeCoordinates(series, first, htg);
        break;
      case Kind::PerCell:
        problem = this->writeCellArray(series, first, piece, arrays);
        break;
      }
      if (!problem.empty())
      {
        return problem;
      }
    }
    return {};
  }

  std::string writeCoordinates(const Series& series, std::int64_t first, vtkHyperTreeGrid* htg)
  {
    vtkDataArray* axis = series.axis == 0   ? htg->GetXCoordinates()
                         : series.axis == 1 ? htg->GetYCoordinates()
                                            : htg->GetZCoordinates();
    const std::int64_t length = this->Dimensions[static_cast<std::size_t>(series.axis)];
    std::vector<double> values(static_cast<std::size_t>(length), 0.0);
    for (std::int64_t i = 0; axis != nullptr && i < length && i < axis->GetNumberOfTuples(); ++i)
    {
      values[static_cast<std::size_t>(i)] = axis->GetComponent(i, 0);
    }
    return writeRows(series, first, length, H5T_NATIVE_DOUBLE, values.data());
  }

  std::string writeCellArray(const Series& series, std::int64_t first,
                             const HyperTreeGridPiece& piece,
                             const std::vector<vtkDataArray*>& arrays)
  {
    const std::string name = series.path.substr(std::string("CellData/").size());
    auto found = std::find_if(arrays.begin(), arrays.end(),
                              [&](vtkDataArray* a) { return name == a->GetName(); });
    if (found == arrays.end())
    {
      // Only the ghost array may be missing (a rank without other ranks' parts).
      std::vector<unsigned char> zeros(
          static_cast<std::size_t>(piece.numberOfCells * series.columns), 0);
      return writeRows(series, first, piece.numberOfCells, H5T_NATIVE_UCHAR, zeros.data());
    }
    vtkDataArray* array = *found;
    const hid_t memoryType = memoryTypeOf(array->GetDataType());
    std::string problem;
    std::int64_t row = first;
    CellArrayBlocks(array, piece.runs)
        .forEach(
            [&](const void* values, vtkIdType tuples)
            {
              if (problem.empty())
              {
                problem = writeRows(series, row, tuples, memoryType, values);
              }
              row += tuples;
            });
    return problem;
  }

  /// The step's row of every Steps dataset (rank 0 writes it).
  std::string writeStepRow(const StepShape& shape, double time)
  {
    for (Series& series : this->Offsets)
    {
      std::string problem;
      if (series.path == "Values")
      {
        problem = writeRows(series, series.committed, 1, H5T_NATIVE_DOUBLE, &time);
      }
      else
      {
        std::int64_t value = 0;
        if (series.path == "NumberOfParts")
        {
          value = shape.pieces;
        }
        else if (series.path == "PartOffsets")
        {
          value = this->Data[0].committed;
        }
        else
        {
          for (const Series& data : this->Data)
          {
            if (data.offsets == series.path)
            {
              value = data.committed;
            }
          }
        }
        problem = writeRows(series, series.committed, 1, H5T_NATIVE_INT64, &value);
      }
      if (!problem.empty())
      {
        return problem;
      }
    }
    return {};
  }
};

VtkHdfWriter::VtkHdfWriter(MPI_Comm communicator, std::string fileName, VtkHdfWriterOptions options)
    : Impl(std::make_unique<Implementation>())
{
  this->Impl->Communicator = communicator;
  this->Impl->FileName = std::move(fileName);
  this->Impl->Options = std::move(options);
}

VtkHdfWriter::~VtkHdfWriter() = default;

std::int64_t VtkHdfWriter::numberOfSteps() const
{
  return this->Impl->Steps;
}

const std::string& VtkHdfWriter::fileName() const
{
  return this->Impl->FileName;
}

void VtkHdfWriter::writeStep(vtkHyperTreeGrid* htg, std::int64_t step, double time)
{
  Implementation& impl = *this->Impl;
  const QuietHdfErrors quiet;
  const MPI_Comm communicator = impl.Communicator;
  const std::string context = impl.where(step, time);

  // ---- what this rank has, and what every rank has -------------------------------------
  std::vector<std::string> problems;
  if (htg == nullptr)
  {
    problems.push_back("no grid");
  }
  const HyperTreeGridPiece piece = HyperTreeGridPiece::describe(htg);
  std::vector<vtkDataArray*> arrays = selectCellArrays(htg, impl.Options.arrays, problems);
  if (htg != nullptr && !impl.Options.arrays.empty())
  {
    if (vtkDataArray* ghosts = htg->GetCellData()->GetArray(GhostArray))
    {
      if (std::find(arrays.begin(), arrays.end(), ghosts) == arrays.end())
      {
        arrays.push_back(ghosts);
      }
    }
  }
  std::string mine;
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
    else
    {
      mine += describe({name, array->GetDataType(), array->GetNumberOfComponents()}) + "\n";
    }
  }
  std::string local;
  for (const std::string& problem : problems)
  {
    local += (local.empty() ? "" : "; ") + problem;
  }
  impl.agree(local, context, nullptr);

  const unsigned int* dims = htg->GetDimensions();
  const std::int64_t branchFactor = htg->GetBranchFactor();
  // What this rank adds to the file, to check the free space first.
  std::int64_t bytes = StepShape::bytes(piece.descriptors.size()) +
                       StepShape::bytes(piece.numberOfCells) +
                       8 * (4 + 2 * piece.numberOfTrees() + piece.numberOfDepths() +
                            static_cast<std::int64_t>(dims[0] + dims[1] + dims[2]));
  for (vtkDataArray* array : arrays)
  {
    bytes += piece.numberOfCells * array->GetNumberOfComponents() * array->GetDataTypeSize();
  }
  const std::vector<std::int64_t> counts = gatherCounts(
      communicator, {piece.numberOfTrees(), piece.numberOfCells, piece.numberOfDepths(),
                     piece.descriptors.size(), branchFactor, dims[0], dims[1], dims[2], bytes});
  StepShape shape;
  shape.pieces = sizeOf(communicator);
  shape.rank = rankOf(communicator);
  for (int r = 0; r < shape.pieces; ++r)
  {
    const std::int64_t* row = counts.data() + 9 * r;
    shape.trees.push_back(row[0]);
    shape.cells.push_back(row[1]);
    shape.depths.push_back(row[2]);
    shape.descriptorBits.push_back(row[3]);
    shape.dataBytes += row[8];
    if (row[4] != branchFactor || row[5] != dims[0] || row[6] != dims[1] || row[7] != dims[2])
    {
      // The same on every rank: every rank compares every row.
      throw WriteError(context + ": the ranks' grids differ in branch factor or dimensions");
    }
  }
  shape.dimensions = {static_cast<std::int64_t>(dims[0]), static_cast<std::int64_t>(dims[1]),
                      static_cast<std::int64_t>(dims[2])};
  impl.Dimensions = shape.dimensions;

  // A write that fails for want of space may leave HDF5 unable to close the file
  // (HDF5 1.10 then crashes at exit, HDFFV-11052): refuse a step that will not
  // fit before touching the file.
  impl.agree(shape.rank == 0 && impl.Options.checkFreeSpace
                 ? freeSpaceProblem(impl.FileName, shape.dataBytes)
                 : std::string(),
             context, nullptr);

  // ---- the file: created at the run's first step, then appended to --------------------
  int exists = std::filesystem::exists(impl.FileName) ? 1 : 0;
  if (communicator != MPI_COMM_NULL)
  {
    MPI_Bcast(&exists, 1, MPI_INT, 0, communicator); // rank 0's view decides
  }
  const bool create = !exists || (!impl.Started && !impl.Options.append);
  StepFile file(communicator, impl.FileName);
  impl.agree(file.open(create), context, nullptr);
  if (create)
  {
    // The arrays: those of every rank, in rank order, each once.
    std::vector<ArraySpec> specs;
    std::map<std::string, std::string> seen;
    for (const std::string& text : gatherTexts(communicator, mine))
    {
      std::istringstream lines(text);
      std::string line;
      while (std::getline(lines, line))
      {
        ArraySpec spec;
        std::istringstream fields(line);
        std::getline(fields, spec.name, '\t');
        fields >> spec.type >> spec.components;
        const auto known = seen.find(spec.name);
        if (known == seen.end())
        {
          seen[spec.name] = line;
          specs.push_back(spec);
        }
        else if (known->second != line)
        {
          file.close();
          throw WriteError(context + ": cell array '" + spec.name +
                           "' differs between ranks in value type or components");
        }
      }
    }
    impl.Arrays = specs;
    impl.Steps = 0;
    impl.declareSeries(specs);
    std::string created = impl.create(file.file(), htg, shape);
    if (created.empty() && H5Fflush(file.file(), H5F_SCOPE_GLOBAL) < 0)
    {
      // On disk before any data: a later failure finds a file it can restore.
      created = "cannot flush the new file: " + hdfErrorText();
    }
    impl.agree(created, context, &file);
  }
  else
  {
    impl.agree(impl.reopen(file.file(), shape, branchFactor), context, &file);
    // Drop rows a failed or interrupted step left behind.
    std::string trimmed;
    for (std::vector<Series>* group : {&impl.Data, &impl.Offsets})
    {
      for (Series& series : *group)
      {
        const hsize_t dims2[2] = {static_cast<hsize_t>(series.committed),
                                  static_cast<hsize_t>(series.columns)};
        if (currentRows(series.dataset.get()) != series.committed &&
            H5Dset_extent(series.dataset.get(), dims2) < 0 && trimmed.empty())
        {
          trimmed = "cannot trim " + series.path + ": " + hdfErrorText();
        }
      }
    }
    impl.agree(trimmed, context, &file);
  }
  // Every array of the file must come from every rank (the ghost array excepted).
  std::string missing;
  for (const ArraySpec& spec : impl.Arrays)
  {
    auto found = std::find_if(arrays.begin(), arrays.end(),
                              [&](vtkDataArray* a) { return spec.name == a->GetName(); });
    if (found == arrays.end())
    {
      if (spec.name != GhostArray)
      {
        missing += (missing.empty() ? "" : "; ") + ("no cell array '" + spec.name + "'");
      }
    }
    else if ((*found)->GetNumberOfComponents() != spec.components)
    {
      missing += (missing.empty() ? "" : "; ") +
                 ("cell array '" + spec.name + "' has " +
                  std::to_string((*found)->GetNumberOfComponents()) + " components, the file " +
                  std::to_string(spec.components));
    }
  }
  impl.agree(missing, context, &file);

  // ---- data, then the step's offsets, then NSteps: the step exists once NSteps says so --
  impl.agree(impl.extend(impl.Data, shape, false), context, &file);
  impl.agree(impl.writePiece(shape, piece, htg, arrays), context, &file);
  std::string row = impl.extend(impl.Offsets, shape, true);
  if (row.empty() && shape.rank == 0)
  {
    row = impl.writeStepRow(shape, time);
  }
  impl.agree(row, context, &file);
  std::string flushed = H5Fflush(file.file(), H5F_SCOPE_GLOBAL) < 0
                            ? "cannot flush the step's data: " + hdfErrorText()
                            : std::string();
  impl.agree(flushed, context, &file);
  const std::int64_t stepsAfter = impl.Steps + 1;
  std::string committed;
  {
    HdfHandle steps = groupHandle(H5Gopen2(file.file(), "VTKHDF/Steps", H5P_DEFAULT));
    if (!Implementation::writeAttribute(steps.get(), "NSteps", H5T_STD_I64LE, H5T_NATIVE_INT64, 0,
                                        &stepsAfter) ||
        H5Fflush(file.file(), H5F_SCOPE_GLOBAL) < 0)
    {
      committed = "cannot update NSteps: " + hdfErrorText();
      Implementation::writeAttribute(steps.get(), "NSteps", H5T_STD_I64LE, H5T_NATIVE_INT64, 0,
                                     &impl.Steps);
    }
  }
  impl.agree(committed, context, &file);
  for (std::vector<Series>* group : {&impl.Data, &impl.Offsets})
  {
    for (Series& series : *group)
    {
      series.dataset.reset();
    }
  }
  const std::string closed = file.close() ? std::string() : "closing: " + hdfErrorText();
  impl.Started = true;
  impl.Steps = stepsAfter;
  const std::string closeProblems = gatherProblems(communicator, closed);
  if (!closeProblems.empty())
  {
    throw WriteError(context + " completely (the step's data and offsets were flushed before): " +
                     closeProblems);
  }
}

} // namespace canopy::io
