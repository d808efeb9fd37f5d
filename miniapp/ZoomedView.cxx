#include "ZoomedView.h"

#include "MovingObjects.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace miniamr
{
namespace
{

std::string point(const char* name, double x, double y, double z)
{
  char text[160];
  std::snprintf(text, sizeof text, "--%s=%.6g,%.6g,%.6g", name, x, y, z);
  return text;
}

} // namespace

namespace
{

/// 2D: the box the first sphere sweeps over the run (objects move step/100 per
/// step, see Simulation::objectClock), seen from in front of it (lower y) at about
/// 25 degrees above the plane: its near side fills the image, its far side and
/// the domain behind recede, so their cells shrink below the pixel threshold.
std::vector<std::string> sphereCamera(const MiniAppOptions& options, const MovingObject& sphere)
{
  const MovingObjects path({sphere}, options.dimension);
  double low[2] = {1.0, 1.0}, high[2] = {0.0, 0.0};
  for (int step = 0; step <= options.steps; ++step)
  {
    const MovingObject at = path.at(0, step / 100.0);
    for (int a = 0; a < 2; ++a)
    {
      low[a] = std::min(low[a], std::max(0.0, at.center[a] - at.radius));
      high[a] = std::max(high[a], std::min(1.0, at.center[a] + at.radius));
    }
  }
  const double cx = (low[0] + high[0]) / 2, cy = (low[1] + high[1]) / 2;
  const double reach = std::hypot(high[0] - low[0], high[1] - low[1]) / 2;
  return {point("camera-position", cx, cy - reach, 0.5 * reach),
          point("camera-focal-point", cx, cy, 0.0), point("camera-view-up", 0.0, 0.0, 1.0)};
}

/// 3D: the adaptive surface is the grid's boundary, which a sphere inside leaves
/// untouched; a plane x = offset cuts it in a refined band. The camera looks
/// along that band on the top face (z = 1) from beyond its front edge, at the
/// middle of the plane's path over the run.
std::vector<std::string> planeCamera(const MiniAppOptions& options, const MovingObject& plane)
{
  const MovingObjects path({plane}, options.dimension);
  const double first = path.at(0, 0.0).offset;
  const double last = path.at(0, options.steps / 100.0).offset;
  // A plane that wrapped around the periodic domain: look at where it started.
  const double x = std::abs(last - first) < 0.5 ? (first + last) / 2 : first;
  return {point("camera-position", x, -0.25, 1.35), point("camera-focal-point", x, 0.35, 1.0),
          point("camera-view-up", 0.0, 0.0, 1.0)};
}

} // namespace

std::vector<std::string> zoomedViewCamera(const MiniAppOptions& options)
{
  for (const auto& object : options.objects)
  {
    if (options.dimension == 2 && object.kind == MovingObject::Kind::Sphere)
    {
      return sphereCamera(options, object);
    }
    if (options.dimension == 3 && object.kind == MovingObject::Kind::Plane &&
        std::abs(object.normal[0]) == 1.0)
    {
      return planeCamera(options, object);
    }
  }
  return {};
}

} // namespace miniamr
