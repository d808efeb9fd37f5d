// The VTKHDF HyperTreeGrid layout (see VtkHdfLayout.h).
#include "VtkHdfLayout.h"

#include <algorithm>
#include <sstream>

namespace canopy::io
{
namespace
{

// VTKHDF 2.4 is the first version with the HyperTreeGrid layout.
constexpr std::int64_t FormatVersion[2] = {2, 4};

/// A dataset of /VTKHDF/Steps, a row per step.
GrowingDataset stepsDataset(std::string path, hid_t fileType)
{
  GrowingDataset dataset;
  dataset.group = "VTKHDF/Steps/";
  dataset.path = std::move(path);
  dataset.fileType = fileType;
  return dataset;
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

hsize_t chunkRowsOf(const Series& series, const StepShape& shape)
{
  const std::size_t rowBytes =
      H5Tget_size(series.data.fileType) * static_cast<std::size_t>(series.data.columns);
  const std::int64_t firstStepRows = shape.total(series.kind, series.axis);
  switch (series.kind)
  {
  case Kind::PerPiece:
    return chunkRows(firstStepRows, rowBytes, 1 << 12, 64);
  case Kind::PerTree:
  case Kind::PerDepth:
    return chunkRows(firstStepRows, rowBytes, 1 << 20, 256);
  case Kind::Coordinate:
    return chunkRows(firstStepRows, rowBytes, 1 << 16, 64);
  default:
    return chunkRows(firstStepRows, rowBytes, 1 << 20, 1024);
  }
}

bool writeRootAttributes(hid_t root, const StepShape& shape, bool transposedRootIndexing)
{
  const std::int64_t branchFactor = shape.mine().branchFactor;
  const int dimensions[3] = {static_cast<int>(shape.dimensions[0]),
                             static_cast<int>(shape.dimensions[1]),
                             static_cast<int>(shape.dimensions[2])};
  const int transposed = transposedRootIndexing ? 1 : 0;
  return writeAttribute(root, "Version", H5T_STD_I64LE, H5T_NATIVE_INT64, 2, FormatVersion) &&
         writeStringAttribute(root, "Type", "HyperTreeGrid") &&
         writeAttribute(root, "BranchFactor", H5T_STD_I64LE, H5T_NATIVE_INT64, 0, &branchFactor) &&
         writeAttribute(root, "Dimensions", H5T_STD_I32LE, H5T_NATIVE_INT, 3, dimensions) &&
         writeAttribute(root, "TransposedRootIndexing", H5T_STD_I32LE, H5T_NATIVE_INT, 0,
                        &transposed);
}

/// Why the grid of the file's `root` group is not one like `shape`'s ("" if it is).
std::string gridProblem(hid_t root, const StepShape& shape)
{
  if (readStringAttribute(root, "Type") != "HyperTreeGrid")
  {
    return "/VTKHDF is not of Type HyperTreeGrid";
  }
  const std::int64_t branchFactor = shape.mine().branchFactor;
  std::int64_t fileBranchFactor = 0;
  int fileDimensions[3] = {0, 0, 0};
  if (!readAttribute(root, "BranchFactor", H5T_NATIVE_INT64, &fileBranchFactor) ||
      !readAttribute(root, "Dimensions", H5T_NATIVE_INT, fileDimensions))
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
  return {};
}

/// The cell arrays of `file`, from its /VTKHDF/CellData datasets.
std::string readArrays(hid_t file, std::vector<ArraySpec>& arrays)
{
  HdfGroup cellData = openGroup(file, "VTKHDF/CellData");
  if (!cellData.valid())
  {
    return "no /VTKHDF/CellData group";
  }
  for (const std::string& name : linkNames(cellData.get()))
  {
    HdfDataset dataset = openDataset(cellData.get(), name);
    const int columns = dataset.valid() ? columnsOf(dataset.get()) : -1;
    if (columns < 1)
    {
      return "cannot open /VTKHDF/CellData/" + name;
    }
    HdfType type{H5Dget_type(dataset.get())};
    arrays.push_back({name, vtkTypeOf(type.get()), columns});
  }
  return {};
}

/// Grows `dataset` by `rows` rows past its steps' ("" or what went wrong).
std::string extend(const GrowingDataset& dataset, std::int64_t rows)
{
  return setRows(dataset.handle.get(), dataset.committed + rows, dataset.columns)
             ? std::string()
             : "cannot extend " + dataset.path + ": " + hdfErrorText();
}

/// The step's row of a /VTKHDF/Steps dataset.
std::string writeValue(const GrowingDataset& dataset, hid_t memoryType, const void* value)
{
  return writeDatasetRows(dataset, dataset.committed, 1, memoryType, value);
}

} // namespace

VtkHdfLayout::VtkHdfLayout(std::vector<ArraySpec> arrays) : Arrays(std::move(arrays))
{
  auto add = [this](std::string path, Kind kind, hid_t type, std::string offsets, int columns = 1,
                    int axis = 0)
  {
    Series series;
    series.data.path = std::move(path);
    series.data.fileType = type;
    series.data.columns = columns;
    series.kind = kind;
    series.axis = axis;
    if (!offsets.empty())
    {
      series.offsets = stepsDataset(std::move(offsets), H5T_STD_I64LE);
    }
    this->AllSeries.push_back(std::move(series));
  };
  // In GridDataset order.
  add("NumberOfTrees", Kind::PerPiece, H5T_STD_I64LE, "");
  add("NumberOfCells", Kind::PerPiece, H5T_STD_I64LE, "");
  add("NumberOfDepths", Kind::PerPiece, H5T_STD_I64LE, "");
  add("DescriptorsSize", Kind::PerPiece, H5T_STD_I64LE, "");
  add("TreeIds", Kind::PerTree, H5T_STD_I64LE, "TreeIdsOffsets");
  add("DepthPerTree", Kind::PerTree, H5T_STD_I64LE, "DepthPerTreeOffsets");
  add("NumberOfCellsPerTreeDepth", Kind::PerDepth, H5T_STD_I64LE,
      "NumberOfCellsPerTreeDepthOffsets");
  add("Descriptors", Kind::DescriptorBytes, H5T_STD_U8LE, "DescriptorsOffsets");
  add("Mask", Kind::MaskBytes, H5T_STD_U8LE, "MaskOffsets");
  add("XCoordinates", Kind::Coordinate, H5T_IEEE_F64LE, "XCoordinatesOffsets", 1, 0);
  add("YCoordinates", Kind::Coordinate, H5T_IEEE_F64LE, "YCoordinatesOffsets", 1, 1);
  add("ZCoordinates", Kind::Coordinate, H5T_IEEE_F64LE, "ZCoordinatesOffsets", 1, 2);
  for (const ArraySpec& spec : this->Arrays)
  {
    add("CellData/" + spec.name, Kind::PerCell, fileTypeOf(spec.type),
        "CellDataOffsets/" + spec.name, spec.components);
  }
  // In StepDataset order.
  this->StepDatasets = {stepsDataset("Values", H5T_IEEE_F64LE),
                        stepsDataset("PartOffsets", H5T_STD_I64LE),
                        stepsDataset("NumberOfParts", H5T_STD_I64LE)};
}

template <typename Visit>
void VtkHdfLayout::forEachStepsDataset(Visit visit)
{
  for (GrowingDataset& dataset : this->StepDatasets)
  {
    visit(dataset);
  }
  for (Series& series : this->AllSeries)
  {
    if (series.offsets)
    {
      visit(*series.offsets);
    }
  }
}

template <typename Visit>
void VtkHdfLayout::forEachDataset(Visit visit)
{
  for (Series& series : this->AllSeries)
  {
    visit(series.data);
  }
  this->forEachStepsDataset(visit);
}

std::string VtkHdfLayout::create(hid_t file, const StepShape& shape, bool transposedRootIndexing)
{
  HdfGroup root = createGroup(file, "VTKHDF");
  if (!root.valid())
  {
    return "cannot create /VTKHDF: " + hdfErrorText();
  }
  if (!writeRootAttributes(root.get(), shape, transposedRootIndexing))
  {
    return "cannot write the attributes of /VTKHDF: " + hdfErrorText();
  }
  for (const char* group : {"VTKHDF/CellData", "VTKHDF/Steps", "VTKHDF/Steps/CellDataOffsets"})
  {
    if (!createGroup(file, group).valid())
    {
      return std::string("cannot create /") + group + ": " + hdfErrorText();
    }
  }
  const std::int64_t noSteps = 0;
  HdfGroup steps = openGroup(file, "VTKHDF/Steps");
  if (!writeAttribute(steps.get(), "NSteps", H5T_STD_I64LE, H5T_NATIVE_INT64, 0, &noSteps))
  {
    return "cannot write /VTKHDF/Steps/NSteps: " + hdfErrorText();
  }
  auto createDataset = [file](GrowingDataset& dataset, hsize_t chunk)
  {
    dataset.handle = createGrowingDataset(file, dataset.group + dataset.path, dataset.fileType,
                                          dataset.columns, chunk);
    return dataset.handle.valid() ? std::string()
                                  : "cannot create /" + std::string(dataset.group) + dataset.path +
                                        ": " + hdfErrorText();
  };
  std::string problem;
  for (Series& series : this->AllSeries)
  {
    if (problem.empty())
    {
      problem = createDataset(series.data, chunkRowsOf(series, shape));
    }
  }
  this->forEachStepsDataset(
      [&](GrowingDataset& dataset)
      {
        if (problem.empty())
        {
          problem = createDataset(dataset, 64);
        }
      });
  return problem;
}

std::string VtkHdfLayout::open(hid_t file, const StepShape& shape, std::int64_t& steps)
{
  HdfGroup root = openGroup(file, "VTKHDF");
  if (!root.valid())
  {
    return "no /VTKHDF group (not a VTKHDF file)";
  }
  std::string problem = gridProblem(root.get(), shape);
  // The file's arrays decide what is written.
  std::vector<ArraySpec> arrays;
  if (problem.empty())
  {
    problem = readArrays(file, arrays);
  }
  if (!problem.empty())
  {
    return problem;
  }
  *this = VtkHdfLayout(std::move(arrays));
  problem = this->openDatasets(file);
  if (!problem.empty())
  {
    return problem;
  }
  HdfGroup stepsGroup = openGroup(file, "VTKHDF/Steps");
  std::int64_t fileSteps = 0;
  if (!readAttribute(stepsGroup.get(), "NSteps", H5T_NATIVE_INT64, &fileSteps) || fileSteps < 0)
  {
    return "cannot read /VTKHDF/Steps/NSteps: " + hdfErrorText();
  }
  steps = fileSteps;
  return this->readCommittedRows(steps, shape);
}

std::string VtkHdfLayout::openDatasets(hid_t file)
{
  std::string problem;
  this->forEachDataset(
      [&](GrowingDataset& dataset)
      {
        if (problem.empty())
        {
          dataset.handle = openDataset(file, dataset.group + dataset.path);
          if (!dataset.handle.valid())
          {
            problem =
                "cannot open /" + std::string(dataset.group) + dataset.path + ": " + hdfErrorText();
          }
        }
      });
  return problem;
}

/// How many rows of each dataset the file's steps use: the last step's offsets
/// plus what its pieces hold. Rows beyond (a step that failed or was cut short)
/// are dropped before the next step is added.
std::string VtkHdfLayout::readCommittedRows(std::int64_t steps, const StepShape& shape)
{
  this->forEachStepsDataset([steps](GrowingDataset& dataset) { dataset.committed = steps; });
  if (steps == 0)
  {
    for (Series& series : this->AllSeries)
    {
      series.data.committed = 0;
    }
    return {};
  }
  const std::int64_t last = steps - 1;
  std::int64_t partOffset = 0, parts = 0;
  if (!readRows(this->step(StepDataset::PartOffsets).handle.get(), last, 1, H5T_NATIVE_INT64,
                &partOffset) ||
      !readRows(this->step(StepDataset::NumberOfParts).handle.get(), last, 1, H5T_NATIVE_INT64,
                &parts) ||
      parts < 0)
  {
    return "cannot read the last step's PartOffsets and NumberOfParts";
  }
  // (Coordinates: one copy of the axis per piece, of the file's Dimensions,
  // which open() found equal to this grid's.)
  StepShape lastStep;
  lastStep.pieces.resize(static_cast<std::size_t>(parts));
  lastStep.dimensions = shape.dimensions;
  for (const PerPieceField& field : PerPieceFields)
  {
    const GrowingDataset& dataset = this->grid(field.dataset).data;
    std::vector<std::int64_t> values(static_cast<std::size_t>(parts));
    if (!readRows(dataset.handle.get(), partOffset, parts, H5T_NATIVE_INT64, values.data()))
    {
      return "cannot read the last step's " + dataset.path;
    }
    for (std::size_t p = 0; p < values.size(); ++p)
    {
      lastStep.pieces[p].*field.count = values[p];
    }
  }
  for (Series& series : this->AllSeries)
  {
    if (!series.offsets)
    {
      series.data.committed = partOffset + parts;
      continue;
    }
    std::int64_t start = 0;
    if (!readRows(series.offsets->handle.get(), last, 1, H5T_NATIVE_INT64, &start))
    {
      return "cannot read Steps/" + series.offsets->path;
    }
    series.data.committed = start + lastStep.total(series.kind, series.axis);
  }
  return {};
}

std::string VtkHdfLayout::trim()
{
  std::string problem;
  this->forEachDataset(
      [&](GrowingDataset& dataset)
      {
        if (rowsOf(dataset.handle.get()) != dataset.committed &&
            !setRows(dataset.handle.get(), dataset.committed, dataset.columns) && problem.empty())
        {
          problem = "cannot trim " + dataset.path + ": " + hdfErrorText();
        }
      });
  return problem;
}

std::string VtkHdfLayout::extendData(const StepShape& shape)
{
  std::string problem;
  for (const Series& series : this->AllSeries)
  {
    if (problem.empty())
    {
      problem = extend(series.data, shape.total(series.kind, series.axis));
    }
  }
  return problem;
}

std::string VtkHdfLayout::extendSteps()
{
  std::string problem;
  this->forEachStepsDataset(
      [&](GrowingDataset& dataset)
      {
        if (problem.empty())
        {
          problem = extend(dataset, 1);
        }
      });
  return problem;
}

std::string VtkHdfLayout::writeStepRow(const StepShape& shape, double time)
{
  const std::int64_t partOffset = this->grid(GridDataset::NumberOfTrees).data.committed;
  const std::int64_t parts = shape.numberOfPieces();
  std::string problem = writeValue(this->step(StepDataset::Values), H5T_NATIVE_DOUBLE, &time);
  if (problem.empty())
  {
    problem = writeValue(this->step(StepDataset::PartOffsets), H5T_NATIVE_INT64, &partOffset);
  }
  if (problem.empty())
  {
    problem = writeValue(this->step(StepDataset::NumberOfParts), H5T_NATIVE_INT64, &parts);
  }
  for (const Series& series : this->AllSeries)
  {
    if (problem.empty() && series.offsets)
    {
      problem = writeValue(*series.offsets, H5T_NATIVE_INT64, &series.data.committed);
    }
  }
  return problem;
}

void VtkHdfLayout::close()
{
  this->forEachDataset([](GrowingDataset& dataset) { dataset.handle.reset(); });
}

std::string writeDatasetRows(const GrowingDataset& dataset, std::int64_t first, std::int64_t rows,
                             hid_t memoryType, const void* values)
{
  return writeRows(dataset.handle.get(), dataset.columns, first, rows, memoryType, values)
             ? std::string()
             : "cannot write " + dataset.path + ": " + hdfErrorText();
}

std::string writeNumberOfSteps(hid_t file, std::int64_t steps)
{
  HdfGroup group = openGroup(file, "VTKHDF/Steps");
  return writeAttribute(group.get(), "NSteps", H5T_STD_I64LE, H5T_NATIVE_INT64, 0, &steps)
             ? std::string()
             : "cannot update NSteps: " + hdfErrorText();
}

} // namespace canopy::io
