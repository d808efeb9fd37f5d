// The walk of one tree that draws the adaptive surface (AdaptiveSurfaceBuilder.h
// says what it computes and why), as every dimension shares it: enter each
// node depth first (TreeTraversal.h), skip what is masked or outside the view,
// stop at leaves or where level of detail says, and draw the node there. What
// drawing means is the dimension's: a segment or a quad (PlanarSurfaceWalk.h),
// the exposed faces of a solid (SolidSurfaceWalk.h). So VTK's geometry filter
// splits its work too (vtkHyperTreeGridGeometryImpl and its per-dimension
// subclasses): the rules every dimension must apply alike live here once.
#pragma once

#include "AdaptiveSurfaceBuilder.h"
#include "CellSink.h"
#include "EdgeVertices.h"
#include "HyperTreeAccess.h"
#include "SiblingDecisions.h"
#include "TreeTraversal.h"
#include "Vec3.h"

#include <vtkType.h>

#include <array>
#include <vector>

namespace canopy
{

class GridSection;

class SurfaceWalk
{
public:
  /// `region`: 1D and 2D culling (the view's section by the grid), or nullptr
  /// (3D, or no culling): then the view volume culls.
  SurfaceWalk(const HyperTreeAccess& grid, const TreeAccess& tree, const SurfaceOptions& options,
              const GridSection* region, CellSink& out);
  virtual ~SurfaceWalk() = default;
  SurfaceWalk(const SurfaceWalk&) = delete;
  SurfaceWalk& operator=(const SurfaceWalk&) = delete;

  /// Walks the tree from its root, drawing into the sink.
  void walk();

protected:
  ///@{
  /// What a dimension adds to the shared walk.
  /// Every node entered, masked or not, before anything is decided about it
  /// (a child of the node entered last one level up): for walks that carry
  /// what lies around a node down the tree.
  virtual void entered(const WalkNode& n) = 0;
  /// Whether anything at or below a refined, unmasked node can be drawn (a
  /// topology fact; a node that cannot is skipped before its box is made).
  virtual bool mayDrawBelow(const WalkNode& n) = 0;
  /// Whether level of detail stops at a node whose box is [lo, hi]: the
  /// footprint of its distinct corners is at most the pixel threshold.
  virtual bool footprintStops(const Vec3& lo, const Vec3& hi) const = 0;
  /// Draws the node where descent stopped (a leaf, or what level of detail
  /// draws whole). Its box and global index are known when the sink takes the
  /// cells' contents (CellSink::takesContents), else only counted.
  virtual void draw(const WalkNode& n, const Vec3& lo, const Vec3& hi, vtkIdType global,
                    bool leaf) = 0;
  ///@}

  /// Whether level of detail stops at the refined, unmasked node m of tree t:
  /// it spans at most the threshold and has no absent descendant (other ranks
  /// draw their parts of it). Kept for the walk's own tree (SiblingDecisions.h).
  bool lodStopsHere(const TreeAccess& t, const WalkNode& m);

  /// What this walk does at a node of tree t (the rule of walk(); culling
  /// aside, a culled neighbour draws nothing to meet, and a subtree with
  /// nothing to draw is walked like any), for the edge searches (EdgeVertices.h).
  EdgeRole roleAt(const TreeAccess& t, const WalkNode& m);

  /// Keeps the edges (bits of `remote`) of the piece about to be emitted along
  /// which another rank's part was met, and the piece, for the ranks' exchange
  /// (EdgeVertexExchange.h). The piece spans lo to hi in the plane of axes u, v.
  void recordShared(unsigned remote, int u, int v, const Vec3& lo, const Vec3& hi);

  const HyperTreeAccess& grid;
  const TreeAccess& tree;
  const SurfaceOptions& options;
  const GridSection* region;
  CellSink& out;

  SiblingDecisions decisions;                  ///< level of detail's, kept (lodStopsHere)
  EdgeScratch scratch{};                       ///< the edge searches' memory
  std::array<std::vector<double>, 4> onEdge{}; ///< a piece's edge vertices (polygonAround)
  std::vector<Vec3> polygon{};                 ///< the same piece's points

private:
  /// Whether the box [lo, hi] may be seen. `inside`: set when the whole box is
  /// inside the view (3D; then neither it nor its descendants need another test).
  bool visible(const Vec3& lo, const Vec3& hi, bool& inside) const;
  /// The walk's rule at one node: skip it, descend, or draw it and skip.
  WalkStep enter(WalkNode& n, Vec3& lo, Vec3& hi);
};

} // namespace canopy
