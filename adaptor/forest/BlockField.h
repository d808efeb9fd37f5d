// One block field of a block forest, read where the simulation keeps it.
//
// A cell's value is found from the cell alone (BlockCells::locate) and the field's
// block addressing: block start + component offset + (position + ghosts) x cell
// strides. No table per cell, no copy. Coarse values follow the leaves-only rule
// (volume averages, the plain mean of a node's equal children) and are computed
// when something reads them:
//  - inside a block, the level just above the cells from its bf^d cells on every
//    read; the levels above that from a per-block pyramid of means, allocated and built on the
//    block's first such read (bf^-2d of the block's cells: 1/64 of them in 3D);
//  - above blocks, a described node's mean of its unmasked children (every present
//    child when all are masked; absent ones left out, as LeafRestriction.h), kept
//    once computed.
// Reads may come from several threads (VTK's SMP filters): each cache is filled
// once under its own std::once_flag.
#pragma once

#include "BlockCells.h"
#include <canopy/ForestDescription.h>

#include <cstddef>
#include <memory>
#include <mutex>
#include <vector>

namespace canopy
{

template <typename T>
class BlockField
{
public:
  BlockField(const FieldDescription& field, std::shared_ptr<const BlockCells> cells);

  int components() const { return Components; }
  std::size_t numberOfCells() const { return Cells->numberOfCells(); }

  /// Component `c` of a cell of the grid.
  T at(std::uint64_t cell, int component) const;
  /// Every component of a cell (one search for the cell, not one per component).
  void tuple(std::uint64_t cell, T* values) const;
  /// Component `c` of interior cell `position` of a block (the simulation's value).
  T leaf(std::size_t block, const std::array<std::uint32_t, 3>& position, int component) const;

  /// Range of each component (ranges[2c], ranges[2c+1]) over every block's interior
  /// cells, NaN skipped (finiteOnly: infinities too). Coarse cells are means of
  /// these, so the grid's range is the same. False for a forest without blocks.
  bool leafRanges(double* ranges, bool finiteOnly) const;
  /// Range of the Euclidean norm over the interior cells, likewise.
  bool leafNormRange(double range[2], bool finiteOnly) const;

private:
  const unsigned char* blockStart(std::size_t block, int component) const;
  double coarseInBlock(std::size_t block, int subLevel,
                       const std::array<std::uint32_t, 3>& position, int component) const;
  double nodeValue(std::size_t node, int component) const;
  void buildPyramid(std::size_t block) const;
  template <typename Visit>
  void forEachLeaf(Visit&& visit) const;

  std::shared_ptr<const BlockCells> Cells;
  int Components = 1;
  std::vector<const void* const*> ComponentTable; ///< per component, or null
  std::vector<std::size_t> ComponentOffset;       ///< bytes, per component
  const unsigned char* Data = nullptr;            ///< one array for every block
  std::size_t BlockStride = 0;
  std::size_t InteriorOffset = 0; ///< bytes from a block's start to its first interior cell
  std::array<std::size_t, 3> CellBytes{{0, 0, 0}};

  // Pyramid of means per block: levels 0 .. blockLevels-2, level s a bf^s-wide
  // cube i fastest, then the components.
  std::size_t PyramidSize = 0; ///< values per block and component
  std::vector<std::size_t> PyramidLevelStart;
  mutable std::unique_ptr<std::unique_ptr<T[]>[]> Pyramids; ///< per block, at its first read
  mutable std::unique_ptr<std::once_flag[]> PyramidBuilt;
  mutable std::unique_ptr<double[]> NodeMean; ///< per described node and component
  mutable std::unique_ptr<std::once_flag[]> NodeMeanBuilt;
};

extern template class BlockField<float>;
extern template class BlockField<double>;

} // namespace canopy
