// The geometry of Canopy's adaptive slices of 3D grids, independent of VTK's
// pipeline.
//
// A slice is an axis-aligned plane x_a = p. It is drawn as one quad per node
// where descent stops: the node's cross-section by the plane. A tree is entered
// only when its root cell is cut by the plane, and from each node only the
// children the plane cuts are entered (f^2 of the f^3 children), so the work is
// proportional to the nodes the plane crosses, never to the grid.
//
// Which cells a plane cuts (the face rule, docs/filters.md): cells are half-open
// [lo, hi) along the plane's axis, and the grid's last cell along that axis
// also owns the grid's upper boundary. A plane on a face shared by two cells
// cuts the cell on its upper side; a plane outside the grid cuts nothing. Root
// cells are told apart by the grid's own coordinates, the children of a node by
// the boundaries between them, computed exactly as every filter computes node
// bounds (HyperTreeAccess::nodeBounds): the same answer on every rank.
//
// View culling tests the cross-section itself (a rectangle) against the view
// volume (exact separating axes): a node is entered only if its cut shares a
// positive area with the view. Level of detail: descent stops at a node whose
// cut projects to at most `pixelThreshold` pixels (the largest side of its
// screen-space bounding box) and which has no absent descendant (other ranks'
// parts of a split tree draw themselves: every pixel keeps one owner). For a
// face-on parallel view of a cubic root cell of side S with pixels of size s,
// a binary tree stops at level l = ceil(log2(S / (t s))), so drawn quads are
// between t/2 and t pixels wide: at t = 1, one to four quads per pixel
// (AdaptiveSlice.LevelOfDetailMatchesTheClosedForm).
//
// Masked nodes (and absent ones) are not drawn; a node stopped by level of
// detail is drawn whole with its own (coarse) value, as the adaptive surface
// does.
#pragma once

#include "AdaptiveSurfaceBuilder.h"
#include "HyperTreeAccess.h"
#include "LeafColorAverage.h"
#include "TreeProgress.h"
#include "ViewVolume.h"

#include <cstddef>
#include <string>
#include <vector>

namespace canopy
{

/// The plane x_axis = position.
struct SlicePlane
{
  int axis;
  double position;
};

/// The view (ViewVolume.h: without one, every cut leaf) and, with a colour map,
/// each quad's colour: a node drawn for level of detail shows the area-weighted
/// average of the colours of the cut leaves below it.
using SliceOptions = ViewOptions;

class AdaptiveSliceBuilder
{
public:
  /// Empty when the planes can slice the grid, otherwise what is wrong (a grid
  /// that is not 3D, an axis other than 0, 1, 2, a position that is not finite).
  static std::string validate(const HyperTreeAccess& grid, const std::vector<SlicePlane>& planes);

  /// Precondition: validate(grid, planes) is empty. `progress`: where count()
  /// reports and learns that the execution was aborted; stopped, it leaves out
  /// the trees not begun, and its result is to be discarded.
  AdaptiveSliceBuilder(const HyperTreeAccess& grid, std::vector<SlicePlane> planes,
                       const SliceOptions& options, const ProgressShare& progress = {});

  /// Walks every tree each plane cuts (in parallel over trees) and keeps the
  /// quads; returns their number. The order is plane by plane, and within a
  /// plane tree by tree, for any number of threads.
  std::size_t count();
  /// Points of those quads (4 each, more where finer neighbours' corners lie on
  /// their edges).
  std::size_t points() const { return PointOffsets.empty() ? 0 : PointOffsets.back(); }
  /// Fills arrays sized for count() cells and points() points.
  void write(const SurfaceArrays& arrays) const;
  /// Grids split between ranks, after count(): the quads' edges along another
  /// rank's part, and then the vertices every rank's such edges put on them
  /// (EdgeVertexExchange.h); points() counts them.
  std::vector<SharedEdge> sharedEdges() const;
  void addSharedVertices(const SharedVertices& shared);
  /// Nodes the last count() examined: what the slices cost.
  std::size_t visited() const { return Visited; }

private:
  /// One tree cut by one plane.
  struct Piece
  {
    const TreeAccess* tree;
    std::size_t plane;
  };
  void slice(const Piece& piece, TreeCells& cells, std::size_t& visited) const;

  const HyperTreeAccess& Grid;
  std::vector<SlicePlane> Planes;
  SliceOptions Options;
  ProgressShare Progress;
  std::vector<Piece> Pieces;
  std::vector<TreeCells> Kept;
  std::vector<std::size_t> Offsets;      ///< per piece, its first cell (prefix sums)
  std::vector<std::size_t> PointOffsets; ///< per piece, its first point
  std::size_t Visited = 0;
};

} // namespace canopy
