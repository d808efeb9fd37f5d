#include "Frustum.h"

#include "Vec3.h"

#include <cmath>
#include <sstream>

namespace canopy
{

std::string Frustum::fromCorners(const std::array<Vec3, 8>& corners, Frustum& frustum)
{
  Vec3 centroid{{0, 0, 0}};
  for (std::size_t i = 0; i < corners.size(); ++i)
  {
    for (int a = 0; a < 3; ++a)
    {
      if (!std::isfinite(corners[i][a]))
      {
        return "frustum corner " + std::to_string(i) + " is not finite";
      }
      centroid[a] += corners[i][a] / 8;
    }
  }
  // Left, right, bottom, top, near, far: the corners vtkFrustumSelector takes.
  static const int faces[6][3] = {{0, 2, 3}, {7, 6, 4}, {5, 4, 0}, {2, 6, 7}, {6, 2, 0}, {1, 3, 7}};
  static const char* const names[6] = {"left", "right", "bottom", "top", "near", "far"};
  for (int f = 0; f < 6; ++f)
  {
    const Vec3& p = corners[static_cast<std::size_t>(faces[f][0])];
    const Vec3& q = corners[static_cast<std::size_t>(faces[f][1])];
    const Vec3& r = corners[static_cast<std::size_t>(faces[f][2])];
    Vec3 n = cross(sub(q, p), sub(r, p));
    const double length = std::sqrt(dot(n, n));
    if (!(length > 0) || !std::isfinite(length))
    {
      return std::string("the frustum's ") + names[f] + " face has no area";
    }
    // Inward: the centroid of the corners is inside.
    if (dot(n, sub(centroid, p)) < 0)
    {
      n = {{-n[0], -n[1], -n[2]}};
    }
    for (int a = 0; a < 3; ++a)
    {
      n[a] /= length;
    }
    frustum.planes[static_cast<std::size_t>(f)] = {{n[0], n[1], n[2], -dot(n, p)}};
  }
  return {};
}

std::string Frustum::problem() const
{
  for (std::size_t i = 0; i < planes.size(); ++i)
  {
    const auto& p = planes[i];
    std::ostringstream out;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]) ||
        !std::isfinite(p[3]))
    {
      out << "frustum plane " << i << " is not finite";
      return out.str();
    }
    const double length = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    if (!(length > 0) || !std::isfinite(length))
    {
      out << "frustum plane " << i << " has a zero (or overflowing) normal";
      return out.str();
    }
  }
  return {};
}

std::vector<HalfSpace> Frustum::halfSpaces(const Vec3& anchor) const
{
  std::vector<HalfSpace> result;
  for (const auto& p : planes)
  {
    // a . x + d >= 0  <=>  -a . (x - o) <= d + a . o, then scaled to a unit normal.
    const Vec3 a{{p[0], p[1], p[2]}};
    const double length = std::sqrt(dot(a, a));
    result.push_back(
        {{{-a[0] / length, -a[1] / length, -a[2] / length}}, (p[3] + dot(a, anchor)) / length});
  }
  return result;
}

} // namespace canopy
