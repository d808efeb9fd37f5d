// Objects moving through the domain (miniAMR's drivers of refinement): the
// cells their surfaces cross are refined to the finest level.
#pragma once

#include "MiniAppOptions.h"

#include <array>
#include <vector>

namespace miniamr
{

class MovingObjects
{
public:
  MovingObjects(std::vector<MovingObject> objects, int dimension);

  /// Whether the surface of any object, at time t, passes through the box.
  bool surfaceCrosses(const std::array<double, 3>& low, const std::array<double, 3>& high,
                      double time) const;

  /// Where object i is at time t (sphere: its center; plane: offset in x of n.x = offset).
  MovingObject at(std::size_t i, double time) const;
  std::size_t size() const { return Objects.size(); }

private:
  std::vector<MovingObject> Objects;
  int Dimension;
};

} // namespace miniamr
