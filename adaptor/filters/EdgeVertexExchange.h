// The corners that another rank's pieces put on the edges of this rank's pieces
// (T-junctions across ranks, EdgeVertices.h).
//
// A rank does not know the grid below another rank's part (an absent node, a
// root cell whose tree is elsewhere), so where a drawn piece's edge runs along
// another rank's part, the finer pieces meeting it there are that rank's. Every
// rank lists the edges of its pieces along which it met another rank's part
// (the line, the edge's two ends), every rank receives all of them (owners are
// unknown: an AllGatherV, as the 3D surface's remote faces), and each inserts,
// into every segment of its own such pieces' polygons, the ends of the other
// ranks' edges that lie on that line strictly inside it.
//
// The ends are enough: a piece of another rank that meets this rank's edge on
// its line met this rank's part across that edge too (it is on the other
// side), so it sent its edge, whose ends are its corners on the line. What
// travels is proportional to the pieces along the ranks' borders, not to the
// grid; extra vertices (an end that meets nothing here) only split an edge
// where it stays straight.
#pragma once

#include "Vec3.h"

#include <array>
#include <cstdint>
#include <map>
#include <tuple>
#include <vector>

class vtkMultiProcessController;

namespace canopy
{

struct TreeCells;

/// A piece's edge along another rank's part: the line (along axis `along`,
/// at `at` on the two other axes, in increasing axis order) and its ends.
struct SharedEdge
{
  int along;
  std::array<double, 2> at;
  double lo;
  double hi;
  /// Values per edge on the wire (SharedEdge <-> double).
  static constexpr std::size_t Values = 5;
};

/// The edge of a rectangle in the plane of axes u and v, spanning lo to hi, in
/// polygonAround's numbering (0, 1: along u at v = lo, hi; 2, 3: along v at u =
/// lo, hi).
SharedEdge sharedEdgeOf(int edge, int u, int v, const Vec3& lo, const Vec3& hi);

/// Every rank's shared edges, indexed by line: where other ranks' pieces have
/// corners.
class SharedVertices
{
public:
  explicit SharedVertices(const std::vector<SharedEdge>& edges);
  /// Appends to `out`, ascending, the ends on the line along `along` through
  /// `p` that lie strictly between a and b.
  void between(int along, const Vec3& p, double a, double b, std::vector<double>& out) const;
  bool empty() const { return Lines.empty(); }

private:
  std::map<std::tuple<int, double, double>, std::vector<double>> Lines;
};

/// Collective over `controller`: every rank's shared edges (this rank's too).
std::vector<SharedEdge> gatherSharedEdges(vtkMultiProcessController* controller,
                                          const std::vector<SharedEdge>& mine);

/// Rewrites the cells `listed` (indices into `cells`, ascending) with the
/// shared vertices inserted, in order, into every segment of their polygons.
void insertSharedVertices(TreeCells& cells, const std::vector<std::uint32_t>& listed,
                          const SharedVertices& shared);

/// Collective: a builder's shared edges (sharedEdges()) to every rank, and the
/// vertices every rank's edges put on its own (addSharedVertices()).
template <typename Builder>
void exchangeSharedVertices(Builder& builder, vtkMultiProcessController* controller)
{
  builder.addSharedVertices(SharedVertices(gatherSharedEdges(controller, builder.sharedEdges())));
}

} // namespace canopy
