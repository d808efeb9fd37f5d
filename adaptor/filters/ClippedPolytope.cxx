#include "ClippedPolytope.h"

#include "Vec3.h"

#include <algorithm>
#include <cmath>

namespace canopy
{
namespace
{

double largest(const Vec3& a)
{
  return std::max({std::abs(a[0]), std::abs(a[1]), std::abs(a[2])});
}

/// Adds a unit axis unless it is (nearly) zero or parallel to one already there.
void addAxis(std::vector<Vec3>& axes, const Vec3& a)
{
  const double length = std::sqrt(dot(a, a));
  if (!(length > 1e-9))
  {
    return;
  }
  const Vec3 unit{{a[0] / length, a[1] / length, a[2] / length}};
  for (const Vec3& b : axes)
  {
    if (std::abs(dot(unit, b)) > 1 - 1e-14)
    {
      return;
    }
  }
  axes.push_back(unit);
}

} // namespace

ClippedPolytope::ClippedPolytope(const std::vector<HalfSpace>& halfSpaces, const Vec3& anchor,
                                 const Vec3& boxLo, const Vec3& boxHi)
    : Anchor(anchor)
{
  std::vector<HalfSpace> all = halfSpaces;
  for (int a = 0; a < 3; ++a)
  {
    Vec3 n{{0, 0, 0}};
    n[a] = 1;
    all.push_back({n, boxHi[a] - anchor[a]});
    n[a] = -1;
    all.push_back({n, anchor[a] - boxLo[a]});
  }
  // Vertices: every point where three planes with independent normals meet and
  // that lies in every half-space (within rounding, relative to its size).
  const std::size_t m = all.size();
  for (std::size_t i = 0; i < m; ++i)
  {
    for (std::size_t j = i + 1; j < m; ++j)
    {
      const Vec3 ij = cross(all[i].normal, all[j].normal);
      for (std::size_t k = j + 1; k < m; ++k)
      {
        const double det = dot(all[k].normal, ij);
        if (!(std::abs(det) > 1e-9))
        {
          continue;
        }
        const Vec3 jk = cross(all[j].normal, all[k].normal);
        const Vec3 ki = cross(all[k].normal, all[i].normal);
        Vec3 x;
        for (int a = 0; a < 3; ++a)
        {
          x[a] = (all[i].offset * jk[a] + all[j].offset * ki[a] + all[k].offset * ij[a]) / det;
        }
        bool inside = true;
        for (std::size_t h = 0; h < m && inside; ++h)
        {
          const double slack = 1e-13 * (largest(x) + std::abs(all[h].offset)) / std::abs(det);
          inside = dot(all[h].normal, x) <= all[h].offset + slack;
        }
        if (inside)
        {
          Vertices.push_back(x);
        }
      }
    }
  }
  // A region without volume (empty, flat): its vertices' centroid is not strictly
  // inside every half-space.
  if (Vertices.size() < 4)
  {
    return;
  }
  Vec3 centroid{{0, 0, 0}};
  for (const Vec3& v : Vertices)
  {
    for (int a = 0; a < 3; ++a)
    {
      centroid[a] += v[a] / static_cast<double>(Vertices.size());
    }
  }
  double size = 0;
  for (const Vec3& v : Vertices)
  {
    size = std::max(size, largest({{v[0] - centroid[0], v[1] - centroid[1], v[2] - centroid[2]}}));
  }
  for (const HalfSpace& h : all)
  {
    if (!(dot(h.normal, centroid) < h.offset - 1e-12 * size))
    {
      return;
    }
  }
  Empty = false;
  // Candidate axes: coordinate axes first (they reject most cells), the face
  // normals, then each coordinate axis crossed with each possible edge direction.
  const Vec3 coordinate[3] = {{{1, 0, 0}}, {{0, 1, 0}}, {{0, 0, 1}}};
  for (const Vec3& e : coordinate)
  {
    addAxis(Axes, e);
  }
  for (const HalfSpace& h : halfSpaces)
  {
    addAxis(Axes, h.normal);
  }
  for (std::size_t i = 0; i < m; ++i)
  {
    for (std::size_t j = i + 1; j < m; ++j)
    {
      const Vec3 edge = cross(all[i].normal, all[j].normal);
      for (const Vec3& e : coordinate)
      {
        addAxis(Axes, cross(e, edge));
      }
    }
  }
  for (const Vec3& a : Axes)
  {
    double lo = 1e300;
    double hi = -1e300;
    for (const Vec3& v : Vertices)
    {
      lo = std::min(lo, dot(a, v));
      hi = std::max(hi, dot(a, v));
    }
    Extents.push_back({{lo, hi}});
  }
}

bool ClippedPolytope::overlaps(const Vec3& lo, const Vec3& hi) const
{
  if (Empty)
  {
    return false;
  }
  for (std::size_t i = 0; i < Axes.size(); ++i)
  {
    const Vec3& a = Axes[i];
    // The box's extent along the axis, relative to the anchor.
    double boxMin = 0;
    double boxMax = 0;
    for (int k = 0; k < 3; ++k)
    {
      boxMin += a[k] * ((a[k] >= 0 ? lo[k] : hi[k]) - Anchor[k]);
      boxMax += a[k] * ((a[k] >= 0 ? hi[k] : lo[k]) - Anchor[k]);
    }
    if (boxMax <= Extents[i][0] || Extents[i][1] <= boxMin)
    {
      return false;
    }
  }
  return true;
}

} // namespace canopy
