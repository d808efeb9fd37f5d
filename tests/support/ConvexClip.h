// Brute-force measures of a cell's part inside a convex region given by planes
// (a, b, c, d: inside where a x + b y + c z + d >= 0), by clipping: the length of
// a segment, the area of a rectangle, the volume of a box. The references the
// selection tests compare against; independent of the filters' separating-axis
// tests.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace canopy::testing
{

using ClipPoint = std::array<double, 3>;
using ClipPlane = std::array<double, 4>;

inline double planeValue(const ClipPlane& h, const ClipPoint& p)
{
  return h[0] * p[0] + h[1] * p[1] + h[2] * p[2] + h[3];
}

inline ClipPoint lerp(const ClipPoint& p, const ClipPoint& q, double t)
{
  return {{p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]), p[2] + t * (q[2] - p[2])}};
}

/// Sutherland-Hodgman: the part of a convex polygon (in 3D) inside the plane.
inline std::vector<ClipPoint> clipPolygon(const std::vector<ClipPoint>& polygon, const ClipPlane& h)
{
  std::vector<ClipPoint> out;
  for (std::size_t i = 0; i < polygon.size(); ++i)
  {
    const ClipPoint& p = polygon[i];
    const ClipPoint& q = polygon[(i + 1) % polygon.size()];
    const double fp = planeValue(h, p);
    const double fq = planeValue(h, q);
    if (fp >= 0)
    {
      out.push_back(p);
    }
    if ((fp > 0 && fq < 0) || (fp < 0 && fq > 0))
    {
      out.push_back(lerp(p, q, fp / (fp - fq)));
    }
  }
  return out;
}

/// Newell's normal (length: twice the area) of a planar polygon.
inline ClipPoint polygonNormal(const std::vector<ClipPoint>& polygon)
{
  ClipPoint n{{0, 0, 0}};
  const ClipPoint& o = polygon.empty() ? n : polygon[0];
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i)
  {
    const ClipPoint a{{polygon[i][0] - o[0], polygon[i][1] - o[1], polygon[i][2] - o[2]}};
    const ClipPoint b{
        {polygon[i + 1][0] - o[0], polygon[i + 1][1] - o[1], polygon[i + 1][2] - o[2]}};
    n[0] += a[1] * b[2] - a[2] * b[1];
    n[1] += a[2] * b[0] - a[0] * b[2];
    n[2] += a[0] * b[1] - a[1] * b[0];
  }
  return n;
}

inline double polygonArea(const std::vector<ClipPoint>& polygon)
{
  const ClipPoint n = polygonNormal(polygon);
  return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/// Area of the part of a convex polygon inside every plane.
inline double clippedArea(std::vector<ClipPoint> polygon, const std::vector<ClipPlane>& planes)
{
  for (const ClipPlane& h : planes)
  {
    polygon = clipPolygon(polygon, h);
    if (polygon.size() < 3)
    {
      return 0;
    }
  }
  return polygonArea(polygon);
}

/// Length of the part of segment pq inside every plane.
inline double clippedLength(const ClipPoint& p, const ClipPoint& q,
                            const std::vector<ClipPlane>& planes)
{
  double t0 = 0;
  double t1 = 1;
  for (const ClipPlane& h : planes)
  {
    const double fp = planeValue(h, p);
    const double fq = planeValue(h, q);
    if (fp < 0 && fq < 0)
    {
      return 0;
    }
    if (fp < 0)
    {
      t0 = std::max(t0, fp / (fp - fq));
    }
    else if (fq < 0)
    {
      t1 = std::min(t1, fp / (fp - fq));
    }
  }
  const double length = std::sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                                  (q[2] - p[2]) * (q[2] - p[2]));
  return t1 > t0 ? (t1 - t0) * length : 0;
}

/// Volume of the part of the box [b0, b1] x [b2, b3] x [b4, b5] inside every
/// plane: the box's faces are clipped one plane at a time, each cut closed by a
/// cap (the cut points sorted by angle), and the volume summed as pyramids from
/// an interior point.
inline double clippedVolume(const double b[6], const std::vector<ClipPlane>& planes)
{
  std::vector<std::vector<ClipPoint>> faces;
  for (int axis = 0; axis < 3; ++axis)
  {
    const int u = (axis + 1) % 3;
    const int v = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side)
    {
      std::vector<ClipPoint> face(4);
      const int corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      for (int c = 0; c < 4; ++c)
      {
        face[c][axis] = b[2 * axis + side];
        face[c][u] = b[2 * u + corners[c][0]];
        face[c][v] = b[2 * v + corners[c][1]];
      }
      faces.push_back(face);
    }
  }
  double scale = 0;
  for (int i = 0; i < 6; ++i)
  {
    scale = std::max(scale, std::abs(b[i]));
  }
  for (const ClipPlane& h : planes)
  {
    const double length = std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    const double tolerance = 1e-12 * (length * scale + std::abs(h[3]));
    bool cuts = false;
    bool keeps = false;
    for (const auto& face : faces)
    {
      for (const ClipPoint& p : face)
      {
        cuts = cuts || planeValue(h, p) < -tolerance;
        keeps = keeps || planeValue(h, p) > tolerance;
      }
    }
    if (!keeps)
    {
      return 0; // nothing strictly inside this plane
    }
    if (!cuts)
    {
      continue; // nothing strictly outside: the plane removes nothing
    }
    std::vector<std::vector<ClipPoint>> clipped;
    std::vector<ClipPoint> cut;
    for (const auto& face : faces)
    {
      auto part = clipPolygon(face, h);
      for (const ClipPoint& p : part)
      {
        if (std::abs(planeValue(h, p)) <= tolerance)
        {
          cut.push_back(p);
        }
      }
      if (part.size() >= 3)
      {
        clipped.push_back(part);
      }
    }
    if (cut.size() >= 3)
    {
      ClipPoint centre{{0, 0, 0}};
      for (const ClipPoint& p : cut)
      {
        for (int a = 0; a < 3; ++a)
        {
          centre[a] += p[a] / static_cast<double>(cut.size());
        }
      }
      // An orthonormal frame of the plane, then sort by angle around the centre.
      const ClipPoint n{{h[0] / length, h[1] / length, h[2] / length}};
      const ClipPoint helper = std::abs(n[0]) < 0.9 ? ClipPoint{{1, 0, 0}} : ClipPoint{{0, 1, 0}};
      ClipPoint e1{{n[1] * helper[2] - n[2] * helper[1], n[2] * helper[0] - n[0] * helper[2],
                    n[0] * helper[1] - n[1] * helper[0]}};
      const double l1 = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
      for (double& x : e1)
      {
        x /= l1;
      }
      const ClipPoint e2{
          {n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0]}};
      auto angle = [&](const ClipPoint& p)
      {
        const ClipPoint d{{p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]}};
        return std::atan2(d[0] * e2[0] + d[1] * e2[1] + d[2] * e2[2],
                          d[0] * e1[0] + d[1] * e1[1] + d[2] * e1[2]);
      };
      std::sort(cut.begin(), cut.end(),
                [&](const ClipPoint& p, const ClipPoint& q) { return angle(p) < angle(q); });
      clipped.push_back(cut);
    }
    faces = clipped;
    if (faces.size() < 4)
    {
      return 0;
    }
  }
  ClipPoint inner{{0, 0, 0}};
  std::size_t count = 0;
  for (const auto& face : faces)
  {
    for (const ClipPoint& p : face)
    {
      for (int a = 0; a < 3; ++a)
      {
        inner[a] += p[a];
      }
      ++count;
    }
  }
  for (double& x : inner)
  {
    x /= static_cast<double>(count);
  }
  double volume = 0;
  for (const auto& face : faces)
  {
    const ClipPoint n = polygonNormal(face);
    const double twiceArea = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(twiceArea > 0))
    {
      continue;
    }
    const double height = std::abs(n[0] * (inner[0] - face[0][0]) + n[1] * (inner[1] - face[0][1]) +
                                   n[2] * (inner[2] - face[0][2])) /
                          twiceArea;
    volume += 0.5 * twiceArea * height / 3;
  }
  return volume;
}

} // namespace canopy::testing
