// A forest that owns its arrays, built from vtkHyperTreeGridSource's descriptor
// strings, so tests can describe the same grid to Canopy and to VTK.
#pragma once

#include <canopy/ForestDescription.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace canopy::testing
{

/// What vtkHyperTreeGridSource needs to build the same grid.
struct SourceParameters
{
  std::array<unsigned int, 3> dimensions{{1, 1, 1}}; ///< points per axis
  std::array<double, 3> gridScale{{1, 1, 1}};
  int branchFactor = 2;
  int maxDepth = 1; ///< levels, the root included
  std::string descriptor;
  std::string mask; ///< empty: no mask
};

/// Owns everything a ForestDescription borrows. Trees are all root cells, in
/// root-index order; nodes stored breadth-first, trees back to back. A "Depth"
/// field (double, every node) holds each node's level, as vtkHyperTreeGridSource's.
class DescriptorForest
{
public:
  explicit DescriptorForest(const SourceParameters& parameters);
  DescriptorForest(const DescriptorForest&) = delete;
  DescriptorForest& operator=(const DescriptorForest&) = delete;

  /// The description, pointing into this object's arrays.
  const ForestDescription& description() const { return Description; }
  ForestDescription& description() { return Description; }

  std::size_t numberOfNodes() const { return Depth.size(); }
  std::size_t numberOfLeaves() const;
  std::size_t numberOfUnmaskedLeaves() const;
  const std::vector<double>& depth() const { return Depth; }
  /// Per tree: refinement bytes, breadth-first.
  const std::vector<std::vector<std::uint8_t>>& refinement() const { return Refinement; }
  const std::vector<std::vector<std::uint8_t>>& masked() const { return Masked; }

private:
  std::array<std::vector<double>, 3> Coordinates;
  std::vector<std::vector<std::uint8_t>> Refinement;
  std::vector<std::vector<std::uint8_t>> Masked;
  std::vector<double> Depth;
  ForestDescription Description;
};

/// Splits a descriptor string into levels ('|'), dropping spaces.
std::vector<std::string> descriptorLevels(const std::string& descriptor);

} // namespace canopy::testing
