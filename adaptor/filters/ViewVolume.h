// The region of space a camera sees and how it maps to pixels.
//
// Built from plain camera parameters so the filter works with a vtkCamera, with
// ParaView's render view, or with explicit numbers. The view volume is the
// camera's frustum without near and far planes (VTK resets its clipping range
// to the data, so nothing in front of the camera is clipped in depth).
#pragma once

#include "HalfSpace.h"

#include <array>
#include <string>
#include <vector>

namespace canopy
{

struct CameraParameters
{
  Vec3 position{{0, 0, 1}};
  Vec3 focalPoint{{0, 0, 0}};
  Vec3 viewUp{{0, 1, 0}};
  bool parallelProjection = true;
  double parallelScale = 1.0; ///< half the view height in world units (parallel)
  double viewAngle = 30.0;    ///< full vertical angle in degrees (perspective)
  int viewportWidth = 512;    ///< pixels
  int viewportHeight = 512;   ///< pixels
};

class ViewVolume;
class ColorTable;

/// What the view-dependent builders take from their filter: the view itself
/// (nullptr: no culling and no level of detail), the switches, and a colour map
/// when the cells' colours are wanted too (LeafColorAverage.h: nodes drawn for
/// level of detail then show their leaves' average colour).
struct ViewOptions
{
  const ViewVolume* view = nullptr;
  bool cullOutsideView = true;
  bool levelOfDetail = true;
  double pixelThreshold = 1.0;
  const ColorTable* colors = nullptr;
};

class ViewVolume
{
public:
  /// Returns an empty string when the parameters describe a usable view,
  /// otherwise what is wrong with them.
  static std::string validate(const CameraParameters& camera);

  /// Precondition: validate(camera) is empty.
  explicit ViewVolume(const CameraParameters& camera);

  /// The half-spaces bounding the view, relative to anchor(): 4 for parallel
  /// projection, 5 for perspective (the fifth keeps what is in front of the camera).
  const std::vector<HalfSpace>& halfSpaces() const { return HalfSpaces; }
  /// The point half-spaces are relative to: the focal point (parallel) or the
  /// camera position (perspective).
  const Vec3& anchor() const
  {
    return Camera.parallelProjection ? Camera.focalPoint : Camera.position;
  }

  /// Largest extent, in pixels, of the screen-space bounding box of the given
  /// points; +infinity when a point is at or behind the camera (perspective).
  template <std::size_t N>
  double footprintInPixels(const std::array<Vec3, N>& points) const;

  /// Pixel coordinates (x right, y up, origin at the lower-left corner) of a point
  /// in front of the camera.
  std::array<double, 2> toPixels(const Vec3& p) const;

  /// True when the axis-aligned box [lo, hi] and the view volume share a region
  /// of positive volume. Exact (separating-axis test on the box's and the
  /// frustum's face normals and edge cross products), not a bounding sphere.
  bool overlapsBox(const Vec3& lo, const Vec3& hi) const;

  /// Quick, by the half-spaces alone: Inside when the box lies strictly inside
  /// every half-space (so inside the view, as are all boxes within it), Outside
  /// when it lies entirely beyond one of them, else Crossing (ask overlapsBox).
  enum class BoxSide
  {
    Outside,
    Inside,
    Crossing
  };
  BoxSide classifyBox(const Vec3& lo, const Vec3& hi) const;

  /// Depth along the direction of projection, from the camera (perspective) or
  /// from the focal point (parallel).
  double depth(const Vec3& p) const;

  const Vec3& directionOfProjection() const { return Forward; }
  /// The screen's up direction (unit, orthogonal to the direction of projection).
  const Vec3& screenUp() const { return Up; }
  const Vec3& position() const { return Camera.position; }
  bool parallel() const { return Camera.parallelProjection; }
  /// World size of one pixel at the focal plane (parallel) .
  double pixelSizeAtFocalPlane() const;
  const CameraParameters& camera() const { return Camera; }

private:
  CameraParameters Camera;
  Vec3 Forward;          ///< unit direction of projection
  Vec3 Up;               ///< unit, orthogonal to Forward
  Vec3 Right;            ///< Forward x Up
  double HalfWidth = 0;  ///< parallel: world units; perspective: tangent
  double HalfHeight = 0; ///< same
  std::vector<HalfSpace> HalfSpaces;
  /// Parallel: the four corners of the view rectangle, relative to the focal point.
  /// Perspective: the four corner ray directions from the camera.
  std::array<Vec3, 4> Corners;
  std::vector<Vec3> SeparatingAxes; ///< frustum face normals and edge x box edge
};

template <std::size_t N>
double ViewVolume::footprintInPixels(const std::array<Vec3, N>& points) const
{
  double lo[2] = {1e300, 1e300};
  double hi[2] = {-1e300, -1e300};
  for (const Vec3& p : points)
  {
    if (!Camera.parallelProjection)
    {
      if (dot(sub(p, Camera.position), Forward) <= 0)
      {
        return 1e300;
      }
    }
    const auto px = toPixels(p);
    for (int a = 0; a < 2; ++a)
    {
      lo[a] = px[a] < lo[a] ? px[a] : lo[a];
      hi[a] = px[a] > hi[a] ? px[a] : hi[a];
    }
  }
  const double dx = hi[0] - lo[0];
  const double dy = hi[1] - lo[1];
  return dx > dy ? dx : dy;
}

} // namespace canopy
