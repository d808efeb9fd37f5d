// Builds a vtkHyperTreeGrid from a ForestDescription without copying field data.
#pragma once

#include <canopy/ForestDescription.h>
#include <canopy/ForestValidation.h>

#include <vtkSmartPointer.h>

#include <string>
#include <vector>

class vtkHyperTreeGrid;

namespace canopy
{

/// Which fields to wrap. Only the requested ones cost anything.
class FieldRequest
{
public:
  /// Every field of the forest.
  static FieldRequest all() { return FieldRequest(true, {}); }
  /// Only these fields; an unknown name is an error.
  static FieldRequest only(std::vector<std::string> names)
  {
    return FieldRequest(false, std::move(names));
  }
  /// No field: topology (and mask) only.
  static FieldRequest none() { return FieldRequest(false, {}); }

  bool includesAll() const { return All; }
  const std::vector<std::string>& names() const { return Names; }

private:
  FieldRequest(bool all, std::vector<std::string> names) : All(all), Names(std::move(names)) {}
  bool All;
  std::vector<std::string> Names;
};

/// Builds the grid. Throws InvalidForest (nothing is built) when the description
/// or the request is malformed.
///
/// - Topology comes from the breadth-first refinement bytes, packed into descriptor
///   bits: each tree is built by vtkHyperTree::InitializeForReader from its bits (the
///   child table allocated once at its size), no per-node cursor walk.
/// - Cells (VTK global indices) are numbered breadth-first, tree by tree: implicit,
///   one offset per tree, no per-node table. With the default storage a cell is its
///   storage slot; with slot maps or absent nodes, fields read through a cell -> slot
///   table (8 bytes per cell, shared by all fields).
/// - EveryNode fields are wrapped in place: AoS by vtkAOSDataArrayTemplate, SoA by
///   vtkSOADataArrayTemplate, strided by a borrowing array. LeavesOnly fields borrow
///   the leaf values and own only the coarse averages (see docs/api.md).
/// - Root coordinates are wrapped in place too. The mask is built (Canopy owns it).
/// The returned grid borrows simulation memory: use it while that memory is valid.
vtkSmartPointer<vtkHyperTreeGrid>
buildHyperTreeGrid(const ForestDescription& forest,
                   const FieldRequest& request = FieldRequest::all());

} // namespace canopy
