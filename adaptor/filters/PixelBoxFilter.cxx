#include "PixelBoxFilter.h"

#include "LeafColorAverage.h"
#include "ViewVolume.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

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

int PixelBoxFilter::faceOnAxis(const ViewVolume& view)
{
  const int normal = alignedAxis(view.directionOfProjection());
  return normal >= 0 && alignedAxis(view.screenUp()) >= 0 ? normal : -1;
}

PixelBoxFilter::PixelBoxFilter(const ViewVolume& view, const double* points,
                               const vtkIdType* offsets, vtkIdType quads,
                               const unsigned char* colors)
    : Width(view.camera().viewportWidth), Height(view.camera().viewportHeight),
      Owner(static_cast<std::size_t>(Width * Height), None)
{
  const int normal = faceOnAxis(view);
  // Each quad's box: its points lie on the rectangle's edges.
  auto boxOf = [&](vtkIdType q)
  {
    std::array<Vec3, 2> box{{{{1e300, 1e300, 1e300}}, {{-1e300, -1e300, -1e300}}}};
    for (vtkIdType k = offsets[q]; k < offsets[q + 1]; ++k)
    {
      for (int a = 0; a < 3; ++a)
      {
        box[0][a] = std::min(box[0][a], points[3 * k + a]);
        box[1][a] = std::max(box[1][a], points[3 * k + a]);
      }
    }
    return box;
  };
  // Face-on quads lie in a plane normal to the view: their points share that
  // coordinate (a slice's other planes are seen edge-on: skipped).
  auto faceOn = [&](vtkIdType q)
  {
    const auto box = boxOf(q);
    return normal >= 0 && box[0][normal] == box[1][normal];
  };
  auto rectOf = [&](vtkIdType q)
  {
    const auto box = boxOf(q);
    const auto a = view.toPixels(box[0]);
    const auto b = view.toPixels(box[1]);
    return PixelRect{std::min(a[0], b[0]), std::max(a[0], b[0]), std::min(a[1], b[1]),
                     std::max(a[1], b[1])};
  };
  auto pixel = [&](long i, long j) -> std::int32_t&
  { return Owner[static_cast<std::size_t>(j * Width + i)]; };

  // Pass 1: which quad holds each pixel centre, and alone.
  for (vtkIdType q = 0; q < quads; ++q)
  {
    if (!faceOn(q))
    {
      continue;
    }
    ++FaceOn;
    const PixelRect r = rectOf(q);
    const auto xs = centresIn(r.x0, r.x1);
    const auto ys = centresIn(r.y0, r.y1);
    const long i0 = std::max(0L, xs[0]), i1 = std::min(Width, xs[1]);
    const long j0 = std::max(0L, ys[0]), j1 = std::min(Height, ys[1]);
    if (xs[1] - xs[0] == 1 && ys[1] - ys[0] == 1)
    {
      if (i0 < i1 && j0 < j1)
      {
        pixel(i0, j0) = static_cast<std::int32_t>(Owners.size());
        Owners.push_back(q);
      }
      continue;
    }
    for (long j = j0; j < j1; ++j)
      for (long i = i0; i < i1; ++i)
        pixel(i, j) = Several;
  }
  Sums.assign(Owners.size(), {{0, 0, 0, 0}});

  // Pass 2: every face-on quad adds its colour, weighted by the area it covers,
  // to the pixels it overlaps that a single quad owns (here, or, through
  // shares, on another rank). A quad holding several centres holds all of its
  // inner pixels' centres itself: only its border ring can matter.
  std::unordered_map<long, std::array<double, 4>> elsewhere;
  for (vtkIdType q = 0; q < quads; ++q)
  {
    if (!faceOn(q))
    {
      continue;
    }
    const PixelRect r = rectOf(q);
    const long i0 = std::max(0L, static_cast<long>(std::floor(r.x0)));
    const long i1 = std::min(Width - 1, static_cast<long>(std::ceil(r.x1)) - 1);
    const long j0 = std::max(0L, static_cast<long>(std::floor(r.y0)));
    const long j1 = std::min(Height - 1, static_cast<long>(std::ceil(r.y1)) - 1);
    const unsigned char* rgb = colors + 3 * q;
    const auto xs = centresIn(r.x0, r.x1);
    const auto ys = centresIn(r.y0, r.y1);
    const bool several = (xs[1] - xs[0]) * (ys[1] - ys[0]) > 1;
    for (long j = j0; j <= j1; ++j)
    {
      const double h = std::min(r.y1, j + 1.0) - std::max(r.y0, static_cast<double>(j));
      const bool ring = !several || j == j0 || j == j1;
      for (long i = i0; i <= i1; i = ring || i == i1 ? i + 1 : i1)
      {
        const std::int32_t slot = pixel(i, j);
        const double w = std::min(r.x1, i + 1.0) - std::max(r.x0, static_cast<double>(i));
        if (slot == Several || w <= 0 || h <= 0)
        {
          continue;
        }
        std::array<double, 4>& sum =
            slot >= 0 ? Sums[static_cast<std::size_t>(slot)] : elsewhere[j * Width + i];
        for (int k = 0; k < 3; ++k)
        {
          sum[static_cast<std::size_t>(k)] += w * h * rgb[k];
        }
        sum[3] += w * h;
      }
    }
  }
  Shares.reserve(5 * elsewhere.size());
  for (const auto& [at, sum] : elsewhere)
  {
    Shares.insert(Shares.end(), {static_cast<double>(at), sum[0], sum[1], sum[2], sum[3]});
  }
}

void PixelBoxFilter::addShares(const std::vector<double>& shares)
{
  for (std::size_t s = 0; s + 4 < shares.size(); s += 5)
  {
    const auto at = static_cast<long>(shares[s]);
    if (at < 0 || at >= Width * Height)
    {
      continue;
    }
    const std::int32_t slot = Owner[static_cast<std::size_t>(at)];
    if (slot < 0)
    {
      continue; // not owned here (this rank's own shares among them)
    }
    std::array<double, 4>& sum = Sums[static_cast<std::size_t>(slot)];
    for (std::size_t k = 0; k < 4; ++k)
    {
      sum[k] += shares[s + 1 + k];
    }
  }
}

PixelBoxFilterCounts PixelBoxFilter::finish(unsigned char* colors) const
{
  PixelBoxFilterCounts counts;
  counts.faceOn = FaceOn;
  for (std::size_t s = 0; s < Owners.size(); ++s)
  {
    const std::array<double, 4>& sum = Sums[s];
    if (sum[3] <= 0)
    {
      continue;
    }
    unsigned char* rgb = colors + 3 * Owners[s];
    for (std::size_t k = 0; k < 3; ++k)
    {
      rgb[k] = colorByte(sum[k] / sum[3]);
    }
    ++counts.recoloured;
  }
  return counts;
}

} // namespace canopy
