// A synthetic AMR forest shaped like a simulation's: refined around a spherical
// blast-wave front, stored depth-first in an array of cell records (so Canopy
// must use a storage-slot map and strided fields), with an optional cut-away
// mask. It stands in for a simulation until the mini-app exists.
#pragma once

#include <canopy/ForestDescription.h>

#include <array>
#include <cstdint>
#include <vector>

namespace canopy::tools
{

struct SyntheticForestOptions
{
  int dimension = 3;
  int branchFactor = 2;
  int rootsPerAxis = 6;
  int maxLevels = 6;
  /// Radius of the refined spherical front, in a unit domain centred on the origin;
  /// vary it over time for a moving front.
  double frontRadius = 0.62;
  bool cutaway = true; ///< mask the octant (quadrant in 2D) facing +x +y (+z)
  /// Store nodes depth-first with a slot map (true) or breadth-first without one.
  bool depthFirstStorage = true;
};

/// The "simulation" state: owns every array the description borrows.
class SyntheticForest
{
public:
  /// What the simulation stores per node, in its own depth-first order.
  struct CellRecord
  {
    double density;
    double velocity[3];
    std::int32_t refinementLevel;
  };

  explicit SyntheticForest(const SyntheticForestOptions& options);
  SyntheticForest(const SyntheticForest&) = delete;
  SyntheticForest& operator=(const SyntheticForest&) = delete;

  const ForestDescription& description() const { return Description; }
  std::size_t numberOfNodes() const { return Cells.size(); }
  std::size_t numberOfLeaves() const { return Pressure.size(); }
  const std::vector<CellRecord>& cells() const { return Cells; }

private:
  std::array<std::vector<double>, 3> Coordinates;
  std::vector<std::vector<std::uint8_t>> Refinement;
  std::vector<std::vector<std::uint8_t>> Masked;
  std::vector<std::vector<std::int64_t>> Slots;
  std::vector<CellRecord> Cells; ///< every node, depth-first, trees back to back
  std::vector<double> Pressure;  ///< leaves only, in slot order
  ForestDescription Description;
};

} // namespace canopy::tools
