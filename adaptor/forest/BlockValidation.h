// Validation stages of block forests (ForestDescription::blockCellsPerSide > 0),
// run by layoutForest after the trees' own checks: the block size, the grid's
// trees with the blocks' cells as levels below each block root (their cells,
// levels and descriptor bits in the layout), the block order, and the block fields.
#pragma once

#include "ForestLayout.h"
#include <canopy/ForestDescription.h>

namespace canopy
{

class ProblemList;

/// Levels below a block root for blocks of `cellsPerSide` cells across, or -1 when
/// that is not a power of the branch factor (at least the branch factor itself).
int blockLevelsOf(int cellsPerSide, int branchFactor);

/// Checks the block size, the trees with their blocks (levels, size) and the block
/// order (blockIndex); sets the layout's cells, levels, descriptor bits, first
/// cells and block counts of the grid's trees.
void layoutBlocks(const ForestDescription& forest, ForestLayout& layout, ProblemList& problems);

/// Checks every field of a block forest: block fields only, floating point, one
/// array or address table per block, strides that step over whole values.
void validateBlockFields(const ForestDescription& forest, const ForestLayout& layout,
                         ProblemList& problems);

} // namespace canopy
