#include "GridSection.h"

#include <algorithm>
#include <cmath>

namespace canopy
{

GridSection::GridSection(const HyperTreeAccess& grid, const std::vector<HalfSpace>& halfSpaces,
                         const Vec3& anchor)
    : Dimension(grid.dimension())
{
  U = grid.activeAxes()[0];
  AnchorU = anchor[U];
  if (Dimension == 1)
  {
    cutLine(grid, halfSpaces, anchor);
  }
  else
  {
    V = grid.activeAxes()[1];
    AnchorV = anchor[V];
    cutPlane(grid, halfSpaces, anchor);
  }
}

void GridSection::cutLine(const HyperTreeAccess& grid, const std::vector<HalfSpace>& halfSpaces,
                          const Vec3& anchor)
{
  const auto& b = grid.bounds();
  Low = b[2 * U] - AnchorU;
  High = b[2 * U + 1] - AnchorU;
  for (const HalfSpace& h : halfSpaces)
  {
    // n . (p - o) <= c on the line p = (t along U, fixed elsewhere).
    double c = h.offset;
    for (int a = 0; a < 3; ++a)
    {
      if (a != U)
      {
        c -= h.normal[a] * (b[2 * a] - anchor[a]);
      }
    }
    const double n = h.normal[U];
    if (n > 0)
    {
      High = std::min(High, c / n);
    }
    else if (n < 0)
    {
      Low = std::max(Low, c / n);
    }
    else if (c < 0)
    {
      High = Low; // the line lies outside this half-space
    }
  }
  Empty = !(Low < High);
}

void GridSection::cutPlane(const HyperTreeAccess& grid, const std::vector<HalfSpace>& halfSpaces,
                           const Vec3& anchor)
{
  const auto& b = grid.bounds();
  // The flat axis is the one neither U nor V.
  const int w = 3 - U - V;
  std::vector<std::array<double, 2>> polygon{{{b[2 * U] - AnchorU, b[2 * V] - AnchorV}},
                                             {{b[2 * U + 1] - AnchorU, b[2 * V] - AnchorV}},
                                             {{b[2 * U + 1] - AnchorU, b[2 * V + 1] - AnchorV}},
                                             {{b[2 * U] - AnchorU, b[2 * V + 1] - AnchorV}}};
  for (const HalfSpace& h : halfSpaces)
  {
    // n . (p - o) <= c with p = (u, v, flat): nu u' + nv v' <= c - nw * (flat - o_w)
    const double c = h.offset - h.normal[w] * (b[2 * w] - anchor[w]);
    polygon = clip(polygon, h.normal[U], h.normal[V], c);
    if (polygon.empty())
    {
      break;
    }
  }
  Polygon = polygon;
  double area = 0;
  for (std::size_t i = 1; i + 1 < Polygon.size(); ++i)
  {
    // Fan from vertex 0: no cancellation between large terms.
    const auto& p0 = Polygon[0];
    const auto& p = Polygon[i];
    const auto& q = Polygon[i + 1];
    area += (p[0] - p0[0]) * (q[1] - p0[1]) - (q[0] - p0[0]) * (p[1] - p0[1]);
  }
  Empty = Polygon.size() < 3 || !(std::abs(area) > 0);
  // Separating axes: u, v and the polygon's edge normals.
  Axes.push_back({{1, 0}});
  Axes.push_back({{0, 1}});
  for (std::size_t i = 0; i < Polygon.size() && !Empty; ++i)
  {
    const auto& p = Polygon[i];
    const auto& q = Polygon[(i + 1) % Polygon.size()];
    const double du = q[0] - p[0];
    const double dv = q[1] - p[1];
    if (du != 0 || dv != 0)
    {
      Axes.push_back({{-dv, du}});
    }
  }
  for (const auto& a : Axes)
  {
    double lo = 1e300;
    double hi = -1e300;
    for (const auto& p : Polygon)
    {
      const double x = a[0] * p[0] + a[1] * p[1];
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    Intervals.push_back({{lo, hi}});
  }
}

bool GridSection::overlaps(const Vec3& lo, const Vec3& hi) const
{
  if (Empty)
  {
    return false;
  }
  const double u0 = lo[U] - AnchorU;
  const double u1 = hi[U] - AnchorU;
  if (Dimension == 1)
  {
    return std::max(u0, Low) < std::min(u1, High);
  }
  const double v0 = lo[V] - AnchorV;
  const double v1 = hi[V] - AnchorV;
  for (std::size_t i = 0; i < Axes.size(); ++i)
  {
    const auto& a = Axes[i];
    const double rmin = a[0] * (a[0] >= 0 ? u0 : u1) + a[1] * (a[1] >= 0 ? v0 : v1);
    const double rmax = a[0] * (a[0] >= 0 ? u1 : u0) + a[1] * (a[1] >= 0 ? v1 : v0);
    if (std::max(rmin, Intervals[i][0]) >= std::min(rmax, Intervals[i][1]))
    {
      return false;
    }
  }
  return true;
}

std::vector<std::array<double, 2>> GridSection::clip(const std::vector<std::array<double, 2>>& in,
                                                     double nu, double nv, double c)
{
  std::vector<std::array<double, 2>> out;
  if (nu == 0 && nv == 0)
  {
    return c >= 0 ? in : out;
  }
  for (std::size_t i = 0; i < in.size(); ++i)
  {
    const auto& p = in[i];
    const auto& q = in[(i + 1) % in.size()];
    const double fp = nu * p[0] + nv * p[1] - c;
    const double fq = nu * q[0] + nv * q[1] - c;
    if (fp <= 0)
    {
      out.push_back(p);
    }
    if ((fp < 0 && fq > 0) || (fp > 0 && fq < 0))
    {
      const double t = fp / (fp - fq);
      out.push_back({{p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])}});
    }
  }
  return out;
}

} // namespace canopy
