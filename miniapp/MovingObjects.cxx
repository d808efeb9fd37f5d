#include "MovingObjects.h"

#include <algorithm>
#include <cmath>

namespace miniamr
{
namespace
{

/// Position on [0, 1] after moving from x with speed v for time t, bouncing off 0 and 1.
double bounce(double x, double v, double t)
{
  double y = std::fmod(x + v * t, 2.0);
  if (y < 0)
    y += 2.0;
  return y <= 1.0 ? y : 2.0 - y;
}

} // namespace

MovingObjects::MovingObjects(std::vector<MovingObject> objects, int dimension)
    : Objects(std::move(objects)), Dimension(dimension)
{
}

MovingObject MovingObjects::at(std::size_t i, double time) const
{
  MovingObject o = Objects[i];
  if (o.kind == MovingObject::Kind::Sphere)
  {
    for (int a = 0; a < Dimension; ++a)
      o.center[a] = bounce(o.center[a], o.velocity[a], time);
  }
  else
  {
    o.offset = std::fmod(o.offset + o.speed * time, 1.0);
    if (o.offset < 0)
      o.offset += 1.0;
  }
  return o;
}

bool MovingObjects::surfaceCrosses(const std::array<double, 3>& low,
                                   const std::array<double, 3>& high, double time) const
{
  for (std::size_t i = 0; i < Objects.size(); ++i)
  {
    const MovingObject o = at(i, time);
    if (o.kind == MovingObject::Kind::Sphere)
    {
      // Nearest and farthest box points from the center straddle the radius.
      double nearest = 0;
      double farthest = 0;
      for (int a = 0; a < Dimension; ++a)
      {
        const double c = o.center[a];
        const double n = std::clamp(c, low[a], high[a]) - c;
        const double f = std::max(std::abs(low[a] - c), std::abs(high[a] - c));
        nearest += n * n;
        farthest += f * f;
      }
      if (nearest <= o.radius * o.radius && farthest >= o.radius * o.radius)
        return true;
    }
    else
    {
      // The box's corners lie on both sides of n . x = offset.
      double lowest = 0;
      double highest = 0;
      for (int a = 0; a < Dimension; ++a)
      {
        lowest += o.normal[a] * (o.normal[a] >= 0 ? low[a] : high[a]);
        highest += o.normal[a] * (o.normal[a] >= 0 ? high[a] : low[a]);
      }
      if (lowest <= o.offset && highest >= o.offset)
        return true;
    }
  }
  return false;
}

} // namespace miniamr
