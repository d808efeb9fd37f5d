// Contours one dual cell (DualTraversal.h) at a time: its dual vertices, its
// split into triangles (2D) or tetrahedra (3D), and marching triangles or
// tetrahedra on each, into a ContourPiece.
//
// Dual vertices: a visible leaf's centre and value; an Outside slot (a vertex on
// the domain's boundary) becomes the boundary vertex of the leaf it mirrors (the
// slot with the outside bits flipped): that leaf's centre projected onto the
// boundary sides, its value extrapolated linearly with the leaf's gradient
// (LeafGradient.h), so a linear field stays linear up to the boundary. A cell
// with a Hidden slot is not contoured (the contour ends there).
//
// The split: Kuhn's. Every simplex contains the cell's diagonal from slot 0
// (all lower sides) to slot 2^d - 1 (all upper sides), which passes through
// the grid vertex the cell surrounds: 2 triangles, 6 tetrahedra. A face shared
// by two 3D cells is the 4 leaves around a grid edge, seen by both cells with
// the same slots along the two other axes, so both split it by the same
// diagonal (lower-lower to upper-upper leaf): the tetrahedra of neighbouring
// cells meet face to face, and marching tetrahedra leaves no crack and has no
// ambiguous case. (The brief's rule, the diagonal through the face's smallest
// leaf id, is consistent too but needs tetrahedra around a centroid in every
// cell; Kuhn's needs neither ids nor a centroid where it does not fold.)
// Simplices with a repeated vertex (a leaf filling several slots) have no
// volume and are dropped; their two faces without the repeated edge are the
// same triangle, which the neighbouring simplices share.
//
// Folds. Within a tree all leaves have one aspect ratio and, where all 2^d
// leaves are distinct, their centres lie on the (scaled) diagonals through the
// vertex: every Kuhn simplex is positively oriented. A leaf filling several
// slots can have its centre far off that diagonal, and trees of other shapes
// can meet: then a Kuhn simplex can be inverted (it folds over its neighbours:
// still watertight, but the contour overlaps itself there). 2D: the quad's
// other diagonal, inside it (no other cell shares a 2D cell's diagonal). 3D:
// the cell's boundary (its faces' Kuhn triangles, the degenerate ones dropped,
// a triangle met twice, inside the cell, dropped both times), cut into parts
// where it pinches (two wedges sharing an edge), each part a fan of
// tetrahedra from one apex: the mean of its vertices, their mean weighted by
// the slots they fill, or one of them (the first that folds nothing, else the
// least folding one; a point inside has as value the same combination of its
// vertices' values: exact for a linear field). A part that is not closed:
// Kuhn's simplices (their boundary is the same). Graded forests (level jumps
// of one) come out fold-free in the tests (a linear field's area exact);
// around jumps of several levels some dual cells are not star-shaped from any
// candidate and still fold a little (docs/filters.md).
//
// Orientation: 2D segments run with the higher values on their left; 3D
// triangles' normals (right-hand rule) point towards lower values.
//
// Tested by tests/unit/ContourTest.cxx: *.Watertight* (cracks), *.LinearField*
// (every vertex on the plane, exact area on graded forests, normals),
// ContourConvergence.SphereAreaAndVolume (second order; the enclosed volume by
// the divergence theorem needs every triangle oriented alike), *.UniformForest*
// (the same edge crossings as VTK's contour of an image).
#pragma once

#include "ContourField.h"
#include "ContourPiece.h"
#include "DualTraversal.h"
#include "LeafGradient.h"
#include "NodeRanges.h"

#include <array>
#include <cstddef>
#include <unordered_map>
#include <vector>

namespace canopy
{

class DualCellContour
{
public:
  /// Everything is borrowed and must outlive this; `values`: the contour
  /// values, their index the points' `contour`; `out`: where cells go;
  /// `ranges`: the nodes' value ranges to prune with (nullptr: no pruning).
  DualCellContour(const HyperTreeAccess& grid, const DualTraversal& dual, const ContourField& field,
                  const std::vector<double>& values, ContourPiece& out,
                  const NodeRanges* ranges = nullptr, bool cull = false);

  /// DualTraversal's visitor. A group is not descended when the union of its
  /// nodes' ranges holds no contour value: every dual cell below it joins
  /// leaves of those nodes' subtrees only (and their boundary vertices, whose
  /// values the ranges cover).
  bool enter(const DualGroup& group, unsigned axes);
  void cell(const DualGroup& group);

  /// Groups descended, groups pruned, and dual cells met (contoured or not).
  std::size_t visited() const { return Visited; }
  std::size_t pruned() const { return Pruned; }
  std::size_t culled() const { return Culled; }
  std::size_t dualCells() const { return DualCells; }

private:
  /// Whether a leaf touches no side of its tree (ContourPiece.h: DualVertex::own).
  bool insideItsTree(const DualNode& leaf) const;
  /// Slot s's dual vertex; false when the cell is not contoured (Hidden).
  bool vertex(const DualGroup& group, unsigned s, DualVertex& v);
  void triangle(const DualVertex& a, const DualVertex& b, const DualVertex& c);
  void tetrahedron(const DualVertex* v[4]);
  /// Out.point, through a small cache of the current cell's edges (each edge
  /// is in several of its tetrahedra).
  vtkIdType point(const DualVertex& a, const DualVertex& b, std::uint32_t contour, double value);
  /// A 3D cell as tetrahedra from centroids to its boundary's triangles, one
  /// centroid per part of the boundary that pinches; false (nothing done)
  /// when a part is not closed.
  bool centroidFan(const std::array<DualVertex, 8>& v);

  const HyperTreeAccess& Grid;
  const DualTraversal& Dual;
  const ContourField& Field;
  const std::vector<double>& Values;
  ContourPiece& Out;
  LeafGradient Gradient;
  /// Gradients of the boundary leaves already met (each is met by several cells).
  std::unordered_map<vtkIdType, std::array<double, 3>> Gradients;
  const NodeRanges* Ranges = nullptr;
  bool Cull = false;
  /// The current cell is drawn by another rank (its triangles only inform normals).
  bool Foreign = false;
  struct CachedPoint
  {
    std::uint64_t a;
    std::uint64_t b;
    std::uint32_t contour;
    vtkIdType id;
  };
  std::array<CachedPoint, 32> Cache;
  std::size_t Cached = 0;
  std::size_t Visited = 0;
  std::size_t Pruned = 0;
  std::size_t Culled = 0;
  std::size_t DualCells = 0;
};

} // namespace canopy
