// What the ranks of a VTKHDF writer gather about a step (see VtkHdfStepShape.h).
#include "VtkHdfStepShape.h"

#include "WriterAgreement.h"
#include <canopy/io/HyperTreeGridPiece.h>

#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>

#include <filesystem>
#include <sstream>

namespace canopy::io
{

std::int64_t StepShape::prefix(Kind kind, int rank, int axis) const
{
  std::int64_t sum = 0;
  for (int r = 0; r < rank; ++r)
  {
    sum += this->rows(kind, r, axis);
  }
  return sum;
}

std::int64_t StepShape::rows(Kind kind, int r, int axis) const
{
  const PieceCounts& piece = this->pieces[static_cast<std::size_t>(r)];
  switch (kind)
  {
  case Kind::PerPiece:
    return 1;
  case Kind::PerTree:
    return piece.trees;
  case Kind::PerDepth:
    return piece.depths;
  case Kind::DescriptorBytes:
    return bytes(piece.descriptorBits);
  case Kind::MaskBytes:
    return bytes(piece.cells);
  case Kind::Coordinate:
    return this->dimensions[static_cast<std::size_t>(axis)];
  case Kind::PerCell:
    return piece.cells;
  }
  return 0;
}

bool StepShape::gridsMatch() const
{
  const PieceCounts& mine = this->mine();
  for (const PieceCounts& piece : this->pieces)
  {
    if (piece.branchFactor != mine.branchFactor || piece.dimensions != mine.dimensions)
    {
      return false;
    }
  }
  return true;
}

PieceCounts countPiece(const HyperTreeGridPiece& piece, vtkHyperTreeGrid* htg,
                       const std::vector<vtkDataArray*>& arrays)
{
  const unsigned int* dims = htg->GetDimensions();
  PieceCounts counts;
  counts.trees = piece.numberOfTrees();
  counts.cells = piece.numberOfCells;
  counts.depths = piece.numberOfDepths();
  counts.descriptorBits = piece.descriptors.size();
  counts.branchFactor = htg->GetBranchFactor();
  counts.dimensions = {dims[0], dims[1], dims[2]};
  // What this rank adds to the file, to check the free space first.
  counts.dataBytes = StepShape::bytes(counts.descriptorBits) + StepShape::bytes(counts.cells) +
                     8 * (4 + 2 * counts.trees + counts.depths +
                          static_cast<std::int64_t>(dims[0] + dims[1] + dims[2]));
  for (vtkDataArray* array : arrays)
  {
    counts.dataBytes += counts.cells * array->GetNumberOfComponents() * array->GetDataTypeSize();
  }
  return counts;
}

StepShape gatherStepShape(MPI_Comm communicator, const PieceCounts& mine)
{
  StepShape shape;
  shape.rank = rankOf(communicator);
  shape.pieces = gatherRecords(communicator, mine);
  shape.dimensions = mine.dimensions;
  for (const PieceCounts& piece : shape.pieces)
  {
    shape.dataBytes += piece.dataBytes;
  }
  return shape;
}

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

} // namespace canopy::io
