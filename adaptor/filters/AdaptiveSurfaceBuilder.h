// The geometry of Canopy's adaptive surface, independent of VTK's pipeline.
//
// 1D: one segment per visible node where descent stops; 2D: one quad. 3D: the
// exposed faces (and exposed parts of faces) of the union of unmasked nodes
// where descent stops. Descent into a subtree happens only if its box overlaps
// the view with positive length (1D: the view's section by the grid's line),
// area (2D: its section by the plane) or volume (3D), and stops at leaves or,
// with level of detail on, at nodes whose projection is at most
// `pixelThreshold` pixels.
//
// Level of detail with parallel projection. Let the domain be 1 wide with s
// root cells across, shown zoomed by z (the view is 1/z wide) in w pixels: a
// pixel is 1/(z w) wide and a node at level l is 1/(s f^l) wide (f the branch
// factor). Descent stops at the first level where the node is at most one
// pixel: f^l >= w z / s, i.e. l = (log(w z) - log s) / log f, the paper's
// delta_max. The code does not assume uniform roots: it projects each node's
// corners and compares the screen extent with the threshold t, which for
// parallel projection gives l = ceil(log(S / (t p)) / log f) with S the root
// cell's largest side and p the pixel size (checked by
// AdaptiveSurface2D.LevelOfDetailMatchesTheClosedForm). A 1D grid's segments
// follow the same rule with S the root cell's length along the line (for a line
// across the screen; AdaptiveSurface1D.LevelOfDetailMatchesTheClosedForm).
#pragma once

#include "HyperTreeAccess.h"
#include "ViewVolume.h"

#include <vtkType.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace canopy
{

struct SurfaceOptions
{
  /// The view; nullptr: no culling and no level of detail (the full surface).
  const ViewVolume* view = nullptr;
  bool cullOutsideView = true;
  bool levelOfDetail = true;
  double pixelThreshold = 1.0;
  bool skipBackFaces = false; ///< 3D only
};

/// Output buffers: 3 doubles per point, pointsPerCell() points per cell (4 for a
/// quad, 2 for a segment), one cell id and one level per cell.
struct SurfaceArrays
{
  double* points;
  vtkIdType* cellIds;
  unsigned char* levels;
};

/// Two passes over the trees (in parallel with vtkSMPTools): count, then write
/// each tree's cells at its offset. The output is allocated once, in its final
/// place; its order is the tree order for any number of threads. A full 1D/2D
/// surface of a kept access is not counted (the access knows its leaves) and is
/// written by a walk of its own (no view to test: the cost is the output); a 3D
/// surface is walked once, its cells kept per tree and copied.
class GridSection;

/// One tree's cells, kept by the counting pass when it is cheaper to copy them
/// than to walk the tree again (3D).
struct TreeCells
{
  std::vector<double> points;
  std::vector<vtkIdType> cellIds;
  std::vector<unsigned char> levels;
};

class AdaptiveSurfaceBuilder
{
public:
  AdaptiveSurfaceBuilder(const HyperTreeAccess& grid, const SurfaceOptions& options);
  ~AdaptiveSurfaceBuilder();
  AdaptiveSurfaceBuilder(const AdaptiveSurfaceBuilder&) = delete;
  AdaptiveSurfaceBuilder& operator=(const AdaptiveSurfaceBuilder&) = delete;
  /// Number of cells (quads, or segments in 1D); call before write().
  std::size_t count();
  /// Points per output cell: 2 (segments) for 1D grids, 4 (quads) otherwise.
  std::size_t pointsPerCell() const { return Grid.dimension() == 1 ? 2 : 4; }
  /// Fills arrays sized for count() cells.
  void write(const SurfaceArrays& arrays) const;

private:
  /// A 1D or 2D surface with neither culling nor level of detail: every visible
  /// leaf, counted by the access and written by FullSurfaceWalk.
  bool fullPlanarSurface() const;

  const HyperTreeAccess& Grid;
  SurfaceOptions Options;
  std::unique_ptr<GridSection> Region; ///< 1D/2D culling region, built once for both passes
  std::vector<std::size_t> Offsets;
  std::vector<TreeCells> Kept; ///< per tree, when the counting pass kept the cells
};

} // namespace canopy
