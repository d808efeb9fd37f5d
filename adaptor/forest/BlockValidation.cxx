#include "BlockValidation.h"

#include "DescriptionChecks.h"
#include "ProblemList.h"
#include "StorageSlots.h"

#include <cstdint>
#include <limits>
#include <sstream>
#include <vector>

namespace canopy
{
namespace
{

std::string powersOf(int branchFactor)
{
  std::ostringstream out;
  for (int n = branchFactor, k = 0; k < 5; n *= branchFactor, ++k)
  {
    out << (k ? ", " : "") << n;
  }
  return out.str();
}

/// The grid's tree of one described tree: blocks at each level add bf^(d s) cells at
/// s levels below. Returns false (with a problem) when it does not fit.
bool layoutTreeWithBlocks(const ForestDescription& forest, std::size_t t, TreeLayout& shape,
                          int blockLevels, ProblemList& problems)
{
  const TreeDescription& tree = forest.trees[t];
  const std::size_t children = childrenPerNode(forest);
  std::vector<std::size_t> cellsAtLevel;
  std::size_t levelStart = 0;
  std::size_t levelSize = 1;
  std::size_t blocks = 0;
  for (std::size_t level = 0; levelSize > 0; ++level)
  {
    const std::size_t refined = countNonZero(tree.refinement + levelStart, levelSize);
    const std::size_t absent = tree.absent ? countNonZero(tree.absent + levelStart, levelSize) : 0;
    const std::size_t leaves = levelSize - refined - absent; // each a block
    blocks += leaves;
    cellsAtLevel.resize(std::max(cellsAtLevel.size(), level + 1 + blockLevels * (leaves > 0)), 0);
    cellsAtLevel[level] += levelSize;
    std::size_t cellsPerBlock = 1;
    for (int s = 1; leaves > 0 && s <= blockLevels; ++s)
    {
      cellsPerBlock *= children;
      cellsAtLevel[level + static_cast<std::size_t>(s)] += leaves * cellsPerBlock;
    }
    levelStart += levelSize;
    levelSize = refined * children;
  }
  const int levels = static_cast<int>(cellsAtLevel.size());
  std::size_t cells = 0;
  for (std::size_t count : cellsAtLevel)
  {
    cells += count;
  }
  if (levels > forest.maxLevels)
  {
    problems.add(treeName(t, tree), ": with the ", blockLevels,
                 " levels of cells inside its blocks it has ", levels,
                 " levels, more than maxLevels = ", forest.maxLevels);
    return false;
  }
  // vtkHyperTree stores child offsets as unsigned int.
  if (cells >= std::numeric_limits<unsigned int>::max())
  {
    problems.add(treeName(t, tree), ": ", cells,
                 " cells with its blocks' exceed what one vtkHyperTree can index");
    return false;
  }
  shape.cells = cells;
  shape.levels = levels;
  shape.descriptorBits = cells - cellsAtLevel.back();
  shape.blocks = blocks;
  return true;
}

void validateBlockOrder(const ForestDescription& forest, const ForestLayout& layout,
                        ProblemList& problems)
{
  std::size_t withIndex = 0;
  for (const TreeDescription& tree : forest.trees)
  {
    withIndex += tree.blockIndex != nullptr;
  }
  if (withIndex == 0)
  {
    return;
  }
  if (withIndex != forest.trees.size())
  {
    problems.add("block order: ", withIndex, " of ", forest.trees.size(),
                 " trees have a blockIndex map; either every tree has one or none does");
    return;
  }
  std::vector<bool> used(layout.totalBlocks, false);
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeDescription& tree = forest.trees[t];
    for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
    {
      if (tree.refinement[n] || (tree.absent && tree.absent[n]))
      {
        continue;
      }
      const std::int64_t block = tree.blockIndex[n];
      if (block < 0 || static_cast<std::size_t>(block) >= layout.totalBlocks)
      {
        problems.add(treeName(t, tree), ": leaf ", n, " has blockIndex ", block, " outside [0, ",
                     layout.totalBlocks, ") (the forest has ", layout.totalBlocks, " blocks)");
        return;
      }
      if (used[static_cast<std::size_t>(block)])
      {
        problems.add(treeName(t, tree), ": leaf ", n, " reuses blockIndex ", block,
                     " of another leaf");
        return;
      }
      used[static_cast<std::size_t>(block)] = true;
    }
  }
}

/// A table of one address per block: every entry present and aligned.
void checkAddressTable(const std::string& name, const char* what, const void* const* table,
                       std::size_t blocks, std::size_t valueSize, ProblemList& problems)
{
  if (table == nullptr)
  {
    if (blocks > 0)
    {
      problems.add(name, ": ", what, " is null");
    }
    return;
  }
  for (std::size_t b = 0; b < blocks; ++b)
  {
    if (table[b] == nullptr || misaligned(table[b], valueSize))
    {
      problems.add(name, ": ", what, " of block ", b,
                   table[b] == nullptr ? " is null" : " is not aligned to its values");
      return;
    }
  }
}

} // namespace

int blockLevelsOf(int cellsPerSide, int branchFactor)
{
  int levels = 0;
  long long n = 1;
  while (n < cellsPerSide)
  {
    n *= branchFactor;
    ++levels;
  }
  return n == cellsPerSide && levels >= 1 ? levels : -1;
}

void layoutBlocks(const ForestDescription& forest, ForestLayout& layout, ProblemList& problems)
{
  const int n = forest.blockCellsPerSide;
  const int blockLevels = blockLevelsOf(n, forest.branchFactor);
  if (blockLevels < 0)
  {
    problems.add("blockCellsPerSide must be a power of the branch factor ", forest.branchFactor,
                 " (", powersOf(forest.branchFactor), ", ...), got ", n,
                 ": the cells of a block become uniform levels of the grid below the block's "
                 "leaf, each level splitting a cell ",
                 forest.branchFactor, " ways along each axis");
    return;
  }
  layout.blockLevels = blockLevels;
  bool shapesValid = true;
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    if (forest.trees[t].storageSlots != nullptr)
    {
      problems.add(treeName(t, forest.trees[t]),
                   ": storageSlots have no use in a block forest (its fields are per block; "
                   "blockIndex gives the blocks your order)");
      shapesValid = false;
    }
  }
  layout.totalCells = 0;
  layout.totalBlocks = 0;
  layout.totalDescriptorBits = 0;
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    TreeLayout& shape = layout.trees[t];
    if (!layoutTreeWithBlocks(forest, t, shape, blockLevels, problems))
    {
      shapesValid = false;
      continue;
    }
    shape.firstCell = layout.totalCells;
    layout.totalCells += shape.cells;
    layout.totalBlocks += shape.blocks;
    layout.totalDescriptorBits += shape.descriptorBits;
  }
  if (shapesValid)
  {
    validateBlockOrder(forest, layout, problems);
  }
}

void validateBlockFields(const ForestDescription& forest, const ForestLayout& layout,
                         ProblemList& problems)
{
  const int axes = forest.dimension;
  for (std::size_t f = 0; f < forest.fields.size(); ++f)
  {
    const FieldDescription& field = forest.fields[f];
    std::ostringstream label;
    label << "field " << f << " '" << field.name << "'";
    const std::string name = label.str();
    if (field.layout != Layout::Blocks)
    {
      problems.add(name, ": a block forest's fields are block fields (Layout::Blocks, "
                         "FieldDescription::blocks): a field per node has no values for the "
                         "cells inside blocks");
      continue;
    }
    if (field.type != ValueType::Float32 && field.type != ValueType::Float64)
    {
      problems.add(name, ": a block field must be floating point, coarse values are volume "
                         "averages");
      continue;
    }
    if (field.numberOfBlocks < layout.totalBlocks)
    {
      problems.add(name, ": ", field.numberOfBlocks, " blocks given but the forest has ",
                   layout.totalBlocks, layout.anyAbsent ? " blocks on this rank" : " blocks");
      continue;
    }
    const std::size_t valueSize = sizeOf(field.type);
    const BlockStrides& strides = field.blockStrides;
    for (int a = 0; a < axes; ++a)
    {
      const std::size_t stride = strides.cellBytes[static_cast<std::size_t>(a)];
      const int ghosts = strides.ghostCells[static_cast<std::size_t>(a)];
      if (stride == 0 || stride % valueSize != 0)
      {
        problems.add(name, ": blockStrides.cellBytes[", a, "] = ", stride,
                     " must be a nonzero multiple of the value size ", valueSize);
      }
      if (ghosts < 0)
      {
        problems.add(name, ": blockStrides.ghostCells[", a, "] = ", ghosts, " is negative");
      }
    }
    const bool separate = !field.componentBlockAddresses.empty();
    if (!separate && field.components > 1 &&
        (strides.componentBytes == 0 || strides.componentBytes % valueSize != 0))
    {
      problems.add(name, ": blockStrides.componentBytes = ", strides.componentBytes,
                   " must be a nonzero multiple of the value size ", valueSize, " for ",
                   field.components, " components");
    }
    const int sources =
        (field.blockAddresses != nullptr) + (field.data != nullptr) + (separate ? 1 : 0);
    if (sources > 1)
    {
      problems.add(name, ": give exactly one of blockAddresses, data with blockStrideBytes, "
                         "or componentBlockAddresses");
      continue;
    }
    const std::size_t blocks = layout.totalBlocks;
    if (separate)
    {
      if (field.componentBlockAddresses.size() != static_cast<std::size_t>(field.components))
      {
        problems.add(name, ": ", field.componentBlockAddresses.size(),
                     " component address tables for ", field.components, " components");
        continue;
      }
      for (std::size_t c = 0; c < field.componentBlockAddresses.size(); ++c)
      {
        const std::string what = "the address table of component " + std::to_string(c);
        checkAddressTable(name, what.c_str(), field.componentBlockAddresses[c], blocks, valueSize,
                          problems);
      }
    }
    else if (field.data != nullptr)
    {
      if (misaligned(field.data, valueSize))
      {
        problems.add(name, ": data pointer is not aligned to its ", valueSize, "-byte values");
      }
      if (blocks > 1 && (field.blockStrideBytes == 0 || field.blockStrideBytes % valueSize != 0))
      {
        problems.add(name, ": blockStrideBytes = ", field.blockStrideBytes,
                     " must be a nonzero multiple of the value size ", valueSize);
      }
    }
    else
    {
      checkAddressTable(name, "blockAddresses", field.blockAddresses, blocks, valueSize, problems);
    }
  }
}

} // namespace canopy
