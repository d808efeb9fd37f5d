// Where a surface walk's cells go (AdaptiveSurfaceBuilder.h's two passes):
// counted in the first pass and written in place in the second, so the output
// is allocated once and never grown or copied; or kept in a tree's own buffer
// when walking once and copying is cheaper (3D, split 2D grids).
#pragma once

#include "AdaptiveSurfaceBuilder.h"
#include "LeafColorAverage.h"
#include "Vec3.h"

#include <vtkType.h>

#include <array>
#include <cstddef>

namespace canopy
{

struct CellSink
{
  SurfaceArrays arrays{nullptr, nullptr, nullptr, nullptr};
  std::size_t next = 0;      ///< cells so far
  std::size_t nextPoint = 0; ///< points so far
  bool counting = true;
  std::size_t limit = 0;      ///< writing: cells the buffer holds (never written past)
  std::size_t pointLimit = 0; ///< writing: points the buffer holds
  std::size_t pointBase = 0;  ///< writing: the output's index of this buffer's first point
  /// Counting into a tree's own buffer (3D: the output is small next to the
  /// walk, so it is walked once and copied, not walked twice).
  TreeCells* keep = nullptr;

  /// Whether the cells' contents are used (written or kept), not only counted:
  /// what only they need (ids, boxes, colours) is skipped otherwise.
  bool takesContents() const { return !counting || keep; }

  /// A cell of `count` points (4 or more: a flat piece; 2: a segment of a 1D
  /// grid). `color`: the cell's RGB (nullptr without a colour map).
  void emit(const Vec3* points, std::size_t count, vtkIdType cellId, int level, const Rgb* color);

  template <std::size_t N>
  void emit(const std::array<Vec3, N>& corners, vtkIdType cellId, int level, const Rgb* color)
  {
    emit(corners.data(), N, cellId, level, color);
  }
};

} // namespace canopy
