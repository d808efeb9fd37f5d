#include "PixelBoxFilter.h"

#include "ViewVolume.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace canopy
{
namespace
{

/// A quad's screen rectangle, in pixel units (pixel (i, j) is [i, i + 1) x [j, j + 1)).
struct PixelRect
{
  double x0, x1, y0, y1;
};

/// The first and one past the last pixel index whose centre (i + 0.5) lies in
/// [lo, hi): a rasterizer's sampling rule.
std::array<long, 2> centresIn(double lo, double hi)
{
  return {{static_cast<long>(std::ceil(lo - 0.5)), static_cast<long>(std::ceil(hi - 0.5))}};
}

/// The axis a direction runs along, or -1 (within rounding of a unit vector).
int alignedAxis(const Vec3& direction)
{
  for (int a = 0; a < 3; ++a)
  {
    if (std::abs(direction[static_cast<std::size_t>(a)]) > 1 - 1e-9)
    {
      return a;
    }
  }
  return -1;
}

} // namespace

PixelBoxFilterCounts boxFilterOnPixels(const ViewVolume& view, const double* points,
                                       vtkIdType quads, unsigned char* colors)
{
  PixelBoxFilterCounts counts;
  const int normal = alignedAxis(view.directionOfProjection());
  const int up = alignedAxis(view.screenUp());
  if (normal < 0 || up < 0 || quads == 0)
  {
    return counts;
  }
  const long width = view.camera().viewportWidth;
  const long height = view.camera().viewportHeight;
  // Face-on quads lie in a plane normal to the view: corners 0 and 2 share
  // that coordinate (a slice's other planes are seen edge-on: skipped).
  auto faceOn = [&](vtkIdType q)
  {
    const double* c = points + 12 * q;
    return c[normal] == c[6 + normal] && c[normal] == c[3 + normal];
  };
  auto rectOf = [&](vtkIdType q)
  {
    const double* c = points + 12 * q;
    const auto a = view.toPixels({{c[0], c[1], c[2]}});
    const auto b = view.toPixels({{c[6], c[7], c[8]}});
    return PixelRect{std::min(a[0], b[0]), std::max(a[0], b[0]), std::min(a[1], b[1]),
                     std::max(a[1], b[1])};
  };

  // Pass 1: the pixels owned by a quad that holds only their centre.
  std::vector<std::int32_t> owner(static_cast<std::size_t>(width * height), -1);
  std::vector<vtkIdType> owners;
  double plane = 0;
  for (vtkIdType q = 0; q < quads; ++q)
  {
    if (!faceOn(q))
    {
      continue;
    }
    // One layer only: quads in planes at different depths overlap on screen.
    const double at = points[12 * q + normal];
    if (counts.faceOn++ == 0)
    {
      plane = at;
    }
    else if (at != plane)
    {
      return {counts.faceOn, 0};
    }
    const PixelRect r = rectOf(q);
    const auto xs = centresIn(r.x0, r.x1);
    const auto ys = centresIn(r.y0, r.y1);
    if (xs[1] - xs[0] == 1 && ys[1] - ys[0] == 1 && xs[0] >= 0 && xs[0] < width && ys[0] >= 0 &&
        ys[0] < height)
    {
      owner[static_cast<std::size_t>(ys[0] * width + xs[0])] =
          static_cast<std::int32_t>(owners.size());
      owners.push_back(q);
    }
  }
  if (owners.empty())
  {
    return counts;
  }

  // Pass 2: every face-on quad adds its colour, weighted by the area it
  // covers, to the owned pixels it overlaps. A quad holding several centres
  // owns none of its inner pixels (their centres are its own): only its border
  // ring can overlap an owned pixel.
  std::vector<std::array<double, 4>> sums(owners.size(), {{0, 0, 0, 0}});
  for (vtkIdType q = 0; q < quads; ++q)
  {
    if (!faceOn(q))
    {
      continue;
    }
    const PixelRect r = rectOf(q);
    const long i0 = std::max(0L, static_cast<long>(std::floor(r.x0)));
    const long i1 = std::min(width - 1, static_cast<long>(std::ceil(r.x1)) - 1);
    const long j0 = std::max(0L, static_cast<long>(std::floor(r.y0)));
    const long j1 = std::min(height - 1, static_cast<long>(std::ceil(r.y1)) - 1);
    const unsigned char* rgb = colors + 3 * q;
    const auto xs = centresIn(r.x0, r.x1);
    const auto ys = centresIn(r.y0, r.y1);
    const bool several = (xs[1] - xs[0]) * (ys[1] - ys[0]) > 1;
    for (long j = j0; j <= j1; ++j)
    {
      const double h = std::min(r.y1, j + 1.0) - std::max(r.y0, static_cast<double>(j));
      const bool border = !several || j == j0 || j == j1;
      for (long i = i0; i <= i1; i = border || i == i1 ? i + 1 : i1)
      {
        const std::int32_t slot = owner[static_cast<std::size_t>(j * width + i)];
        if (slot < 0)
        {
          continue;
        }
        const double w = std::min(r.x1, i + 1.0) - std::max(r.x0, static_cast<double>(i));
        if (w <= 0 || h <= 0)
        {
          continue;
        }
        std::array<double, 4>& sum = sums[static_cast<std::size_t>(slot)];
        for (int k = 0; k < 3; ++k)
        {
          sum[static_cast<std::size_t>(k)] += w * h * rgb[k];
        }
        sum[3] += w * h;
      }
    }
  }

  // Pass 3: each owner shows its pixel's average.
  for (std::size_t s = 0; s < owners.size(); ++s)
  {
    const std::array<double, 4>& sum = sums[s];
    if (sum[3] <= 0)
    {
      continue;
    }
    unsigned char* rgb = colors + 3 * owners[s];
    for (int k = 0; k < 3; ++k)
    {
      rgb[k] = static_cast<unsigned char>(
          std::lround(std::clamp(sum[static_cast<std::size_t>(k)] / sum[3], 0.0, 255.0)));
    }
    ++counts.recoloured;
  }
  return counts;
}

} // namespace canopy
