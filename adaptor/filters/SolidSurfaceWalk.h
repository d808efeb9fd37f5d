// The adaptive surface of a 3D tree (SurfaceWalk.h's walk): of each node where
// descent stops, the parts of its six faces that no unmasked node (nor one
// level of detail draws as a solid) covers on the other side (FaceSide.h), as
// polygons carrying the corners of the smaller pieces meeting their edges
// (FaceEdgeVertices.h). What lies around each node is carried down the walk
// (SolidNeighbours.h). A subtree that cannot expose any face is skipped whole;
// what a node's faces see is kept in the access (TreeAccess's memos) for the
// next execution on the same topology. Faces whose other side is another
// rank's are kept to ask that rank (SurfaceOptions::remoteFaces).
#pragma once

#include "FaceSide.h"
#include "SolidNeighbours.h"
#include "SurfaceWalk.h"

namespace canopy
{

class SolidSurfaceWalk final : public SurfaceWalk
{
public:
  /// Precondition: grid.dimension() is 3.
  SolidSurfaceWalk(const HyperTreeAccess& grid, const TreeAccess& tree,
                   const SurfaceOptions& options, CellSink& out);

  /// Enters the nodes from the root down to the one at `level`, `ijk` (drawn
  /// by this rank, so reached through unmasked refined nodes) and returns it: a
  /// face other ranks answered about is emitted as the walk would have.
  WalkNode enterPath(int level, const Index3& ijk);

  /// Face of [lo, hi] (the box of node n, drawn, the node entered last at its
  /// level) normal to `axis` on side `side` (0 low, 1 high), restricted on the
  /// two other axes to [plo, phi] (the face of n's cell at `pieceLevel`,
  /// `pieceIJK`: n's own, or a finer one inside it facing a finer hole),
  /// outward-oriented, with the corners of the pieces meeting its edges
  /// (FaceEdgeVertices.h).
  void emitFace(int axis, int side, const WalkNode& n, const Vec3& lo, const Vec3& hi,
                const Vec3& plo, const Vec3& phi, int pieceLevel, const Index3& pieceIJK,
                vtkIdType global, bool inside);

private:
  void entered(const WalkNode& n) override { around.enter(n); }
  bool mayDrawBelow(const WalkNode& n) override;
  bool footprintStops(const Vec3& lo, const Vec3& hi) const override
  {
    return faces.lodStops(lo, hi);
  }
  /// For each of the six faces of a node where descent stopped: the parts not
  /// covered by unmasked (or solid-by-level-of-detail) nodes on the other side;
  /// with remote faces, the faces whose other side is partly another rank's are
  /// kept to ask that rank.
  void draw(const WalkNode& n, const Vec3& lo, const Vec3& hi, vtkIdType global,
            bool leaf) override;

  /// Whether the face normal to `axis` on side `side` at coordinate x is turned
  /// away from the camera and back faces are skipped.
  bool turnedAway(int axis, int side, double x) const
  {
    if (!options.view || !options.skipBackFaces)
    {
      return false;
    }
    const double outward = side ? 1.0 : -1.0;
    const double facing = options.view->parallel()
                              ? outward * options.view->directionOfProjection()[axis]
                              : outward * (x - options.view->position()[axis]);
    return facing >= 0;
  }
  /// Whether any face inside an unmasked node's subtree can be exposed: yes if
  /// something below it is masked or a neighbour region across one of its
  /// faces is not solid (absent, masked, or with masked parts).
  bool mayExposeInside(const WalkNode& n);

  FaceSide faces;
  SolidNeighbours around; ///< the nodes around each node of the walk's path
};

} // namespace canopy
