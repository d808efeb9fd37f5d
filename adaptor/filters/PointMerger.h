// Merges points by exact value into a preallocated coordinate buffer: an
// open-addressing table of point ids (no allocation per point), ids given in
// order of first use. -0.0 and 0.0 are the same point (compared with ==).
#pragma once

#include <vtkType.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <vector>

namespace canopy
{

class PointMerger
{
public:
  /// `coordinates`: room for 3 * maxPoints doubles; filled from the start.
  PointMerger(double* coordinates, std::size_t maxPoints) : Coordinates(coordinates)
  {
    std::size_t capacity = 16;
    while (capacity < 2 * maxPoints)
    {
      capacity *= 2;
    }
    Slots.assign(capacity, -1);
  }

  /// The id of the point, added if new.
  vtkIdType id(const std::array<double, 3>& p)
  {
    const std::size_t mask = Slots.size() - 1;
    for (std::size_t slot = hash(p) & mask;; slot = (slot + 1) & mask)
    {
      const vtkIdType existing = Slots[slot];
      if (existing < 0)
      {
        double* out = Coordinates + 3 * Count;
        out[0] = p[0];
        out[1] = p[1];
        out[2] = p[2];
        Slots[slot] = Count;
        return Count++;
      }
      const double* q = Coordinates + 3 * existing;
      if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2])
      {
        return existing;
      }
    }
  }

  vtkIdType count() const { return Count; }

private:
  static std::size_t hash(const std::array<double, 3>& p)
  {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (double x : p)
    {
      const double normal = x + 0.0; // -0.0 -> 0.0
      std::uint64_t bits = 0;
      std::memcpy(&bits, &normal, sizeof bits);
      h = (h ^ bits) * 0xff51afd7ed558ccdull;
      h ^= h >> 29;
    }
    return static_cast<std::size_t>(h);
  }

  double* Coordinates;
  std::vector<vtkIdType> Slots;
  vtkIdType Count = 0;
};

} // namespace canopy
