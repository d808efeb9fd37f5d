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

std::vector<std::string> zoomedViewCamera(const MiniAppOptions& options)
{
  const auto sphere =
      std::find_if(options.objects.begin(), options.objects.end(),
                   [](const MovingObject& o) { return o.kind == MovingObject::Kind::Sphere; });
  if (sphere == options.objects.end())
  {
    return {};
  }
  // The box the sphere sweeps over the run (objects move step/100 per step, see
  // Simulation::objectClock), its surface included.
  const MovingObjects path({*sphere}, options.dimension);
  std::array<double, 3> low{}, high{};
  low.fill(std::numeric_limits<double>::max());
  high.fill(std::numeric_limits<double>::lowest());
  for (int step = 0; step <= options.steps; ++step)
  {
    const MovingObject at = path.at(0, step / 100.0);
    for (int a = 0; a < options.dimension; ++a)
    {
      low[a] = std::min(low[a], std::max(0.0, at.center[a] - at.radius));
      high[a] = std::max(high[a], std::min(1.0, at.center[a] + at.radius));
    }
  }
  for (int a = options.dimension; a < 3; ++a)
  {
    low[a] = high[a] = 0.0;
  }
  const double cx = (low[0] + high[0]) / 2, cy = (low[1] + high[1]) / 2;
  const double reach = std::hypot(high[0] - low[0], high[1] - low[1], high[2] - low[2]) / 2;
  // Looking down at the region from in front of it (lower y) at about 35 degrees
  // above the plane: its near side fills the image; the far side of the domain
  // recedes, so its cells shrink below the pixel threshold. In 3D the camera is
  // outside the cube, above its top face.
  const double top = options.dimension == 3 ? 1.0 : 0.0;
  return {point("camera-position", cx, cy - 1.0 * reach, top + 0.5 * reach),
          point("camera-focal-point", cx, cy, top), point("camera-view-up", 0.0, 0.0, 1.0)};
}

} // namespace miniamr
