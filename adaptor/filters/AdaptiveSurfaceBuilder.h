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

#include "EdgeVertexExchange.h"
#include "HyperTreeAccess.h"
#include "LeafColorAverage.h"
#include "TreeProgress.h"
#include "ViewVolume.h"

#include <vtkType.h>

#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace canopy
{

/// The view (ViewVolume.h: without one, the full surface) and the surface's own switches.
struct SurfaceOptions : ViewOptions
{
  // With a colour map (ViewOptions::colors): 1D and 2D nodes drawn for level of
  // detail average their leaves' colours; 3D faces show their node's mapped value.
  bool skipBackFaces = false; ///< 3D only
  /// 3D, trees split between ranks or on other ranks: faces whose other side is
  /// another rank's are not taken as covered but collected (remoteFaces()) for
  /// the ranks that own that side to answer (answerRemoteFaces()): needed as
  /// soon as any rank has a mask, since only the owner knows what it masks.
  /// Off: another rank's part is solid (exact when no rank masks anything).
  bool remoteFaces = false;
  /// 2D and 3D, grids split between ranks: the edges of drawn pieces along
  /// another rank's part are collected (sharedEdges()) so that the ranks can
  /// put their pieces' corners there (EdgeVertexExchange.h). 3D collects them
  /// always; 2D then keeps its cells to add them before writing.
  bool sharedVertices = false;
  /// 3D: keep what each node's faces see (a topology and mask fact) in the
  /// access, for the next execution on the same access (a camera move). Off for
  /// an access used once (a new mask each step): the memos would cost more
  /// fresh memory than they save.
  bool memoize = true;
};

/// A face of a drawn 3D node whose other side is, in part or whole, another
/// rank's: what the owner needs to find its side (the node's root cell, level
/// and integer position, the face's axis and side).
struct RemoteFace
{
  std::array<std::int64_t, 3> root;
  std::int64_t level;
  std::array<std::int64_t, 3> ijk;
  std::int64_t axis;
  std::int64_t side;
  /// Values per face on the wire (RemoteFace <-> int64).
  static constexpr std::size_t Values = 9;
};

/// An owner's answer: a piece of a remote face to draw, because the owner masks
/// the cells there. `whole`: the asking node's whole face (the owner's masked
/// node is as large or larger); else the owner's masked node's box on the face,
/// and that node's level and integer position (the asking rank looks for the
/// pieces meeting its edges there: EdgeVertices.h).
struct RemotePiece
{
  std::size_t face; ///< index in the asking rank's remoteFaces()
  bool whole;
  Vec3 lo;
  Vec3 hi;
  std::int64_t level = 0;
  std::array<std::int64_t, 3> ijk{{0, 0, 0}};
  /// Values per piece on the wire (RemotePiece <-> double).
  static constexpr std::size_t Values = 12;
};

/// Output buffers: 3 doubles per point; per cell, where its points start
/// (`offsets`: one more entry than cells, the last the number of points), its
/// cell id and its level. A segment (1D) has 2 points; a flat piece (a quad) 4,
/// or more where finer neighbours' corners lie on its edges (EdgeVertices.h).
struct SurfaceArrays
{
  double* points;
  vtkIdType* offsets;
  vtkIdType* cellIds;
  unsigned char* levels;
  unsigned char* colors = nullptr; ///< RGB per cell, with SurfaceOptions::colors
};

/// A remote face as the asking rank keeps it, to draw the pieces it is sent.
struct AskedFace
{
  RemoteFace face;
  vtkIdType global;
  bool inside; ///< the node is inside the view volume
};

/// One tree's cells, kept by the counting pass when it is cheaper to copy them
/// than to walk the tree again (3D), and its faces to ask other ranks about.
struct TreeCells
{
  std::vector<double> points;
  std::vector<std::uint32_t> sizes; ///< points per cell
  std::vector<vtkIdType> cellIds;
  std::vector<unsigned char> levels;
  std::vector<unsigned char> colors; ///< RGB, with a colour map
  std::vector<AskedFace> asked;
  std::vector<SharedEdge> shared;         ///< edges along another rank's part
  std::vector<std::uint32_t> sharedCells; ///< the cells with such an edge, ascending
};

/// Copies the cells kept per tree (or per piece) into `arrays`, each list at
/// its offsets (`cellOffsets` in cells, `pointOffsets` in points: prefix sums
/// with one more entry than `kept`), in parallel; writes the last offset too.
void copyKeptCells(const std::vector<TreeCells>& kept, const std::vector<std::size_t>& cellOffsets,
                   const std::vector<std::size_t>& pointOffsets, const SurfaceArrays& arrays);

class GridSection;

/// Two passes over the trees (in parallel with vtkSMPTools): count, then write
/// each tree's cells at its offset. The output is allocated once, in its final
/// place; its order is the tree order for any number of threads. A full 1D/2D
/// surface of a kept access is not counted (the access knows its leaves) and is
/// written by a walk of its own (no view to test: the cost is the output); a 3D
/// surface, and a 2D one with level of detail (its output bounded by the view's
/// pixels), is walked once, its cells kept per tree and copied.
class AdaptiveSurfaceBuilder
{
public:
  /// `buffers`: per-tree cell buffers lent for the builder's life (their
  /// capacity kept between executions: fresh memory costs page faults); they
  /// are given back, emptied or not, when the builder is destroyed.
  /// `progress`: where the walks of count() and write() report and learn that
  /// the execution was aborted; stopped, they leave out the trees not begun,
  /// and their results are to be discarded.
  AdaptiveSurfaceBuilder(const HyperTreeAccess& grid, const SurfaceOptions& options,
                         std::vector<TreeCells>* buffers = nullptr,
                         const ProgressShare& progress = {});
  ~AdaptiveSurfaceBuilder();
  AdaptiveSurfaceBuilder(const AdaptiveSurfaceBuilder&) = delete;
  AdaptiveSurfaceBuilder& operator=(const AdaptiveSurfaceBuilder&) = delete;
  /// Number of cells (quads, or segments in 1D); call before write(). With
  /// remoteFaces, the pieces other ranks send (addRemotePieces) come on top.
  std::size_t count();

  ///@{
  /// Ranks' exchange (remoteFaces on): after count(), the faces to ask the other
  /// ranks about; each rank answers every other rank's faces for the parts it
  /// owns; the asking rank adds the pieces it was sent, then writes. The same
  /// view, level-of-detail threshold and options must be used on every rank.
  std::vector<RemoteFace> remoteFaces() const;
  std::vector<RemotePiece> answerRemoteFaces(const std::vector<RemoteFace>& faces) const;
  void addRemotePieces(const std::vector<RemotePiece>& pieces);
  /// The pieces' edges along another rank's part (after count() and the remote
  /// pieces), and then the vertices every rank's such edges put on them
  /// (EdgeVertexExchange.h); cells() and points() count them.
  std::vector<SharedEdge> sharedEdges() const;
  void addSharedVertices(const SharedVertices& shared);
  /// Cells in all: count() plus the pieces added since.
  std::size_t cells() const { return Offsets.empty() ? 0 : Offsets.back(); }
  ///@}
  /// Points of those cells, all together.
  std::size_t points() const { return PointOffsets.empty() ? 0 : PointOffsets.back(); }
  /// Whether the cells are segments (1D grids: VTK_LINE) rather than polygons.
  bool segments() const { return Grid.dimension() == 1; }
  /// Fills arrays sized for cells() cells and points() points.
  void write(const SurfaceArrays& arrays) const;

private:
  /// A 1D or 2D surface with neither culling nor level of detail: every visible
  /// leaf, counted by the access and written by FullSurfaceWalk.
  bool fullPlanarSurface() const;

  const HyperTreeAccess& Grid;
  SurfaceOptions Options;
  ProgressShare Progress;
  bool CountWalked = false;            ///< count() walked the trees: write() has half the progress
  std::unique_ptr<GridSection> Region; ///< 1D/2D culling region, built once for both passes
  void computeOffsets(const std::vector<std::size_t>& counts,
                      const std::vector<std::size_t>& pointCounts);

  std::vector<std::size_t> Offsets;       ///< per tree, its first cell (prefix sums)
  std::vector<std::size_t> PointOffsets;  ///< per tree, its first point
  std::vector<TreeCells> Kept;            ///< per tree, when the counting pass kept the cells
  std::vector<TreeCells>* Lent = nullptr; ///< where Kept's buffers came from
  /// Where remoteFaces() entries come from: (tree, position in its asked list).
  std::vector<std::pair<std::size_t, std::size_t>> AskedAt;
};

} // namespace canopy
