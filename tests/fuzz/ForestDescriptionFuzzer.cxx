// libFuzzer target for Canopy's forest description (docs/testing.md).
//
// Each input is decoded into a ForestDescription that owns its memory: dimension,
// branch factor, maxLevels, root grid, trees (refinement, mask and absent bytes,
// optional storage slots) and fields of every layout and centering, and a field
// request. Most inputs describe a valid forest; some carry a deliberate defect
// ("corruption") that makes them invalid by docs/api.md. Then:
//  - a defective description must be refused with canopy::InvalidForest;
//  - any other must build, and the grid must agree with an independent reading of
//    the description: the trees' shape from the refinement bytes (leaves, levels),
//    cells numbered breadth-first tree by tree, each root where its index says, the
//    mask (masked or absent nodes), the ghost marks of absent nodes, and every value
//    of every requested field: present nodes read from the simulation's arrays at
//    their slot, absent ones NaN (integers 0), coarse nodes of leaves-only fields the
//    mean of their present children (unmasked ones, or all if every one is masked);
//  - the simulation's memory is never written.
// Anything else aborts with a message (libFuzzer saves the input). AddressSanitizer
// catches reads outside the simulation's arrays: every array is allocated to its
// exact size.
//
// Input format (tests/fuzz/make_corpus.py writes inputs in it): bytes read front to
// back, every read past the end is 0.
//   header   shape: bit 0 3D, bit 1 branch factor 3, bit 2 missingTreesAreElsewhere,
//                   bit 3 storage slots, bits 4-5 flat axis of a 2D grid (3: a 1D
//                   line instead, along the grid defect's axis, whatever bit 0),
//                   bits 6-7 field request (all, none, some, some + an unknown name)
//            maxLevels: < 0xF0 -> 1 + v % 5, else WildLevels[v - 0xF0]
//            points per axis: 3 bytes, 2 + v % 3 (flat axes of a 2D or 1D grid: 1)
//            grid defect: v % 16 (10 NaN, 11 not increasing, 12 null, 13 no points,
//                   14 wrong flat axes, 15 too many points), axis (v / 16) % 3 (a 1D
//                   grid's line)
//            coordinates: spacing 0.5 * (1 + v % 3)
//   trees    count: v % (root cells + 1); then per tree:
//            root: picks the (v % free)-th unused root cell
//            flags: bit 0 mask, bit 1 absent, bits 2-7 defect (TreeDefect)
//            one refinement byte per node that may refine (odd = refined), breadth-first
//            with a mask: one byte per node (odd = masked)
//            with absent: one byte per leaf below the root (odd = absent)
//   slots    with storage slots and trees: 4 bytes seed of the permutation, 1 byte defect
//   fields   count: v % 5; then per field 3 bytes:
//            A: bits 0-1 type, 2-3 layout, bit 4 leaves-only, bits 5-6 components - 1 (% 3)
//            B: bits 0-1 record padding (strided), 2-3 extra tuples, 4-6 special value
//               (4 NaN, 5 +inf, 6 -inf, 7 -0.0), bit 7 null pointer when there is nothing
//            C: defect, v % 32 (FieldDefect; below 18: none)
//   request  with "some": one byte, bit i selects field i
#include <canopy/HtgBuilder.h>

#include <vtkAbstractArray.h>
#include <vtkBitArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkVariant.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <limits>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace
{

using canopy::Centering;
using canopy::FieldDescription;
using canopy::ForestDescription;
using canopy::Layout;
using canopy::TreeDescription;
using canopy::ValueType;

/// Keeps each input small enough for hundreds of runs per second.
constexpr std::size_t NodeBudget = 1200;

/// maxLevels at and around the bounds docs/api.md states (62 binary, 39 ternary).
constexpr std::array<int, 16> WildLevels{
    {0, -1, INT_MIN, INT_MAX, 61, 62, 63, 64, 38, 39, 40, 6, 7, 8, 9, 10}};

int maxSupportedLevels(int branchFactor)
{
  return branchFactor == 2 ? 62 : 39;
}

enum TreeDefect
{
  ExtraNode = 48,
  MissingNode,
  NullRefinement,
  NoNodes,
  BeyondMaxLevels,
  AbsentRoot,
  RefinedAbsentNode,
  DuplicateRoot,
  RootOutOfRange,
};

enum FieldDefect
{
  FewerTuples = 18,
  ZeroComponents,
  NegativeComponents,
  EmptyName,
  DuplicateName,
  NullData,
  MisalignedData,
  StrideTooSmall,
  StrideNotMultiple,
  SoAPointerCount,
  IntegerLeavesOnly,
  NullTupleAddress,
  UnknownLayout,
  UnknownType,
};

class Input
{
public:
  Input(const std::uint8_t* data, std::size_t size) : Data(data), Size(size) {}
  std::uint8_t byte() { return Position < Size ? Data[Position++] : 0; }
  std::uint32_t word()
  {
    std::uint32_t value = 0;
    for (int i = 0; i < 4; ++i)
    {
      value = value << 8 | byte();
    }
    return value;
  }

private:
  const std::uint8_t* Data;
  std::size_t Size;
  std::size_t Position = 0;
};

[[noreturn]] void fail(const std::string& message)
{
  std::fprintf(stderr, "canopy forest fuzzer: %s\n", message.c_str());
  std::fflush(stderr);
  std::abort();
}

std::size_t valueSize(ValueType type)
{
  return type == ValueType::Float32 || type == ValueType::Int32 ? 4 : 8;
}

bool isInteger(ValueType type)
{
  return type == ValueType::Int32 || type == ValueType::Int64;
}

/// A value as the grid should give it: exact for every type (int64 beyond 2^53 too).
struct Scalar
{
  bool integer = false;
  double real = 0;
  long long whole = 0;

  bool operator==(const Scalar& other) const
  {
    if (integer)
    {
      return other.integer && whole == other.whole;
    }
    return !other.integer && ((std::isnan(real) && std::isnan(other.real)) || real == other.real);
  }
  std::string str() const
  {
    std::ostringstream out;
    out.precision(17);
    if (integer)
    {
      out << whole;
    }
    else
    {
      out << real;
    }
    return out.str();
  }
};

struct Tree
{
  std::int64_t rootIndex = 0;
  std::vector<std::uint8_t> refinement; ///< what the description points to
  std::vector<std::uint8_t> masked, absent;
  std::vector<std::int64_t> slots;
  std::size_t claimedNodes = 0;
  bool nullRefinement = false;
  // The real shape (before defects), for the independent check.
  std::vector<bool> refined;
  std::vector<int> level;
  std::size_t nodes() const { return refined.size(); }
  bool isMasked(std::size_t n) const { return !masked.empty() && masked[n] != 0; }
  bool isAbsent(std::size_t n) const { return !absent.empty() && absent[n] != 0; }
};

struct Field
{
  std::string name;
  ValueType type = ValueType::Float64;
  int components = 1;
  Layout layout = Layout::AoS;
  bool leavesOnly = false;
  std::size_t tuples = 0;
  int special = 0;
  std::size_t specialTuple = 0;
  // The simulation's memory, each piece allocated to its exact size.
  std::vector<unsigned char> block;              ///< AoS, strided
  std::vector<std::vector<unsigned char>> parts; ///< SoA components, indirect records
  std::vector<const void*> addresses;            ///< indirect
  std::vector<std::vector<unsigned char>> snapshot;
};

/// What the simulation stores for tuple `tuple`, component `c` of field `f`.
template <typename T>
T storedValue(const Field& field, std::size_t f, std::size_t tuple, int c)
{
  if constexpr (std::is_floating_point_v<T>)
  {
    if (field.special != 0 && tuple == field.specialTuple && c == 0)
    {
      switch (field.special)
      {
      case 4:
        return std::numeric_limits<T>::quiet_NaN();
      case 5:
        return std::numeric_limits<T>::infinity();
      case 6:
        return -std::numeric_limits<T>::infinity();
      default:
        return T(-0.0);
      }
    }
    return static_cast<T>(0.5 * static_cast<double>(f + 1) + 1.25 * static_cast<double>(tuple) +
                          0.0625 * c);
  }
  else if constexpr (sizeof(T) == 4)
  {
    return static_cast<T>(100000 * static_cast<long long>(f + 1) +
                          8 * static_cast<long long>(tuple) + c);
  }
  else
  {
    // Above 2^53: a detour through double would show.
    return static_cast<T>((1LL << 60) + (static_cast<long long>(f) << 24) +
                          8 * static_cast<long long>(tuple) + c);
  }
}

template <typename T>
Scalar scalarOf(T value)
{
  Scalar s;
  s.integer = std::is_integral_v<T>;
  s.real = static_cast<double>(value);
  s.whole = std::is_integral_v<T> ? static_cast<long long>(value) : 0;
  return s;
}

Scalar absentScalar(ValueType type)
{
  Scalar s;
  s.integer = isInteger(type);
  s.real = std::numeric_limits<double>::quiet_NaN();
  return s;
}

/// The decoded input: a description, the memory it borrows, and what was done to it.
struct Generated
{
  ForestDescription forest;
  int requestMode = 0;
  std::vector<std::string> requested;
  std::vector<std::string> defects; ///< non-empty: the description is invalid
  std::array<std::vector<double>, 3> coordinates;
  std::array<std::size_t, 3> points{{1, 1, 1}};
  std::array<std::size_t, 3> cells{{1, 1, 1}};
  std::size_t rootCells = 1;
  std::vector<Tree> trees;
  std::vector<Field> fields;
  bool explicitSlots = false;
  std::size_t children = 4;

  void defect(const std::string& what) { defects.push_back(what); }
};

void generateGrid(Input& in, Generated& g, int dimension, int flatAxis)
{
  std::array<std::uint8_t, 3> pointBytes{};
  for (auto& v : pointBytes)
  {
    v = in.byte();
  }
  const std::uint8_t gridDefect = in.byte();
  const int lineAxis = (gridDefect / 16) % 3;
  for (int a = 0; a < 3; ++a)
  {
    const bool flat = (dimension == 2 && a == flatAxis) || (dimension == 1 && a != lineAxis);
    g.points[a] = flat ? 1 : 2 + pointBytes[a] % 3;
  }
  const double spacing = 0.5 * (1 + in.byte() % 3);
  std::array<std::size_t, 3> claimed = g.points;
  std::array<bool, 3> nullAxis{{false, false, false}};
  const int kind = gridDefect % 16;
  int axis = (gridDefect / 16) % 3;
  if ((kind == 10 || kind == 11) && g.points[axis] < 2)
  {
    axis = (axis + 1) % 3; // a non-flat axis (a 1D grid's line is never flat here)
  }
  for (int a = 0; a < 3; ++a)
  {
    g.cells[a] = g.points[a] > 1 ? g.points[a] - 1 : 1;
  }
  g.rootCells = g.cells[0] * g.cells[1] * g.cells[2];
  std::array<std::size_t, 3> allocated = g.points;
  switch (kind)
  {
  case 13:
    claimed[axis] = 0;
    g.defect("an axis without points");
    break;
  case 14:
    if (dimension == 3)
    {
      claimed[axis] = allocated[axis] = 1;
      g.defect("a 3D grid with a flat axis");
    }
    else if (dimension == 1)
    {
      const int second = (lineAxis + 1) % 3;
      claimed[second] = allocated[second] = 2;
      g.defect("a 1D grid with a second axis");
    }
    else
    {
      claimed[flatAxis] = allocated[flatAxis] = 2;
      g.defect("a 2D grid without a flat axis");
    }
    break;
  case 15:
    claimed[axis] = (std::size_t(1) << 32) + 1; // more than VTK indexes; never read
    g.defect("more points than a vtkHyperTreeGrid holds");
    break;
  case 12:
    nullAxis[axis] = true;
    g.defect("a null coordinate pointer");
    break;
  default:
    break;
  }
  for (int a = 0; a < 3; ++a)
  {
    g.coordinates[a].resize(allocated[a]);
    for (std::size_t i = 0; i < allocated[a]; ++i)
    {
      g.coordinates[a][i] = -3.0 + 10.0 * a + spacing * static_cast<double>(i);
    }
  }
  if (kind == 10)
  {
    g.coordinates[axis].back() = std::numeric_limits<double>::quiet_NaN();
    g.defect("a NaN coordinate");
  }
  if (kind == 11)
  {
    g.coordinates[axis][1] = g.coordinates[axis][0];
    g.defect("coordinates not increasing");
  }
  canopy::RootGrid& grid = g.forest.rootGrid;
  grid.x = nullAxis[0] ? nullptr : g.coordinates[0].data();
  grid.y = nullAxis[1] ? nullptr : g.coordinates[1].data();
  grid.z = nullAxis[2] ? nullptr : g.coordinates[2].data();
  grid.pointsX = claimed[0];
  grid.pointsY = claimed[1];
  grid.pointsZ = claimed[2];
}

/// Refinement breadth-first, one byte per node that may still refine.
void generateShape(Input& in, Tree& tree, int levelCap, std::size_t& budget, std::size_t children)
{
  tree.refined.assign(1, false);
  tree.level.assign(1, 0);
  budget -= std::min<std::size_t>(budget, 1);
  for (std::size_t n = 0; n < tree.refined.size(); ++n)
  {
    tree.refinement.push_back(0);
    if (tree.level[n] + 1 >= levelCap || budget < children)
    {
      continue;
    }
    const std::uint8_t v = in.byte();
    if (v & 1)
    {
      tree.refinement[n] = v; // any nonzero byte means refined
      tree.refined[n] = true;
      for (std::size_t c = 0; c < children; ++c)
      {
        tree.refined.push_back(false);
        tree.level.push_back(tree.level[n] + 1);
      }
      budget -= children;
    }
  }
}

void generateTrees(Input& in, Generated& g, int levelCap)
{
  const std::size_t count = in.byte() % (g.rootCells + 1);
  std::vector<std::int64_t> freeRoots(g.rootCells);
  for (std::size_t r = 0; r < g.rootCells; ++r)
  {
    freeRoots[r] = static_cast<std::int64_t>(r);
  }
  std::size_t budget = NodeBudget;
  g.trees.resize(count);
  for (std::size_t t = 0; t < count; ++t)
  {
    Tree& tree = g.trees[t];
    const std::uint8_t pick = in.byte();
    const std::size_t index = pick % freeRoots.size();
    tree.rootIndex = freeRoots[index];
    freeRoots.erase(freeRoots.begin() + static_cast<std::ptrdiff_t>(index));
    const std::uint8_t flags = in.byte();
    const int defect = flags >> 2;
    const int cap = defect == BeyondMaxLevels ? levelCap + 1 : levelCap;
    generateShape(in, tree, cap, budget, g.children);
    if (defect == BeyondMaxLevels && tree.level.back() + 1 > levelCap)
    {
      g.defect("a tree refined beyond maxLevels");
    }
    const std::size_t n = tree.nodes();
    if (flags & 1)
    {
      tree.masked.resize(n);
      for (auto& m : tree.masked)
      {
        const std::uint8_t v = in.byte();
        m = v & 1 ? v : 0;
      }
    }
    if (flags & 2)
    {
      tree.absent.assign(n, 0);
      for (std::size_t node = 1; node < n; ++node)
      {
        if (!tree.refined[node])
        {
          const std::uint8_t v = in.byte();
          tree.absent[node] = v & 1 ? v : 0;
        }
      }
    }
    tree.claimedNodes = n;
    switch (defect)
    {
    case ExtraNode:
      tree.refinement.push_back(0);
      tree.claimedNodes = n + 1;
      g.defect("a refinement byte too many");
      break;
    case MissingNode:
      tree.refinement.pop_back();
      tree.claimedNodes = n - 1;
      g.defect("a refinement byte too few");
      break;
    case NullRefinement:
      tree.nullRefinement = true;
      g.defect("a null refinement pointer");
      break;
    case NoNodes:
      tree.claimedNodes = 0;
      g.defect("a tree without nodes");
      break;
    case AbsentRoot:
      tree.absent.resize(n, 0);
      tree.absent[0] = 1;
      g.defect("an absent root");
      break;
    case RefinedAbsentNode:
      for (std::size_t node = 1; node < n; ++node)
      {
        if (tree.refined[node])
        {
          tree.absent.resize(n, 0);
          tree.absent[node] = 1;
          g.defect("a refined absent node");
          break;
        }
      }
      break;
    case DuplicateRoot:
      if (t > 0)
      {
        tree.rootIndex = g.trees[t - 1].rootIndex;
        g.defect("two trees on one root cell");
      }
      break;
    case RootOutOfRange:
      tree.rootIndex = flags & 1 ? -1 : static_cast<std::int64_t>(g.rootCells);
      g.defect("a root index out of range");
      break;
    default:
      break;
    }
  }
}

/// Present nodes breadth-first, trees back to back (the default storage order).
std::size_t countPresent(const Generated& g, bool leavesOnly)
{
  std::size_t count = 0;
  for (const Tree& tree : g.trees)
  {
    for (std::size_t n = 0; n < tree.nodes(); ++n)
    {
      count += !tree.isAbsent(n) && (!leavesOnly || !tree.refined[n]);
    }
  }
  return count;
}

void generateSlots(Input& in, Generated& g)
{
  if (!g.explicitSlots || g.trees.empty())
  {
    return;
  }
  std::minstd_rand random(in.word());
  const std::uint8_t defect = in.byte() % 8;
  const std::size_t present = countPresent(g, false);
  std::vector<std::int64_t> permutation(present);
  for (std::size_t i = 0; i < present; ++i)
  {
    permutation[i] = static_cast<std::int64_t>(i);
  }
  std::shuffle(permutation.begin(), permutation.end(), random);
  std::size_t next = 0;
  for (Tree& tree : g.trees)
  {
    tree.slots.resize(tree.nodes());
    for (std::size_t n = 0; n < tree.nodes(); ++n)
    {
      // Entries of absent nodes are ignored (docs/api.md): anything goes.
      tree.slots[n] =
          tree.isAbsent(n) ? std::numeric_limits<std::int64_t>::min() + 7 : permutation[next++];
    }
  }
  Tree* first = nullptr;
  std::size_t firstNode = 0;
  for (Tree& tree : g.trees)
  {
    for (std::size_t n = 0; n < tree.nodes() && !first; ++n)
    {
      if (!tree.isAbsent(n))
      {
        first = &tree;
        firstNode = n;
      }
    }
  }
  if (defect == 5 && present >= 2)
  {
    // The next present node after the first takes the first's slot.
    bool seenFirst = false;
    for (Tree& tree : g.trees)
    {
      for (std::size_t n = 0; n < tree.nodes(); ++n)
      {
        if (tree.isAbsent(n))
        {
          continue;
        }
        if (seenFirst)
        {
          tree.slots[n] = first->slots[firstNode];
          g.defect("a storage slot used twice");
          return;
        }
        seenFirst = true;
      }
    }
  }
  if (defect == 6 && first)
  {
    first->slots[firstNode] = static_cast<std::int64_t>(present);
    g.defect("a storage slot out of range");
  }
  if (defect == 7 && g.trees.size() >= 2)
  {
    g.trees[0].slots.clear();
    g.defect("storage slots on some trees only");
  }
}

template <typename T>
void storeTuple(Field& field, std::size_t f, std::size_t tuple, unsigned char* const* component)
{
  for (int c = 0; c < field.components; ++c)
  {
    const T value = storedValue<T>(field, f, tuple, c);
    std::memcpy(component[c], &value, sizeof(T));
  }
}

template <typename T>
void fillField(Field& field, std::size_t f, std::size_t stridePadding)
{
  const auto nc = static_cast<std::size_t>(field.components);
  const std::size_t size = sizeof(T);
  std::vector<unsigned char*> at(nc);
  switch (field.layout)
  {
  case Layout::AoS:
  case Layout::Strided:
  {
    const std::size_t stride =
        field.layout == Layout::AoS ? nc * size : (nc + stridePadding) * size;
    // Exactly up to the last tuple's last component.
    field.block.resize(field.tuples == 0 ? 0 : (field.tuples - 1) * stride + nc * size);
    for (std::size_t i = 0; i < field.tuples; ++i)
    {
      for (std::size_t c = 0; c < nc; ++c)
      {
        at[c] = field.block.data() + i * stride + c * size;
      }
      storeTuple<T>(field, f, i, at.data());
    }
    break;
  }
  case Layout::SoA:
    field.parts.assign(nc, std::vector<unsigned char>(field.tuples * size));
    for (std::size_t i = 0; i < field.tuples; ++i)
    {
      for (std::size_t c = 0; c < nc; ++c)
      {
        at[c] = field.parts[c].data() + i * size;
      }
      storeTuple<T>(field, f, i, at.data());
    }
    break;
  case Layout::Blocks: // not generated: block forests have their own checks
    break;
  case Layout::Indirect:
    // One allocation per record: reading past a record is caught.
    field.parts.assign(field.tuples, std::vector<unsigned char>(nc * size));
    field.addresses.resize(field.tuples);
    for (std::size_t i = 0; i < field.tuples; ++i)
    {
      for (std::size_t c = 0; c < nc; ++c)
      {
        at[c] = field.parts[i].data() + c * size;
      }
      storeTuple<T>(field, f, i, at.data());
      field.addresses[i] = field.parts[i].data();
    }
    break;
  }
}

void generateFields(Input& in, Generated& g)
{
  const std::size_t count = in.byte() % 5;
  g.fields.resize(count);
  const std::size_t presentNodes = countPresent(g, false);
  const std::size_t presentLeaves = countPresent(g, true);
  for (std::size_t f = 0; f < count; ++f)
  {
    Field& field = g.fields[f];
    const std::uint8_t a = in.byte();
    const std::uint8_t b = in.byte();
    const int defect = in.byte() % 32;
    field.name = "field" + std::to_string(f);
    field.type = static_cast<ValueType>(a & 3);
    field.layout = static_cast<Layout>((a >> 2) & 3);
    field.leavesOnly = (a >> 4) & 1;
    field.components = 1 + ((a >> 5) & 3) % 3;
    if (field.leavesOnly && isInteger(field.type))
    {
      if (defect == IntegerLeavesOnly)
      {
        g.defect("an integer leaves-only field");
      }
      else
      {
        field.type = field.type == ValueType::Int32 ? ValueType::Float32 : ValueType::Float64;
      }
    }
    const std::size_t needed = field.leavesOnly ? presentLeaves : presentNodes;
    field.tuples = needed + ((b >> 2) & 3); // more than needed is fine
    if (defect == FewerTuples && needed > 0)
    {
      field.tuples = needed - 1;
      g.defect("a field with too few tuples");
    }
    field.special = (b >> 4) & 7;
    field.special = field.special >= 4 ? field.special : 0;
    field.specialTuple = needed / 2;
    const std::size_t padding = b & 3;
    switch (field.type)
    {
    case ValueType::Float32:
      fillField<float>(field, f, padding);
      break;
    case ValueType::Float64:
      fillField<double>(field, f, padding);
      break;
    case ValueType::Int32:
      fillField<std::int32_t>(field, f, padding);
      break;
    case ValueType::Int64:
      fillField<std::int64_t>(field, f, padding);
      break;
    }
    for (const auto& part : field.parts)
    {
      field.snapshot.push_back(part);
    }
    field.snapshot.push_back(field.block);

    FieldDescription d;
    d.name = field.name;
    d.type = field.type;
    d.components = field.components;
    d.layout = field.layout;
    d.centering = field.leavesOnly ? Centering::LeavesOnly : Centering::EveryNode;
    d.numberOfTuples = field.tuples;
    const std::size_t size = valueSize(field.type);
    const bool nullWhenEmpty = (b >> 7) != 0 && field.tuples == 0;
    switch (field.layout)
    {
    case Layout::AoS:
    case Layout::Strided:
      d.data = nullWhenEmpty || field.block.empty() ? nullptr : field.block.data();
      d.tupleStrideBytes = (static_cast<std::size_t>(field.components) + padding) * size;
      break;
    case Layout::SoA:
      for (auto& part : field.parts)
      {
        d.componentData.push_back(nullWhenEmpty || part.empty() ? nullptr : part.data());
      }
      break;
    case Layout::Indirect:
      d.tupleAddresses =
          nullWhenEmpty || field.addresses.empty() ? nullptr : field.addresses.data();
      break;
    case Layout::Blocks: // not generated
      break;
    }
    switch (defect)
    {
    case ZeroComponents:
    case NegativeComponents:
      d.components = defect == ZeroComponents ? 0 : -1;
      g.defect("a field with fewer than one component");
      break;
    case EmptyName:
      d.name.clear();
      g.defect("a field without a name");
      break;
    case DuplicateName:
      if (f > 0)
      {
        d.name = g.forest.fields[0].name;
        g.defect("two fields with one name");
      }
      break;
    case NullData:
      if (field.tuples > 0)
      {
        if (field.layout == Layout::SoA)
        {
          d.componentData[0] = nullptr;
        }
        else if (field.layout == Layout::Indirect)
        {
          d.tupleAddresses = nullptr;
        }
        else
        {
          d.data = nullptr;
        }
        g.defect("a null field pointer");
      }
      break;
    case MisalignedData:
      if (field.layout == Layout::SoA)
      {
        if (field.tuples > 0)
        {
          d.componentData[0] = field.parts[0].data() + 1;
          g.defect("a misaligned component pointer");
        }
      }
      else if (field.layout == Layout::Indirect)
      {
        if (field.tuples > 0)
        {
          field.addresses[0] = field.parts[0].data() + 1;
          g.defect("a misaligned tuple address");
        }
      }
      else if (!field.block.empty())
      {
        d.data = field.block.data() + 1;
        g.defect("a misaligned data pointer");
      }
      break;
    case StrideTooSmall:
      if (field.layout == Layout::Strided)
      {
        d.tupleStrideBytes = static_cast<std::size_t>(field.components) * size - 1;
        g.defect("a stride smaller than a tuple");
      }
      break;
    case StrideNotMultiple:
      if (field.layout == Layout::Strided)
      {
        d.tupleStrideBytes += 1;
        g.defect("a stride that is not a multiple of the value size");
      }
      break;
    case SoAPointerCount:
      if (field.layout == Layout::SoA)
      {
        d.componentData.push_back(d.componentData[0]);
        g.defect("an SoA field with a pointer too many");
      }
      break;
    case NullTupleAddress:
      if (field.layout == Layout::Indirect && field.tuples > 0)
      {
        field.addresses[field.tuples - 1] = nullptr;
        g.defect("a null tuple address");
      }
      break;
    case UnknownLayout:
      d.layout = static_cast<Layout>(7);
      g.defect("an unknown layout");
      break;
    case UnknownType:
      d.type = static_cast<ValueType>(9);
      g.defect("an unknown value type");
      break;
    default:
      break;
    }
    g.forest.fields.push_back(std::move(d));
  }
}

Generated generate(const std::uint8_t* data, std::size_t size)
{
  Input in(data, size);
  Generated g;
  const std::uint8_t shape = in.byte();
  const int flatBits = (shape >> 4) & 3;
  const int dimension = flatBits == 3 ? 1 : shape & 1 ? 3 : 2;
  const int branchFactor = shape & 2 ? 3 : 2;
  g.forest.dimension = dimension;
  g.forest.branchFactor = branchFactor;
  g.forest.missingTreesAreElsewhere = (shape >> 2) & 1;
  g.explicitSlots = (shape >> 3) & 1;
  const int flatAxis = std::min(flatBits, 2);
  g.requestMode = shape >> 6;
  g.children = static_cast<std::size_t>(dimension == 3 ? branchFactor * branchFactor * branchFactor
                                        : dimension == 2 ? branchFactor * branchFactor
                                                         : branchFactor);
  const std::uint8_t levels = in.byte();
  const int maxLevels = levels < 0xF0 ? 1 + levels % 5 : WildLevels[levels - 0xF0];
  g.forest.maxLevels = maxLevels;
  const bool levelsValid = maxLevels >= 1 && maxLevels <= maxSupportedLevels(branchFactor);
  if (!levelsValid)
  {
    g.defect("maxLevels out of range");
  }
  generateGrid(in, g, dimension, flatAxis);
  generateTrees(in, g, levelsValid ? maxLevels : 1);
  generateSlots(in, g);
  for (Tree& tree : g.trees)
  {
    TreeDescription d;
    d.rootIndex = tree.rootIndex;
    d.refinement = tree.nullRefinement ? nullptr : tree.refinement.data();
    d.numberOfNodes = tree.claimedNodes;
    d.masked = tree.masked.empty() ? nullptr : tree.masked.data();
    d.absent = tree.absent.empty() ? nullptr : tree.absent.data();
    d.storageSlots = tree.slots.empty() ? nullptr : tree.slots.data();
    g.forest.trees.push_back(d);
  }
  generateFields(in, g);
  if (g.requestMode >= 2)
  {
    const std::uint8_t chosen = in.byte();
    for (std::size_t f = 0; f < g.fields.size(); ++f)
    {
      if ((chosen >> f) & 1)
      {
        g.requested.push_back(g.forest.fields[f].name);
      }
    }
    if (g.requestMode == 3)
    {
      g.requested.push_back("no such field");
      g.defect("a request for an unknown field");
    }
  }
  return g;
}

// ---- the independent check ----

struct Shape
{
  std::vector<std::size_t> firstCell; ///< per tree
  std::size_t totalCells = 0;
};

std::string where(std::size_t t, std::size_t n)
{
  return "tree " + std::to_string(t) + " node " + std::to_string(n);
}

/// Trees from the refinement bytes against the vtkHyperTrees, breadth-first.
Shape checkTrees(const Generated& g, vtkHyperTreeGrid* htg)
{
  Shape shape;
  if (htg->GetDimension() != static_cast<unsigned>(g.forest.dimension) ||
      htg->GetBranchFactor() != static_cast<unsigned>(g.forest.branchFactor))
  {
    fail("dimension or branch factor differ from the description");
  }
  std::vector<bool> described(g.rootCells, false);
  for (std::size_t t = 0; t < g.trees.size(); ++t)
  {
    const Tree& tree = g.trees[t];
    described[static_cast<std::size_t>(tree.rootIndex)] = true;
    shape.firstCell.push_back(shape.totalCells);
    vtkHyperTree* hyperTree = htg->GetTree(tree.rootIndex);
    if (!hyperTree)
    {
      fail("tree " + std::to_string(t) + " is missing from the grid");
    }
    std::deque<vtkIdType> queue{0};
    std::size_t bfs = 0;
    std::size_t leaves = 0;
    while (!queue.empty())
    {
      const vtkIdType local = queue.front();
      queue.pop_front();
      if (bfs >= tree.nodes())
      {
        fail("tree " + std::to_string(t) + " has more nodes in the grid than described");
      }
      if (hyperTree->IsLeaf(local) == tree.refined[bfs])
      {
        fail(where(t, bfs) + ": refined in one and a leaf in the other");
      }
      const vtkIdType cell = hyperTree->GetGlobalIndexFromLocal(local);
      if (cell != static_cast<vtkIdType>(shape.totalCells + bfs))
      {
        fail(where(t, bfs) + " is cell " + std::to_string(cell) + ", not " +
             std::to_string(shape.totalCells + bfs) + " (breadth-first, tree by tree)");
      }
      if (tree.refined[bfs])
      {
        const vtkIdType elder = hyperTree->GetElderChildIndex(static_cast<unsigned>(local));
        for (std::size_t c = 0; c < g.children; ++c)
        {
          queue.push_back(elder + static_cast<vtkIdType>(c));
        }
      }
      else
      {
        ++leaves;
      }
      ++bfs;
    }
    const int levels = tree.level.back() + 1;
    if (bfs != tree.nodes() ||
        hyperTree->GetNumberOfVertices() != static_cast<vtkIdType>(tree.nodes()) ||
        hyperTree->GetNumberOfLeaves() != static_cast<vtkIdType>(leaves) ||
        hyperTree->GetNumberOfLevels() != static_cast<unsigned>(levels))
    {
      fail("tree " + std::to_string(t) + ": node, leaf or level count differs");
    }
    // The root sits where its index says: i fastest, then j, then k.
    const auto r = static_cast<std::size_t>(tree.rootIndex);
    const std::array<std::size_t, 3> ijk{
        {r % g.cells[0], (r / g.cells[0]) % g.cells[1], r / (g.cells[0] * g.cells[1])}};
    vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> cursor;
    htg->InitializeNonOrientedGeometryCursor(cursor, tree.rootIndex);
    double bounds[6];
    cursor->GetBounds(bounds);
    for (int a = 0; a < 3; ++a)
    {
      const auto& x = g.coordinates[a];
      const double low = x[ijk[a]];
      const double high = g.points[a] > 1 ? x[ijk[a] + 1] : low;
      if (bounds[2 * a] != low || bounds[2 * a + 1] != high)
      {
        fail("tree " + std::to_string(t) + " (root " + std::to_string(r) +
             "): its root cell is not where the root index says");
      }
    }
    shape.totalCells += tree.nodes();
  }
  for (std::size_t r = 0; r < g.rootCells; ++r)
  {
    if (!described[r] && htg->GetTree(static_cast<vtkIdType>(r)) != nullptr)
    {
      fail("root cell " + std::to_string(r) + " has a tree but none was described");
    }
  }
  return shape;
}

void checkMaskAndGhosts(const Generated& g, vtkHyperTreeGrid* htg, const Shape& shape)
{
  vtkBitArray* mask = htg->HasMask() ? htg->GetMask() : nullptr;
  if (mask && mask->GetNumberOfTuples() < static_cast<vtkIdType>(shape.totalCells))
  {
    fail("the mask has fewer values than the grid has cells");
  }
  auto* ghosts = vtkUnsignedCharArray::SafeDownCast(
      htg->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()));
  if (ghosts && ghosts->GetNumberOfTuples() != static_cast<vtkIdType>(shape.totalCells))
  {
    fail("the ghost array does not have one value per cell");
  }
  for (std::size_t t = 0; t < g.trees.size(); ++t)
  {
    const Tree& tree = g.trees[t];
    for (std::size_t n = 0; n < tree.nodes(); ++n)
    {
      const auto cell = static_cast<vtkIdType>(shape.firstCell[t] + n);
      const bool hidden = tree.isMasked(n) || tree.isAbsent(n);
      if ((mask ? mask->GetValue(cell) != 0 : false) != hidden)
      {
        fail(where(t, n) + (hidden ? ": masked or absent but not masked in the grid"
                                   : ": masked in the grid but not in the description"));
      }
      if (tree.isAbsent(n) &&
          (!ghosts || ghosts->GetValue(cell) != vtkDataSetAttributes::DUPLICATECELL))
      {
        fail(where(t, n) + ": absent but not marked DUPLICATECELL");
      }
      if (!tree.isAbsent(n) && ghosts && ghosts->GetValue(cell) != 0)
      {
        fail(where(t, n) + ": present but marked as a ghost");
      }
    }
  }
}

/// Each node's storage slot (present nodes only).
std::vector<std::vector<std::size_t>> slotsOf(const Generated& g)
{
  std::vector<std::vector<std::size_t>> slots(g.trees.size());
  std::size_t next = 0;
  for (std::size_t t = 0; t < g.trees.size(); ++t)
  {
    const Tree& tree = g.trees[t];
    slots[t].resize(tree.nodes());
    for (std::size_t n = 0; n < tree.nodes(); ++n)
    {
      if (!tree.isAbsent(n))
      {
        slots[t][n] = tree.slots.empty() ? next++ : static_cast<std::size_t>(tree.slots[n]);
      }
    }
  }
  return slots;
}

/// What every cell of a field should read, from the description alone.
template <typename T>
std::vector<Scalar> expectedValues(const Generated& g, const Shape& shape, std::size_t f)
{
  const Field& field = g.fields[f];
  const auto nc = static_cast<std::size_t>(field.components);
  const auto slots = slotsOf(g);
  std::vector<Scalar> expected(shape.totalCells * nc, absentScalar(field.type));
  // Leaves-only: leaf tuples are the present leaves in slot order.
  std::vector<std::pair<std::size_t, std::pair<std::size_t, std::size_t>>> leaves;
  for (std::size_t t = 0; t < g.trees.size(); ++t)
  {
    for (std::size_t n = 0; n < g.trees[t].nodes(); ++n)
    {
      if (!g.trees[t].isAbsent(n) && !g.trees[t].refined[n])
      {
        leaves.push_back({slots[t][n], {t, n}});
      }
    }
  }
  std::sort(leaves.begin(), leaves.end());
  std::vector<std::vector<std::size_t>> leafTuple(g.trees.size());
  for (std::size_t t = 0; t < g.trees.size(); ++t)
  {
    leafTuple[t].resize(g.trees[t].nodes());
  }
  for (std::size_t i = 0; i < leaves.size(); ++i)
  {
    leafTuple[leaves[i].second.first][leaves[i].second.second] = i;
  }
  for (std::size_t t = 0; t < g.trees.size(); ++t)
  {
    const Tree& tree = g.trees[t];
    std::vector<T> value(tree.nodes() * nc, std::numeric_limits<T>::quiet_NaN());
    // Children of the k-th refined node (breadth-first) start at node 1 + k * children.
    std::vector<std::size_t> firstChild(tree.nodes(), 0);
    std::size_t refinedSoFar = 0;
    for (std::size_t n = 0; n < tree.nodes(); ++n)
    {
      if (tree.refined[n])
      {
        firstChild[n] = 1 + refinedSoFar++ * g.children;
      }
    }
    for (std::size_t n = tree.nodes(); n-- > 0;)
    {
      if (tree.isAbsent(n))
      {
        continue;
      }
      for (std::size_t c = 0; c < nc; ++c)
      {
        T v;
        if (!field.leavesOnly)
        {
          v = storedValue<T>(field, f, slots[t][n], static_cast<int>(c));
        }
        else if (!tree.refined[n])
        {
          v = storedValue<T>(field, f, leafTuple[t][n], static_cast<int>(c));
        }
        else
        {
          // The mean of the present children (in double, in child order), unmasked
          // ones first; if every present child is masked, all of them.
          double sum = 0;
          std::size_t used = 0;
          for (int pass = 0; pass < 2 && used == 0; ++pass)
          {
            for (std::size_t k = 0; k < g.children; ++k)
            {
              const std::size_t child = firstChild[n] + k;
              if (tree.isAbsent(child) || (pass == 0 && tree.isMasked(child)))
              {
                continue;
              }
              sum += static_cast<double>(value[child * nc + c]);
              ++used;
            }
          }
          v = used == 0 ? std::numeric_limits<T>::quiet_NaN()
                        : static_cast<T>(sum / static_cast<double>(used));
        }
        value[n * nc + c] = v;
        expected[(shape.firstCell[t] + n) * nc + c] = scalarOf(v);
      }
    }
  }
  return expected;
}

Scalar actualValue(vtkDataArray* array, vtkIdType index, bool integer)
{
  const vtkVariant v = array->GetVariantValue(index);
  Scalar s;
  s.integer = integer;
  if (integer)
  {
    s.whole = v.ToLongLong();
  }
  else
  {
    s.real = v.ToDouble();
  }
  return s;
}

int vtkTypeOf(ValueType type)
{
  switch (type)
  {
  case ValueType::Float32:
    return VTK_FLOAT;
  case ValueType::Float64:
    return VTK_DOUBLE;
  case ValueType::Int32:
    return VTK_INT;
  case ValueType::Int64:
    break;
  }
  return VTK_LONG_LONG;
}

void checkField(const Generated& g, const Shape& shape, std::size_t f, vtkDataArray* array)
{
  const Field& field = g.fields[f];
  const auto nc = static_cast<std::size_t>(field.components);
  if (array->GetNumberOfTuples() != static_cast<vtkIdType>(shape.totalCells) ||
      array->GetNumberOfComponents() != field.components)
  {
    fail("field " + field.name + ": not one tuple of " + std::to_string(nc) + " per cell");
  }
  if (array->GetDataType() != vtkTypeOf(field.type))
  {
    fail("field " + field.name + ": VTK type " + std::to_string(array->GetDataType()));
  }
  std::vector<Scalar> expected;
  switch (field.type)
  {
  case ValueType::Float32:
    expected = expectedValues<float>(g, shape, f);
    break;
  case ValueType::Float64:
    expected = expectedValues<double>(g, shape, f);
    break;
  case ValueType::Int32:
    expected = expectedValues<std::int32_t>(g, shape, f);
    break;
  case ValueType::Int64:
    expected = expectedValues<std::int64_t>(g, shape, f);
    break;
  }
  // The array itself, and a copy made the way filters copy arrays (NewInstance + DeepCopy).
  vtkSmartPointer<vtkDataArray> copy = vtkSmartPointer<vtkDataArray>::Take(array->NewInstance());
  copy->DeepCopy(array);
  // VTK copies plain AoS arrays value by value in their own type (its dispatch
  // lists hold no SoA arrays in ParaView 5.11's build).
  const bool dispatched = array->GetArrayType() == vtkAbstractArray::AoSDataArrayTemplate;
  for (vtkDataArray* read : {array, copy.GetPointer()})
  {
    for (std::size_t i = 0; i < expected.size(); ++i)
    {
      const Scalar actual = actualValue(read, static_cast<vtkIdType>(i), isInteger(field.type));
      Scalar wanted = expected[i];
      if (read != array && field.type == ValueType::Int64 && !dispatched)
      {
        // VTK 9.2 copies arrays of types outside its dispatch lists (Canopy's
        // strided, indirect and slot-mapped arrays) through double: 64-bit
        // integers come out rounded to double (docs/api.md).
        wanted.whole = static_cast<long long>(static_cast<double>(wanted.whole));
      }
      if (!(actual == wanted))
      {
        fail("field " + field.name + " (" + array->GetClassName() +
             (read == array ? "" : ", deep copy") + "): cell " + std::to_string(i / nc) +
             " component " + std::to_string(i % nc) + " reads " + actual.str() + ", expected " +
             wanted.str());
      }
    }
  }
}

void checkGrid(const Generated& g, vtkHyperTreeGrid* htg)
{
  const Shape shape = checkTrees(g, htg);
  checkMaskAndGhosts(g, htg, shape);
  // Root coordinates are borrowed, not copied.
  vtkDataArray* axes[3] = {htg->GetXCoordinates(), htg->GetYCoordinates(), htg->GetZCoordinates()};
  for (int a = 0; a < 3; ++a)
  {
    auto* axis = vtkDoubleArray::SafeDownCast(axes[a]);
    if (!axis || axis->GetNumberOfTuples() != static_cast<vtkIdType>(g.points[a]) ||
        axis->GetPointer(0) != g.coordinates[a].data())
    {
      fail("axis " + std::to_string(a) + ": the coordinates are not the simulation's");
    }
  }
  // Exactly the requested fields, besides the ghost array.
  std::set<std::string> wanted;
  for (const Field& field : g.fields)
  {
    if (g.requestMode == 0 ||
        std::find(g.requested.begin(), g.requested.end(), field.name) != g.requested.end())
    {
      wanted.insert(field.name);
    }
  }
  vtkCellData* cellData = htg->GetCellData();
  std::set<std::string> present;
  for (int i = 0; i < cellData->GetNumberOfArrays(); ++i)
  {
    const char* name = cellData->GetArrayName(i);
    if (name && std::string(name) != vtkDataSetAttributes::GhostArrayName())
    {
      present.insert(name);
    }
  }
  if (present != wanted)
  {
    fail("the grid's fields are not the requested ones");
  }
  for (std::size_t f = 0; f < g.fields.size(); ++f)
  {
    if (wanted.count(g.fields[f].name))
    {
      checkField(g, shape, f, cellData->GetArray(g.fields[f].name.c_str()));
    }
  }
}

void checkNeverWritten(const Generated& g)
{
  for (const Field& field : g.fields)
  {
    std::size_t i = 0;
    for (const auto& part : field.parts)
    {
      if (part != field.snapshot[i++])
      {
        fail("field " + field.name + ": the simulation's memory was written");
      }
    }
    if (field.block != field.snapshot[i])
    {
      fail("field " + field.name + ": the simulation's memory was written");
    }
  }
}

std::string joined(const std::vector<std::string>& lines, const char* separator = "\n  ")
{
  std::string out;
  for (const auto& line : lines)
  {
    out += (out.empty() && separator[0] != '\n' ? "" : separator) + line;
  }
  return out;
}

/// CANOPY_FUZZ_DESCRIBE=1: one line per input on stderr saying what it decoded to
/// and whether it was built (tests/fuzz/make_corpus.py --check reads it).
void describe(const Generated& g, const char* outcome)
{
  static const bool enabled = std::getenv("CANOPY_FUZZ_DESCRIBE") != nullptr;
  if (!enabled)
  {
    return;
  }
  std::size_t nodes = 0;
  for (const Tree& tree : g.trees)
  {
    nodes += tree.nodes();
  }
  std::fprintf(stderr,
               "canopy fuzz input: %dD, branch factor %d, maxLevels %d, %zu tree(s), %zu "
               "node(s), %zu field(s), defects: %s; %s\n",
               g.forest.dimension, g.forest.branchFactor, g.forest.maxLevels, g.trees.size(), nodes,
               g.fields.size(), g.defects.empty() ? "none" : joined(g.defects, ", ").c_str(),
               outcome);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const Generated g = generate(data, size);
  const canopy::FieldRequest request = g.requestMode == 0 ? canopy::FieldRequest::all()
                                       : g.requestMode == 1
                                           ? canopy::FieldRequest::none()
                                           : canopy::FieldRequest::only(g.requested);
  vtkSmartPointer<vtkHyperTreeGrid> htg;
  try
  {
    htg = canopy::buildHyperTreeGrid(g.forest, request);
  }
  catch (const canopy::InvalidForest& invalid)
  {
    if (g.defects.empty())
    {
      fail(std::string("a valid description was refused:\n") + invalid.what());
    }
    if (invalid.problems().empty())
    {
      fail("InvalidForest without a problem");
    }
    checkNeverWritten(g);
    describe(g, "refused");
    return 0;
  }
  if (!g.defects.empty())
  {
    fail("an invalid description was built; its defects:" + joined(g.defects));
  }
  checkGrid(g, htg);
  htg = nullptr;
  checkNeverWritten(g);
  describe(g, "built");
  return 0;
}
