// Canopy's description of a simulation's AMR forest: borrowed views only.
//
// A forest is a rectilinear grid of root cells; some of them carry a refinement
// tree (2^d- or 3^d-ary). The simulation keeps ownership of every pointer given
// here (coordinates, refinement bytes, masks, slot maps, fields) and must keep
// them alive and unchanged in shape while the vtkHyperTreeGrid built from this
// description is in use. Canopy never writes through them.
#pragma once

#include <array>
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
  AoS,      ///< tuples contiguous, components interleaved: x0 y0 z0 x1 y1 z1 ...
  SoA,      ///< one contiguous array per component
  Strided,  ///< components contiguous within a tuple, tuples tupleStrideBytes apart
  Indirect, ///< components contiguous within a tuple, tuple i at tupleAddresses[i]: records
            ///< scattered in memory (e.g. p4est's per-quadrant user_data)
  Blocks    ///< block forests only: each block's cells in the code's own block array,
            ///< ghost zones included (see BlockStrides); the only layout they take
};

/// How the cells of one block lie in the simulation's block array (a block forest's
/// field, Layout::Blocks). Interior cell (i, j, k), 0 <= i, j, k < cellsPerSide,
/// component c is at
///   blockStart + componentOffset(c)
///     + (i + ghostCells[0]) * cellBytes[0] + (j + ghostCells[1]) * cellBytes[1]
///     + (k + ghostCells[2]) * cellBytes[2]
/// where blockStart is where the block's array begins (its first ghost cell) and
/// componentOffset(c) = c * componentBytes (or 0 when components are separate arrays).
/// i, j, k run along the forest's axes that are not flat, in x, y, z order (a 2D
/// forest in the xz-plane: i along x, j along z); strides and ghosts of missing
/// axes are ignored. Ghost cells are never read.
struct BlockStrides
{
  std::array<std::size_t, 3> cellBytes{{0, 0, 0}}; ///< from cell i to i+1, j to j+1, k to k+1
  std::size_t componentBytes = 0;                  ///< from component c to c+1
  std::array<int, 3> ghostCells{{0, 0, 0}};        ///< ghost cells before the interior

  /// `[var][k][j][i]` (C order; Athena++/Parthenon/AthenaPK MeshBlock arrays, var
  /// outermost): each component a whole (n + 2 ghosts)^d array, i fastest.
  template <typename T>
  static BlockStrides variableOutermost(int dimension, int cellsPerSide, int ghostCells)
  {
    return packed(dimension, cellsPerSide, ghostCells, 1, sizeof(T), true);
  }

  /// `[k][j][i][var]` (C order; FLASH's unk(var, i, j, k, block) in Fortran): the
  /// components of a cell together.
  template <typename T>
  static BlockStrides variableInnermost(int dimension, int cellsPerSide, int ghostCells,
                                        int components)
  {
    return packed(dimension, cellsPerSide, ghostCells, components, sizeof(T), false);
  }

private:
  static BlockStrides packed(int dimension, int cellsPerSide, int ghostCells, int components,
                             std::size_t valueSize, bool variableOutermost);
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

  /// Blocks (block forests): how many blocks the arrays below describe (validated
  /// against the forest's blocks) and where each block's cells lie in its array.
  std::size_t numberOfBlocks = 0;
  BlockStrides blockStrides;
  /// Blocks allocated one by one: where block b's array begins (borrowed table).
  const void* const* blockAddresses = nullptr;
  /// Or all blocks in one array: block b's array begins at data + b * blockStrideBytes.
  std::size_t blockStrideBytes = 0;
  /// Or each component in arrays of its own, one table per component (borrowed),
  /// componentBlockAddresses[c][b]: componentBytes is then unused.
  std::vector<const void* const*> componentBlockAddresses;

  /// The simulation's own count of changes to this field's values, when it keeps
  /// one: 0 (the default), none: the values may have changed at every build.
  /// Nonzero and the same as at a GridBuilder's last build, with the field
  /// described alike (the same memory, layout and strides) and the topology
  /// (trees, masks, absent parts, slot maps) unchanged: the simulation promises the values did not
  /// change since, and the builder keeps the field's array object, unmodified, so that what filters
  /// derived from its values is kept too (the contour's value ranges; a
  /// leaves-only field's coarse averages are not computed again). A value
  /// changed under the same revision is then not seen.
  std::uint64_t valuesRevision = 0;

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

  /// Block forest, blocks allocated one by one (Athena++, Parthenon): block b's
  /// array begins at blockAddresses[b]. The table is borrowed, as are the blocks.
  /// A block field's coarse values (inside and above blocks) are volume averages,
  /// computed when something reads them.
  template <typename T>
  static FieldDescription blocks(std::string name, const T* const* blockAddresses,
                                 std::size_t numberOfBlocks, BlockStrides strides,
                                 int components = 1)
  {
    FieldDescription f = typedBlocks<T>(std::move(name), numberOfBlocks, strides, components);
    f.blockAddresses = reinterpret_cast<const void* const*>(blockAddresses);
    return f;
  }

  /// Block forest, every block in one array (FLASH's unk): block b's array begins at
  /// firstBlock + b * blockStrideBytes.
  template <typename T>
  static FieldDescription blockArray(std::string name, const T* firstBlock,
                                     std::size_t blockStrideBytes, std::size_t numberOfBlocks,
                                     BlockStrides strides, int components = 1)
  {
    FieldDescription f = typedBlocks<T>(std::move(name), numberOfBlocks, strides, components);
    f.data = firstBlock;
    f.blockStrideBytes = blockStrideBytes;
    return f;
  }

  /// Block forest, each component its own per-block arrays (a vector field kept as
  /// three scalar variables): componentBlockAddresses[c][b].
  template <typename T>
  static FieldDescription blockComponents(std::string name,
                                          const std::vector<const T* const*>& componentTables,
                                          std::size_t numberOfBlocks, BlockStrides strides)
  {
    FieldDescription f = typedBlocks<T>(std::move(name), numberOfBlocks, strides,
                                        static_cast<int>(componentTables.size()));
    for (const T* const* table : componentTables)
    {
      f.componentBlockAddresses.push_back(reinterpret_cast<const void* const*>(table));
    }
    return f;
  }

private:
  template <typename T>
  static FieldDescription typedBlocks(std::string name, std::size_t numberOfBlocks,
                                      BlockStrides strides, int components)
  {
    FieldDescription f =
        typed<T>(std::move(name), Layout::Blocks, components, Centering::LeavesOnly, 0);
    f.numberOfBlocks = numberOfBlocks;
    f.blockStrides = strides;
    return f;
  }

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
  /// Block forests, optional: per node, breadth-first, the index of the leaf's block
  /// in the fields' block tables (entries of refined and absent nodes are ignored).
  /// Without it, blocks are the present leaves breadth-first, tree by tree. Either
  /// every tree has one or none does; the present leaves' entries must be exactly
  /// 0 .. blocks-1.
  const std::int64_t* blockIndex = nullptr;
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
  /// Octrees of blocks (Athena++/Parthenon MeshBlocks, FLASH/PARAMESH, ForestClaw
  /// patches): 0 for an ordinary forest. n > 0: every present leaf of every tree's
  /// description is a block of n^d cells, n a power of branchFactor (2, 4, 8, ...;
  /// 8 to 64 are usual), whose cells become log_branchFactor(n) uniform levels
  /// of the grid below the leaf. Fields are then block fields (Layout::Blocks),
  /// read where the blocks are (no per-cell table); storageSlots are not used
  /// (blockIndex orders blocks). See docs/blocks.md.
  int blockCellsPerSide = 0;
  /// The simulation's own count of changes to its mesh, when it keeps one
  /// (p4est's `revision`, deal.II's refinement cycles): 0, none. Nonzero and the
  /// same as at the last build of a GridBuilder: the simulation promises that
  /// no tree, mask, absent part, slot map or block index changed since, and the
  /// builder then reuses them without reading their bytes (it still checks the
  /// number of trees, their roots and node counts, and reads their bytes when
  /// those differ). Field values and coordinates are read at every build.
  std::uint64_t revision = 0;
};

} // namespace canopy
