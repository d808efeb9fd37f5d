#include "PlanarSurfaceWalk.h"

namespace canopy
{

PlanarSurfaceWalk::PlanarSurfaceWalk(const HyperTreeAccess& grid, const TreeAccess& tree,
                                     const SurfaceOptions& options, const GridSection* region,
                                     CellSink& out)
    : SurfaceWalk(grid, tree, options, region, out)
{
  if (grid.dimension() == 2)
  {
    plane.emplace(grid, tree, grid.activeAxes()[0], grid.activeAxes()[1]);
  }
}

void PlanarSurfaceWalk::entered(const WalkNode& n)
{
  if (plane)
  {
    plane->enter(n);
  }
}

bool PlanarSurfaceWalk::footprintStops(const Vec3& lo, const Vec3& hi) const
{
  // The box's distinct corners only: a flat box has 4 (2D), a segment 2 (1D).
  const auto& axes = grid.activeAxes();
  const double pixels =
      plane ? options.view->footprintInPixels(rectangleCorners(lo, hi, axes[0], axes[1]))
            : options.view->footprintInPixels(segmentEnds(lo, hi, axes[0]));
  return pixels <= options.pixelThreshold;
}

void PlanarSurfaceWalk::draw(const WalkNode& n, const Vec3& lo, const Vec3& hi, vtkIdType global,
                             bool leaf)
{
  const Rgb color = colorOf(n, global, leaf);
  if (plane)
  {
    emitPlaneQuad(n, lo, hi, global, options.colors ? &color : nullptr);
  }
  else
  {
    out.emit(segmentEnds(lo, hi, grid.activeAxes()[0]), global, n.level,
             options.colors ? &color : nullptr);
  }
}

void PlanarSurfaceWalk::emitPlaneQuad(const WalkNode& n, const Vec3& lo, const Vec3& hi,
                                      vtkIdType global, const Rgb* color)
{
  const int u = grid.activeAxes()[0];
  const int v = grid.activeAxes()[1];
  const unsigned remote = rectangleEdgeVertices(
      grid, n, plane->at(n.level), u, v, lo, hi, -1, nullptr,
      [this](const TreeAccess& t, const WalkNode& m) { return roleAt(t, m); }, onEdge, scratch);
  recordShared(remote, u, v, lo, hi);
  polygonAround(rectangleCorners(lo, hi, u, v), u, v, hi,
                {{&onEdge[0], &onEdge[1], &onEdge[2], &onEdge[3]}}, polygon);
  out.emit(polygon.data(), polygon.size(), global, n.level, color);
}

Rgb PlanarSurfaceWalk::colorOf(const WalkNode& n, vtkIdType global, bool leaf) const
{
  if (!options.colors || !out.takesContents())
  {
    return Rgb{{0, 0, 0}};
  }
  if (leaf)
  {
    return options.colors->mapCell(global);
  }
  return averageColor(grid, tree, n, grid.dimension(), *options.colors, EveryChild{});
}

} // namespace canopy
