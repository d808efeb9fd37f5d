// The adaptive surface of a 1D or a 2D tree (SurfaceWalk.h's walk): a segment
// (1D) or a quad (2D) per node where descent stops, coloured by its leaves
// when a node stands for several. A 2D quad is a polygon carrying the corners
// of the smaller quads meeting its edges (EdgeVertices.h), found below its
// neighbours, which the walk carries down the tree (PlaneNeighbours).
#pragma once

#include "EdgeVertices.h"
#include "LeafColorAverage.h"
#include "SurfaceWalk.h"

#include <optional>

namespace canopy
{

class PlanarSurfaceWalk final : public SurfaceWalk
{
public:
  /// Precondition: grid.dimension() is 1 or 2.
  PlanarSurfaceWalk(const HyperTreeAccess& grid, const TreeAccess& tree,
                    const SurfaceOptions& options, const GridSection* region, CellSink& out);

private:
  void entered(const WalkNode& n) override;
  bool mayDrawBelow(const WalkNode&) override { return true; }
  bool footprintStops(const Vec3& lo, const Vec3& hi) const override;
  void draw(const WalkNode& n, const Vec3& lo, const Vec3& hi, vtkIdType global,
            bool leaf) override;

  /// A 2D node's quad, with the corners of finer neighbours on its edges.
  void emitPlaneQuad(const WalkNode& n, const Vec3& lo, const Vec3& hi, vtkIdType global,
                     const Rgb* color);
  /// A drawn node's colour: a leaf's own, a coarser node's the average of its
  /// leaves' (only when it is written: counting needs none).
  Rgb colorOf(const WalkNode& n, vtkIdType global, bool leaf) const;

  std::optional<PlaneNeighbours> plane; ///< 2D: the nodes across each node's edges
};

} // namespace canopy
