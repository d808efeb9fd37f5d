// Holes in a rendered picture: background pixels where the picture must be
// covered. The region is the convex hull of world points as the renderer's
// camera projects them (a slice's rectangle, a box's eight corners), shrunk by
// a margin in pixels, so that only pixels wholly inside count: no rasterization
// rule at the border can excuse them.
#pragma once

#include "OffscreenRenderer.h"

#include <vtkRenderer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace canopy::testing
{

using Pixel = std::array<int, 2>;

/// Display coordinates (pixels, origin at the lower-left corner of the window:
/// pixel (i, j) covers [i, i + 1) x [j, j + 1)) of world points, by the
/// renderer's active camera and window size.
inline std::vector<std::array<double, 2>>
projectToDisplay(vtkRenderer* renderer, const std::vector<std::array<double, 3>>& world)
{
  std::vector<std::array<double, 2>> display;
  for (const auto& p : world)
  {
    renderer->SetWorldPoint(p[0], p[1], p[2], 1.0);
    renderer->WorldToDisplay();
    const double* d = renderer->GetDisplayPoint();
    display.push_back({{d[0], d[1]}});
  }
  return display;
}

/// Counter-clockwise convex hull (Andrew's monotone chain).
inline std::vector<std::array<double, 2>> convexHull(std::vector<std::array<double, 2>> points)
{
  std::sort(points.begin(), points.end());
  auto turn = [](const std::array<double, 2>& o, const std::array<double, 2>& a,
                 const std::array<double, 2>& b)
  { return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]); };
  std::vector<std::array<double, 2>> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], points[i]) <= 0)
      --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;)
  {
    while (k >= lower && turn(hull[k - 2], hull[k - 1], points[i]) <= 0)
      --k;
    hull[k++] = points[i];
  }
  hull.resize(k > 0 ? k - 1 : 0);
  return hull;
}

/// Pixels whose centre lies inside the hull of `world`'s projection, at least
/// `margin` pixels from its border, and which show exactly `background`. Also
/// counts the pixels tested (`inside`), so a caller can check that the region
/// is not empty.
inline std::vector<Pixel> holesInside(const Image& image, vtkRenderer* renderer,
                                      const std::vector<std::array<double, 3>>& world,
                                      double margin, const std::array<unsigned char, 3>& background,
                                      std::size_t* inside = nullptr)
{
  const auto hull = convexHull(projectToDisplay(renderer, world));
  std::vector<Pixel> holes;
  std::size_t tested = 0;
  for (int j = 0; j < image.height; ++j)
  {
    for (int i = 0; i < image.width; ++i)
    {
      const double c[2] = {i + 0.5, j + 0.5};
      bool in = hull.size() >= 3;
      for (std::size_t e = 0; in && e < hull.size(); ++e)
      {
        const auto& p = hull[e];
        const auto& q = hull[(e + 1) % hull.size()];
        const double dx = q[0] - p[0];
        const double dy = q[1] - p[1];
        // Distance to the edge's line, positive inside (the hull is counter-clockwise).
        in = (dx * (c[1] - p[1]) - dy * (c[0] - p[0])) / std::hypot(dx, dy) >= margin;
      }
      if (!in)
      {
        continue;
      }
      ++tested;
      const unsigned char* rgb =
          image.rgb.data() + 3 * (static_cast<std::size_t>(j) * image.width + i);
      if (rgb[0] == background[0] && rgb[1] == background[1] && rgb[2] == background[2])
      {
        holes.push_back({{i, j}});
      }
    }
  }
  if (inside)
  {
    *inside = tested;
  }
  return holes;
}

} // namespace canopy::testing
