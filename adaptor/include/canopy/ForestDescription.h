// Canopy's description of a simulation's AMR forest: borrowed views only.
//
// A forest is a rectilinear grid of root cells; some of them carry a refinement
// tree (2^d- or 3^d-ary). The simulation keeps ownership of every pointer given
// here (coordinates, refinement bytes, masks, slot maps, fields) and must keep
// them alive and unchanged in shape while the vtkHyperTreeGrid built from this
// description is in use. Canopy never writes through them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace canopy
{

/// Scalar type of a field's values.
enum class ValueType
{
  Float32,
  Float64,
  Int32,
  Int64
};

/// How a field's components are laid out in simulation memory.
enum class Layout
{
  AoS,     ///< tuples contiguous, components interleaved: x0 y0 z0 x1 y1 z1 ...
  SoA,     ///< one contiguous array per component
  Strided, ///< components contiguous within a tuple, tuples tupleStrideBytes apart
  Indirect ///< components contiguous within a tuple, tuple i at tupleAddresses[i]: records
           ///< scattered in memory (e.g. p4est's per-quadrant user_data)
};

/// Which nodes a field has values for.
enum class Centering
{
  EveryNode, ///< one tuple per node (coarse and leaf), indexed by the node's storage slot
  LeavesOnly ///< one tuple per leaf, leaves in storage order; Canopy restricts to coarse nodes
};

/// Size in bytes of one value of the given type.
std::size_t sizeOf(ValueType type);

/// The ValueType corresponding to a C++ scalar type.
template <typename T>
constexpr ValueType valueTypeOf();
template <>
constexpr ValueType valueTypeOf<float>()
{
  return ValueType::Float32;
}
template <>
constexpr ValueType valueTypeOf<double>()
{
  return ValueType::Float64;
}
template <>
constexpr ValueType valueTypeOf<std::int32_t>()
{
  return ValueType::Int32;
}
template <>
constexpr ValueType valueTypeOf<std::int64_t>()
{
  return ValueType::Int64;
}

/// A borrowed cell field. Build one with the typed factories below.
struct FieldDescription
{
  std::string name;
  ValueType type = ValueType::Float64;
  int components = 1;
  Layout layout = Layout::AoS;
  Centering centering = Centering::EveryNode;
  /// AoS and Strided: address of component 0 of tuple 0.
  const void* data = nullptr;
  /// SoA: one address per component.
  std::vector<const void*> componentData;
  /// Strided: bytes from one tuple to the next (>= components * value size).
  std::size_t tupleStrideBytes = 0;
  /// Indirect: one address per tuple, each of component 0 (borrowed, as are the values).
  const void* const* tupleAddresses = nullptr;
  /// How many tuples the simulation's array holds (validated against the forest).
  std::size_t numberOfTuples = 0;

  template <typename T>
  static FieldDescription aos(std::string name, const T* data, std::size_t numberOfTuples,
                              int components = 1, Centering centering = Centering::EveryNode)
  {
    FieldDescription f =
        typed<T>(std::move(name), Layout::AoS, components, centering, numberOfTuples);
    f.data = data;
    return f;
  }

  template <typename T>
  static FieldDescription soa(std::string name, const std::vector<const T*>& componentData,
                              std::size_t numberOfTuples,
                              Centering centering = Centering::EveryNode)
  {
    FieldDescription f =
        typed<T>(std::move(name), Layout::SoA, static_cast<int>(componentData.size()), centering,
                 numberOfTuples);
    f.componentData.assign(componentData.begin(), componentData.end());
    return f;
  }

  /// A field inside an array of records, e.g. `&cells[0].velocity[0]` with
  /// tupleStrideBytes = sizeof(Cell).
  template <typename T>
  static FieldDescription strided(std::string name, const T* firstValue,
                                  std::size_t tupleStrideBytes, std::size_t numberOfTuples,
                                  int components = 1, Centering centering = Centering::EveryNode)
  {
    FieldDescription f =
        typed<T>(std::move(name), Layout::Strided, components, centering, numberOfTuples);
    f.data = firstValue;
    f.tupleStrideBytes = tupleStrideBytes;
    return f;
  }

  /// Tuples scattered in memory: tuple i's components start at tupleAddresses[i].
  /// The address table is borrowed too (it must outlive the grid).
  template <typename T>
  static FieldDescription indirect(std::string name, const void* const* tupleAddresses,
                                   std::size_t numberOfTuples, int components = 1,
                                   Centering centering = Centering::EveryNode)
  {
    FieldDescription f =
        typed<T>(std::move(name), Layout::Indirect, components, centering, numberOfTuples);
    f.tupleAddresses = tupleAddresses;
    return f;
  }

private:
  /// What every factory sets; the caller adds where the values are.
  template <typename T>
  static FieldDescription typed(std::string name, Layout layout, int components,
                                Centering centering, std::size_t numberOfTuples)
  {
    FieldDescription f;
    f.name = std::move(name);
    f.type = valueTypeOf<T>();
    f.components = components;
    f.layout = layout;
    f.centering = centering;
    f.numberOfTuples = numberOfTuples;
    return f;
  }
};

/// One refinement tree, described breadth-first.
///
/// Nodes are numbered breadth-first within the tree: the root is node 0, then the
/// root's children in child order (x fastest, then y, then z), then their
/// children, level by level. `refinement[n]` is nonzero when node n is refined.
/// Exactly one byte per node, the deepest level (all zeros) included.
struct TreeDescription
{
  /// Index of the root cell in the root grid, i fastest, then j, then k.
  std::int64_t rootIndex = 0;
  /// One byte per node, breadth-first; nonzero = refined.
  const std::uint8_t* refinement = nullptr;
  /// Number of nodes in the tree (the length of refinement, masked and storageSlots).
  std::size_t numberOfNodes = 0;
  /// Optional, one byte per node, breadth-first; nonzero = masked (hidden with its subtree).
  const std::uint8_t* masked = nullptr;
  /// Optional node -> storage-slot map, one entry per node, breadth-first. Either every
  /// tree of the forest has one or none does; see ForestDescription.
  const std::int64_t* storageSlots = nullptr;
  /// Optional, one byte per node, breadth-first; nonzero = absent: another rank owns
  /// this part of the tree (a tree split between ranks, as p4est does). An absent node
  /// is a leaf of this description (describe another rank's part by its coarsest node)
  /// and is never the root. Absent nodes have no storage slot and no field values:
  /// the simulation's arrays hold only the nodes this rank has (see docs/api.md).
  const std::uint8_t* absent = nullptr;
};

/// The root grid: rectilinear point coordinates per axis, not necessarily uniform.
/// A 2D forest lies in an axis-aligned plane: exactly one axis has a single point.
/// A 1D forest is a line of roots along one axis: the two others have a single point.
struct RootGrid
{
  const double* x = nullptr;
  const double* y = nullptr;
  const double* z = nullptr;
  std::size_t pointsX = 0;
  std::size_t pointsY = 0;
  std::size_t pointsZ = 0;
};

/// A whole (rank-local) forest.
///
/// Storage order. Slots number the nodes this rank has, 0 .. presentNodes-1 over
/// the whole forest; absent nodes (TreeDescription::absent) have none. By default
/// each tree's present nodes are stored breadth-first, absent ones skipped, and the
/// trees back to back in the order of `trees` (without absent nodes, node n of the
/// t-th tree lives in slot (nodes of trees before t) + n). A simulation that keeps
/// its own order (depth-first, Morton, a memory pool) gives every tree a
/// storageSlots map instead; the slots of all trees' present nodes together must
/// then be exactly 0 .. presentNodes-1 (the entries of absent nodes are ignored).
/// EveryNode fields are indexed by slot. LeavesOnly fields hold one tuple per
/// present leaf, leaves ordered by slot (so breadth-first, tree by tree, by default).
struct ForestDescription
{
  int dimension = 3;    ///< 1, 2 or 3
  int branchFactor = 2; ///< 2 or 3
  /// Number of levels any tree may have, the root level included (VTK's MaxDepth).
  int maxLevels = 32;
  RootGrid rootGrid;
  std::vector<TreeDescription> trees;
  std::vector<FieldDescription> fields;
  /// What a root cell without a tree in `trees` is. false: nothing (a hole in the
  /// domain). true: its tree is on another rank (every root cell has a tree
  /// somewhere, as in p4est's bricks), so in 3D the faces toward it are inside the
  /// domain and not drawn; images then composite the same for any rank count.
  bool missingTreesAreElsewhere = false;
};

} // namespace canopy
