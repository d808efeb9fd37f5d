#include "ForestLayout.h"
#include <canopy/ForestValidation.h>

#include "BlockValidation.h"
#include "DescriptionChecks.h"
#include "StorageSlots.h"
#include "ValidatedTrees.h"

#include "ProblemList.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <set>
#include <sstream>
#include <unordered_set>

namespace canopy
{
namespace
{

std::string joinLines(const std::vector<std::string>& lines)
{
  std::ostringstream out;
  out << "invalid forest description:";
  for (const auto& line : lines)
  {
    out << "\n  - " << line;
  }
  return out.str();
}

void validateAxis(const char* axis, const double* coords, std::size_t points, ProblemList& problems)
{
  if (points == 0)
  {
    problems.add("root grid: axis ", axis, " has no points (a flat axis has exactly 1)");
    return;
  }
  if (coords == nullptr)
  {
    problems.add("root grid: axis ", axis, " coordinates pointer is null");
    return;
  }
  for (std::size_t i = 0; i < points; ++i)
  {
    if (!std::isfinite(coords[i]))
    {
      problems.add("root grid: axis ", axis, " coordinate ", i, " is not finite");
      return;
    }
    if (i > 0 && !(coords[i] > coords[i - 1]))
    {
      problems.add("root grid: axis ", axis, " coordinates are not strictly increasing at point ",
                   i, " (", coords[i - 1], " then ", coords[i], ")");
      return;
    }
  }
}

void validateRootGrid(const ForestDescription& forest, ForestLayout& layout, ProblemList& problems)
{
  const RootGrid& grid = forest.rootGrid;
  const std::array<std::size_t, 3> points{{grid.pointsX, grid.pointsY, grid.pointsZ}};
  int flatAxes = 0;
  for (int a = 0; a < 3; ++a)
  {
    flatAxes += points[a] == 1;
    layout.rootCells[a] = points[a] > 1 ? points[a] - 1 : 1;
  }
  if (forest.dimension == 3 && flatAxes != 0)
  {
    problems.add("root grid: a 3D forest needs at least 2 points on every axis, got ", points[0],
                 " x ", points[1], " x ", points[2]);
  }
  if (forest.dimension == 2 && flatAxes != 1)
  {
    problems.add("root grid: a 2D forest needs exactly one flat axis (1 point), got ", points[0],
                 " x ", points[1], " x ", points[2]);
  }
  if (forest.dimension == 1 && flatAxes != 2)
  {
    problems.add("root grid: a 1D forest needs exactly two flat axes (1 point each), got ",
                 points[0], " x ", points[1], " x ", points[2]);
  }
  // VTK indexes root cells with vtkIdType and points per axis with unsigned int.
  for (int a = 0; a < 3; ++a)
  {
    if (points[a] > std::numeric_limits<unsigned int>::max())
    {
      problems.add("root grid: axis ", "xyz"[a], " has ", points[a],
                   " points, more than a vtkHyperTreeGrid can hold (",
                   std::numeric_limits<unsigned int>::max(), ")");
    }
  }
  std::size_t cells = 0;
  if (__builtin_mul_overflow(layout.rootCells[0], layout.rootCells[1], &cells) ||
      __builtin_mul_overflow(cells, layout.rootCells[2], &cells) ||
      cells > static_cast<std::size_t>(std::numeric_limits<std::int64_t>::max()))
  {
    problems.add("root grid: ", layout.rootCells[0], " x ", layout.rootCells[1], " x ",
                 layout.rootCells[2], " root cells overflow a 64-bit cell index");
    cells = 0;
  }
  layout.numberOfRootCells = cells;
  if (problems.empty())
  {
    validateAxis("x", grid.x, grid.pointsX, problems);
    validateAxis("y", grid.y, grid.pointsY, problems);
    validateAxis("z", grid.z, grid.pointsZ, problems);
  }
}

/// Absent nodes (parts of a split tree another rank owns) are leaves below the
/// root; they take no storage slot and no field value.
bool validateAbsentNodes(std::size_t t, const TreeDescription& tree, TreeLayout& shape,
                         ProblemList& problems)
{
  if (tree.absent[0] != 0)
  {
    problems.add(treeName(t, tree),
                 ": the root is absent; leave a tree this rank has no part of out of the forest");
    return false;
  }
  std::size_t absent = 0;
  std::size_t refinedAbsent = 0;
  std::size_t firstRefinedAbsent = 0;
  for (std::size_t n = 1; n < tree.numberOfNodes; ++n)
  {
    if (tree.absent[n] == 0)
    {
      continue;
    }
    ++absent;
    if (tree.refinement[n] != 0 && refinedAbsent++ == 0)
    {
      firstRefinedAbsent = n;
    }
  }
  if (refinedAbsent != 0)
  {
    problems.add(treeName(t, tree), ": ", refinedAbsent,
                 " absent node(s) are refined (first: node ", firstRefinedAbsent,
                 "); describe another rank's part by its coarsest node, as a leaf");
    return false;
  }
  shape.numberOfPresentNodes = tree.numberOfNodes - absent;
  shape.numberOfPresentLeaves = shape.numberOfLeaves - absent;
  return true;
}

/// Walks the breadth-first refinement bytes level by level and checks they
/// describe exactly numberOfNodes nodes within maxLevels levels.
bool validateTreeShape(const ForestDescription& forest, std::size_t t, TreeLayout& shape,
                       ProblemList& problems)
{
  const TreeDescription& tree = forest.trees[t];
  const std::size_t children = childrenPerNode(forest);
  const std::size_t n = tree.numberOfNodes;
  std::size_t levelStart = 0;
  std::size_t levelSize = 1;
  std::size_t lastLevelSize = 1;
  int levels = 0;
  while (levelSize > 0)
  {
    ++levels;
    if (levels > forest.maxLevels)
    {
      problems.add(treeName(t, tree), ": refined beyond maxLevels = ", forest.maxLevels, " (level ",
                   levels - 2, " has refined nodes)");
      return false;
    }
    if (levelStart + levelSize > n)
    {
      problems.add(treeName(t, tree), ": refinement bits describe at least ",
                   levelStart + levelSize, " nodes but numberOfNodes is ", n);
      return false;
    }
    const std::size_t refined = countNonZero(tree.refinement + levelStart, levelSize);
    shape.numberOfLeaves += levelSize - refined;
    lastLevelSize = levelSize;
    levelStart += levelSize;
    levelSize = refined * children;
  }
  if (levelStart != n)
  {
    problems.add(treeName(t, tree), ": refinement bits describe ", levelStart,
                 " nodes but numberOfNodes is ", n, " (", n - levelStart, " bytes too many)");
    return false;
  }
  // vtkHyperTree stores child offsets as unsigned int.
  if (n >= std::numeric_limits<unsigned int>::max())
  {
    problems.add(treeName(t, tree), ": ", n, " nodes exceed what one vtkHyperTree can index");
    return false;
  }
  shape.numberOfNodes = n;
  shape.cells = n;
  shape.levels = levels;
  shape.descriptorBits = n - lastLevelSize;
  shape.numberOfPresentNodes = n;
  shape.numberOfPresentLeaves = shape.numberOfLeaves;
  return tree.absent == nullptr || validateAbsentNodes(t, tree, shape, problems);
}

void validateTrees(const ForestDescription& forest, ForestLayout& layout, ProblemList& problems,
                   const ValidatedTrees* known)
{
  // Sorted roots find duplicates without a table as large as the root grid.
  std::vector<std::pair<std::int64_t, std::size_t>> roots;
  roots.reserve(forest.trees.size());
  std::size_t withSlots = 0;
  layout.trees.resize(forest.trees.size());
  bool shapesValid = true;
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeDescription& tree = forest.trees[t];
    TreeLayout& shape = layout.trees[t];
    if (tree.rootIndex < 0 || static_cast<std::size_t>(tree.rootIndex) >= layout.numberOfRootCells)
    {
      problems.add(treeName(t, tree), ": root index out of range [0, ", layout.numberOfRootCells,
                   ")");
      shapesValid = false;
    }
    else
    {
      roots.emplace_back(tree.rootIndex, t);
    }
    withSlots += tree.storageSlots != nullptr;
    layout.anyMask = layout.anyMask || tree.masked != nullptr;
    layout.anyAbsent = layout.anyAbsent || tree.absent != nullptr;
    if (tree.numberOfNodes == 0)
    {
      problems.add(treeName(t, tree), ": numberOfNodes is 0 (a tree has at least its root)");
      shapesValid = false;
      continue;
    }
    if (tree.refinement == nullptr)
    {
      problems.add(treeName(t, tree), ": refinement pointer is null");
      shapesValid = false;
      continue;
    }
    if (known && known->unchanged[t])
    {
      shape = known->previous->trees[t]; // same bytes as a tree validated before
    }
    else if (!validateTreeShape(forest, t, shape, problems))
    {
      shapesValid = false;
      continue;
    }
    shape.firstSlot = layout.totalPresentNodes;
    shape.firstCell = layout.totalNodes;
    layout.totalNodes += shape.numberOfNodes;
    layout.totalCells += shape.numberOfNodes;
    layout.totalLeaves += shape.numberOfLeaves;
    layout.totalPresentNodes += shape.numberOfPresentNodes;
    layout.totalPresentLeaves += shape.numberOfPresentLeaves;
    layout.totalDescriptorBits += shape.descriptorBits;
  }
  std::sort(roots.begin(), roots.end());
  for (std::size_t i = 1; i < roots.size(); ++i)
  {
    if (roots[i].first == roots[i - 1].first)
    {
      const std::size_t t = roots[i].second;
      problems.add(treeName(t, forest.trees[t]),
                   ": duplicate root, another tree already uses root cell ", roots[i].first);
      shapesValid = false;
    }
  }
  layout.explicitSlots = withSlots > 0;
  if (withSlots != 0 && withSlots != forest.trees.size())
  {
    problems.add("storage slots: ", withSlots, " of ", forest.trees.size(),
                 " trees have a storageSlots map; either every tree has one or none does");
    return;
  }
  if (!layout.explicitSlots || !shapesValid || (known && known->slotsKnownValid()))
  {
    return;
  }
  // Slots of all trees' present nodes together must be a permutation of
  // 0 .. totalPresentNodes-1 (absent nodes have no slot; their entries are ignored).
  std::vector<bool> slotUsed(layout.totalPresentNodes, false);
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeDescription& tree = forest.trees[t];
    for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
    {
      if (tree.absent && tree.absent[n])
      {
        continue;
      }
      const std::int64_t slot = tree.storageSlots[n];
      if (slot < 0 || static_cast<std::size_t>(slot) >= layout.totalPresentNodes)
      {
        problems.add(treeName(t, tree), ": node ", n, " has storage slot ", slot, " outside [0, ",
                     layout.totalPresentNodes, ")",
                     layout.anyAbsent ? " (slots number the nodes that are not absent)" : "");
        return;
      }
      if (slotUsed[static_cast<std::size_t>(slot)])
      {
        problems.add(treeName(t, tree), ": node ", n, " reuses storage slot ", slot,
                     " of another node");
        return;
      }
      slotUsed[static_cast<std::size_t>(slot)] = true;
    }
  }
}

void validateFields(const ForestDescription& forest, const ForestLayout& layout,
                    ProblemList& problems)
{
  std::set<std::string> names;
  for (std::size_t f = 0; f < forest.fields.size(); ++f)
  {
    const FieldDescription& field = forest.fields[f];
    std::ostringstream label;
    label << "field " << f << " '" << field.name << "'";
    const std::string name = label.str();
    if (field.name.empty())
    {
      problems.add(name, ": empty name");
    }
    else if (!names.insert(field.name).second)
    {
      problems.add(name, ": duplicate field name");
    }
    if (field.components < 1)
    {
      problems.add(name, ": components must be >= 1, got ", field.components);
      continue;
    }
    const std::size_t valueSize = sizeOf(field.type);
    if (valueSize == 0)
    {
      problems.add(name, ": unknown value type");
      continue;
    }
    switch (field.layout)
    {
    case Layout::AoS:
      // A rank without trees may pass no memory at all: null with zero tuples.
      if (field.data == nullptr && field.numberOfTuples > 0)
      {
        problems.add(name, ": data pointer is null");
      }
      break;
    case Layout::Strided:
      if (field.data == nullptr && field.numberOfTuples > 0)
      {
        problems.add(name, ": data pointer is null");
      }
      if (field.tupleStrideBytes < valueSize * static_cast<std::size_t>(field.components))
      {
        problems.add(name, ": tupleStrideBytes ", field.tupleStrideBytes,
                     " is smaller than one tuple (",
                     valueSize * static_cast<std::size_t>(field.components), " bytes)");
      }
      else if (field.tupleStrideBytes % valueSize != 0)
      {
        problems.add(name, ": tupleStrideBytes ", field.tupleStrideBytes,
                     " is not a multiple of the value size ", valueSize);
      }
      break;
    case Layout::SoA:
      if (field.componentData.size() != static_cast<std::size_t>(field.components))
      {
        problems.add(name, ": SoA field has ", field.componentData.size(),
                     " component pointers for ", field.components, " components");
      }
      for (std::size_t c = 0; c < field.componentData.size(); ++c)
      {
        if (field.componentData[c] == nullptr && field.numberOfTuples > 0)
        {
          problems.add(name, ": component ", c, " pointer is null");
        }
      }
      break;
    case Layout::Indirect:
      if (field.tupleAddresses == nullptr && field.numberOfTuples > 0)
      {
        problems.add(name, ": tupleAddresses pointer is null");
        break;
      }
      for (std::size_t i = 0; i < field.numberOfTuples; ++i)
      {
        const void* address = field.tupleAddresses[i];
        if (address == nullptr || misaligned(address, valueSize))
        {
          problems.add(name, ": the address of tuple ", i,
                       address == nullptr ? " is null" : " is not aligned to its values");
          break;
        }
      }
      break;
    case Layout::Blocks:
      problems.add(name, ": a block field (Layout::Blocks) needs a block forest "
                         "(ForestDescription::blockCellsPerSide > 0)");
      continue;
    default:
      problems.add(name, ": unknown layout");
      continue;
    }
    // Values are read as T: pointers must be aligned to the value size.
    if (field.layout == Layout::SoA)
    {
      for (std::size_t c = 0; c < field.componentData.size(); ++c)
      {
        if (misaligned(field.componentData[c], valueSize))
        {
          problems.add(name, ": component ", c, " pointer is not aligned to its ", valueSize,
                       "-byte values");
        }
      }
    }
    else if (field.layout != Layout::Indirect && misaligned(field.data, valueSize))
    {
      problems.add(name, ": data pointer is not aligned to its ", valueSize, "-byte values");
    }
    const bool leavesOnly = field.centering == Centering::LeavesOnly;
    if (leavesOnly && field.type != ValueType::Float32 && field.type != ValueType::Float64)
    {
      problems.add(name, ": a leaves-only field must be floating point, coarse values are "
                         "volume averages");
    }
    const std::size_t needed = leavesOnly ? layout.totalPresentLeaves : layout.totalPresentNodes;
    if (field.numberOfTuples < needed)
    {
      problems.add(name, ": ", field.numberOfTuples, " tuples given but the forest has ", needed,
                   leavesOnly ? " leaves" : " nodes",
                   layout.anyAbsent ? " that are not absent" : "");
    }
  }
}

} // namespace

InvalidForest::InvalidForest(std::vector<std::string> problems)
    : std::invalid_argument(joinLines(problems)), Problems(std::move(problems))
{
}

ForestCounts validateForest(const ForestDescription& forest)
{
  const ForestLayout layout = layoutForest(forest);
  ForestCounts counts;
  counts.totalNodes = layout.totalNodes;
  counts.totalCells = layout.totalCells;
  counts.numberOfBlocks = layout.totalBlocks;
  counts.totalLeaves = layout.totalLeaves;
  counts.totalPresentNodes = layout.totalPresentNodes;
  counts.totalPresentLeaves = layout.totalPresentLeaves;
  counts.numberOfRootCells = layout.numberOfRootCells;
  counts.anyMask = layout.anyMask;
  counts.anyAbsent = layout.anyAbsent;
  return counts;
}

ForestLayout layoutForest(const ForestDescription& forest, const ValidatedTrees* known)
{
  ProblemList problems;
  ForestLayout layout;
  if (forest.dimension < 1 || forest.dimension > 3)
  {
    problems.add("dimension must be 1, 2 or 3, got ", forest.dimension);
  }
  if (forest.branchFactor != 2 && forest.branchFactor != 3)
  {
    problems.add("branchFactor must be 2 or 3, got ", forest.branchFactor);
  }
  else if (forest.maxLevels < 1 || forest.maxLevels > maxSupportedLevels(forest.branchFactor))
  {
    problems.add("maxLevels must be in [1, ", maxSupportedLevels(forest.branchFactor),
                 "] for branch factor ", forest.branchFactor, ", got ", forest.maxLevels);
  }
  if (!problems.empty())
  {
    // Every later check depends on these three.
    throw InvalidForest(problems.take());
  }
  validateRootGrid(forest, layout, problems);
  if (problems.empty())
  {
    validateTrees(forest, layout, problems, known);
  }
  if (problems.empty() && forest.blockCellsPerSide != 0)
  {
    layoutBlocks(forest, layout, problems);
    if (problems.empty())
    {
      validateBlockFields(forest, layout, problems);
    }
  }
  else if (problems.empty())
  {
    for (std::size_t t = 0; t < forest.trees.size(); ++t)
    {
      if (forest.trees[t].blockIndex != nullptr)
      {
        problems.add(treeName(t, forest.trees[t]),
                     ": a blockIndex needs a block forest (blockCellsPerSide > 0)");
      }
    }
    validateFields(forest, layout, problems);
  }
  if (!problems.empty())
  {
    throw InvalidForest(problems.take());
  }
  return layout;
}

} // namespace canopy
