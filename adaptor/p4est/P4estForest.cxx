#include <canopy/P4estForest.h>

// Internal to Canopy (adaptor/common, not installed): validateForest's problem list.
#include "ProblemList.h"
#include <canopy/ForestValidation.h>

#include <p4est.h>
#include <p4est_connectivity.h>
#include <p8est.h>
#include <p8est_connectivity.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

namespace canopy
{
namespace
{

/// The parts of p4est's and p8est's APIs the description needs.
template <int D>
struct Api;

template <>
struct Api<2>
{
  using Forest = p4est_t;
  using Tree = p4est_tree_t;
  using Quadrant = p4est_quadrant_t;
  using Connectivity = p4est_connectivity_t;
  static constexpr int MaxLevel = P4EST_MAXLEVEL;
  static constexpr int Children = P4EST_CHILDREN;
  static const Tree* tree(const Forest* forest, p4est_topidx_t t)
  {
    return p4est_tree_array_index(forest->trees, t);
  }
  static const Quadrant* quadrant(const Tree* tree, std::size_t i)
  {
    return p4est_quadrant_array_index(const_cast<sc_array_t*>(&tree->quadrants), i);
  }
  static std::array<p4est_qcoord_t, 3> position(const Quadrant* q) { return {{q->x, q->y, 0}}; }
};

template <>
struct Api<3>
{
  using Forest = p8est_t;
  using Tree = p8est_tree_t;
  using Quadrant = p8est_quadrant_t;
  using Connectivity = p8est_connectivity_t;
  static constexpr int MaxLevel = P8EST_MAXLEVEL;
  static constexpr int Children = P8EST_CHILDREN;
  static const Tree* tree(const Forest* forest, p4est_topidx_t t)
  {
    return p8est_tree_array_index(forest->trees, t);
  }
  static const Quadrant* quadrant(const Tree* tree, std::size_t i)
  {
    return p8est_quadrant_array_index(const_cast<sc_array_t*>(&tree->quadrants), i);
  }
  static std::array<p4est_qcoord_t, 3> position(const Quadrant* q) { return {{q->x, q->y, q->z}}; }
};

/// Every message names the p4est bridge: the problem is in the p4est forest, not
/// in a description the simulation wrote.
constexpr const char* problemPrefix = "p4est forest: ";

/// The root grid of a brick-like connectivity, and each tree's root cell.
struct BrickLattice
{
  std::array<std::vector<double>, 3> axes;
  std::vector<std::int64_t> rootOfTree;
};

/// Each tree must be an unrotated axis-aligned box (corner c at lo + bit_a(c) (hi - lo)
/// in vertex coordinates), one cell of a rectilinear lattice, every cell one tree.
template <int D>
BrickLattice latticeOf(const typename Api<D>::Connectivity* connectivity, ProblemList& problems)
{
  BrickLattice lattice;
  const std::size_t trees = static_cast<std::size_t>(connectivity->num_trees);
  if (connectivity->num_vertices == 0 || connectivity->vertices == nullptr ||
      connectivity->tree_to_vertex == nullptr)
  {
    problems.add("the connectivity has no vertices, so its trees have no place in space; "
                 "Canopy needs a brick (p4est_connectivity_new_brick) or trees that are "
                 "axis-aligned boxes on a lattice of vertices");
    problems.raise<InvalidForest>();
  }
  constexpr int children = Api<D>::Children;
  using Corner = std::array<double, 3>;
  const auto corner = [&](std::size_t t, int c)
  {
    const auto v = static_cast<std::size_t>(connectivity->tree_to_vertex[t * children + c]);
    const double* p = connectivity->vertices + 3 * v;
    return Corner{{p[0], p[1], p[2]}};
  };
  std::vector<Corner> lows(trees);
  std::vector<Corner> highs(trees);
  std::size_t notBoxes = 0;
  for (std::size_t t = 0; t < trees; ++t)
  {
    const Corner lo = corner(t, 0);
    const Corner hi = corner(t, children - 1);
    bool box = true;
    for (int a = 0; a < D; ++a)
    {
      box = box && hi[a] > lo[a];
    }
    for (int c = 0; c < children && box; ++c)
    {
      const Corner p = corner(t, c);
      for (int a = 0; a < 3; ++a)
      {
        const double expected = a < D && ((c >> a) & 1) ? hi[a] : lo[a];
        const double tolerance = 1e-12 * (1 + std::abs(expected));
        box = box && std::abs(p[a] - expected) <= tolerance;
      }
    }
    if (!box && notBoxes++ < 5)
    {
      problems.add("tree ", t,
                   ": its corners are not an unrotated axis-aligned box in vertex coordinates "
                   "(rotated, mirrored or curved trees are not supported)");
    }
    lows[t] = lo;
    highs[t] = hi;
    if (D == 2 && lo[2] != lows[0][2])
    {
      problems.add("tree ", t, ": the 2D connectivity is not planar (vertex z ", lo[2],
                   " differs from ", lows[0][2], ")");
    }
  }
  if (notBoxes > 5)
  {
    problems.add("... and ", notBoxes - 5, " more trees that are not axis-aligned boxes");
  }
  problems.raiseIfAny<InvalidForest>();
  for (int a = 0; a < 3; ++a)
  {
    auto& axis = lattice.axes[static_cast<std::size_t>(a)];
    for (std::size_t t = 0; t < trees; ++t)
    {
      axis.push_back(lows[t][a]);
      if (a < D)
      {
        axis.push_back(highs[t][a]);
      }
    }
    std::sort(axis.begin(), axis.end());
    axis.erase(std::unique(axis.begin(), axis.end()), axis.end());
  }
  std::array<std::size_t, 3> cells{{1, 1, 1}};
  for (int a = 0; a < D; ++a)
  {
    cells[a] = lattice.axes[a].size() - 1;
  }
  const std::size_t latticeCells = cells[0] * cells[1] * cells[2];
  std::vector<std::int64_t> treeAtCell(latticeCells, -1);
  lattice.rootOfTree.resize(trees);
  for (std::size_t t = 0; t < trees; ++t)
  {
    std::array<std::size_t, 3> ijk{{0, 0, 0}};
    bool oneCell = true;
    for (int a = 0; a < D; ++a)
    {
      const auto& axis = lattice.axes[a];
      ijk[a] = static_cast<std::size_t>(std::lower_bound(axis.begin(), axis.end(), lows[t][a]) -
                                        axis.begin());
      oneCell = oneCell && ijk[a] + 1 < axis.size() && axis[ijk[a] + 1] == highs[t][a];
    }
    if (!oneCell)
    {
      problems.add("tree ", t, ": spans several cells of the lattice of tree corners");
      continue;
    }
    const std::size_t root = ijk[0] + cells[0] * (ijk[1] + cells[1] * ijk[2]);
    if (treeAtCell[root] >= 0)
    {
      problems.add("trees ", treeAtCell[root], " and ", t, " occupy the same lattice cell");
      continue;
    }
    treeAtCell[root] = static_cast<std::int64_t>(t);
    lattice.rootOfTree[t] = static_cast<std::int64_t>(root);
  }
  if (problems.empty() && trees != latticeCells)
  {
    problems.add("the ", trees, " trees do not tile the ", latticeCells,
                 "-cell lattice of their corners (Canopy needs a box of trees, as a brick is)");
  }
  problems.raiseIfAny<InvalidForest>();
  return lattice;
}

/// One local tree described breadth-first down to this rank's quadrants.
struct DescribedTree
{
  std::int64_t root = 0;
  std::vector<std::uint8_t> refinement;
  std::vector<std::uint8_t> absent;
  std::vector<std::int64_t> slots;
  std::size_t presentNodes = 0;
};

template <int D>
DescribedTree describeTree(const typename Api<D>::Tree* tree, std::int64_t root,
                           std::int64_t firstSlot, std::size_t treeIndex, ProblemList& problems)
{
  using A = Api<D>;
  constexpr int children = A::Children;
  const std::size_t count = tree->quadrants.elem_count;
  DescribedTree out;
  out.root = root;

  // One sweep over the local quadrants in Morton order emits the described
  // nodes in pre-order: each quadrant opens the nodes down to it, children
  // skipped on the way (no local quadrant inside) are absent leaves. A stack
  // holds the open nodes and the next child each expects. Cost: O(nodes).
  struct Open
  {
    int level;
    int nextChild;
  };
  std::vector<std::uint8_t> level; // per pre-order node
  std::vector<std::uint8_t> kind;  // 0 present leaf, 1 refined, 2 absent
  level.reserve(count + count / 2 + 8);
  kind.reserve(count + count / 2 + 8);
  std::vector<Open> stack;
  const auto emit = [&](int nodeLevel, std::uint8_t nodeKind)
  {
    level.push_back(static_cast<std::uint8_t>(nodeLevel));
    kind.push_back(nodeKind);
  };
  // Closes complete nodes; then the top is the deepest node still expecting children.
  const auto closeComplete = [&]()
  {
    while (!stack.empty() && stack.back().nextChild == children)
    {
      stack.pop_back();
      if (!stack.empty())
      {
        ++stack.back().nextChild;
      }
    }
  };
  for (std::size_t k = 0; k < count; ++k)
  {
    const typename A::Quadrant* q = A::quadrant(tree, k);
    const auto p = A::position(q);
    if (k == 0 && q->level == 0)
    {
      emit(0, 0); // the rank owns the whole tree as one quadrant
      break;
    }
    if (k == 0)
    {
      emit(0, 1);
      stack.push_back({0, 0});
    }
    if (stack.empty())
    {
      problems.add("tree ", treeIndex, ": quadrant ", k,
                   " lies outside the tree or quadrants overlap (not a valid linear quadtree)");
      problems.raise<InvalidForest>();
    }
    while (true)
    {
      Open& top = stack.back();
      const int shift = A::MaxLevel - (top.level + 1);
      int child = 0;
      for (int a = 0; a < D; ++a)
      {
        child |= ((p[a] >> shift) & 1) << a;
      }
      if (child < top.nextChild || q->level <= top.level)
      {
        problems.add("tree ", treeIndex, ": quadrant ", k,
                     " is not in Morton order or overlaps another (not a valid linear quadtree)");
        problems.raise<InvalidForest>();
      }
      for (; top.nextChild < child; ++top.nextChild)
      {
        emit(top.level + 1, 2); // no local quadrant in there: another rank's
      }
      if (q->level == top.level + 1)
      {
        emit(top.level + 1, 0);
        ++top.nextChild;
        closeComplete();
        break;
      }
      emit(top.level + 1, 1);
      stack.push_back({top.level + 1, 0});
    }
  }
  // What follows this rank's last quadrant is another rank's.
  while (!stack.empty())
  {
    for (Open& top = stack.back(); top.nextChild < children; ++top.nextChild)
    {
      emit(top.level + 1, 2);
    }
    closeComplete();
  }

  // Breadth-first order is pre-order sorted by level (stable: within a level both
  // go left to right), so a counting sort by level gives each node its place.
  // Slots number the present nodes in pre-order: leaves then come in local
  // quadrant order, which is how p4est codes store their fields.
  const std::size_t nodes = level.size();
  std::vector<std::size_t> levelStart(A::MaxLevel + 2, 0);
  for (std::uint8_t l : level)
  {
    ++levelStart[static_cast<std::size_t>(l) + 1];
  }
  for (std::size_t l = 1; l < levelStart.size(); ++l)
  {
    levelStart[l] += levelStart[l - 1];
  }
  out.refinement.assign(nodes, 0);
  out.absent.assign(nodes, 0);
  out.slots.assign(nodes, -1);
  std::int64_t slot = firstSlot;
  for (std::size_t d = 0; d < nodes; ++d)
  {
    const std::size_t b = levelStart[level[d]]++;
    out.refinement[b] = kind[d] == 1;
    out.absent[b] = kind[d] == 2;
    if (kind[d] != 2)
    {
      out.slots[b] = slot++;
    }
  }
  out.presentNodes = static_cast<std::size_t>(slot - firstSlot);
  return out;
}

} // namespace

template <int D>
struct BasicP4estForest<D>::State
{
  const typename Api<D>::Forest* forest = nullptr;
  long revision = 0;
  std::size_t quadrants = 0;
  BrickLattice lattice;
  std::vector<DescribedTree> trees;
  std::vector<std::vector<const void*>> userDataAddresses; ///< per user-data field
  ForestDescription description;

  void addField(FieldDescription field)
  {
    ProblemList problems(problemPrefix);
    if (field.name.empty())
    {
      problems.add("a field name is empty");
    }
    for (const auto& existing : description.fields)
    {
      if (existing.name == field.name)
      {
        problems.add("field '", field.name, "' is already described");
      }
    }
    if (field.components < 1)
    {
      problems.add("field '", field.name, "' has ", field.components, " components (at least 1)");
    }
    problems.raiseIfAny<InvalidForest>();
    description.fields.push_back(std::move(field));
  }
};

template <int D>
BasicP4estForest<D>::BasicP4estForest(const Forest* forest) : Impl(std::make_unique<State>())
{
  using A = Api<D>;
  ProblemList problems(problemPrefix);
  const typename A::Forest* p = forest;
  if (p == nullptr)
  {
    problems.add("the forest pointer is null");
    problems.raise<InvalidForest>();
  }
  if (p->connectivity == nullptr || p->trees == nullptr)
  {
    problems.add("the forest has no connectivity or no trees (destroyed?)");
    problems.raise<InvalidForest>();
  }
  State& s = *Impl;
  s.forest = p;
  s.revision = p->revision;
  s.quadrants = static_cast<std::size_t>(p->local_num_quadrants);
  s.lattice = latticeOf<D>(p->connectivity, problems);

  std::int64_t slots = 0;
  int maxLevel = 0;
  std::size_t described = 0;
  for (p4est_topidx_t t = p->first_local_tree; t >= 0 && t <= p->last_local_tree; ++t)
  {
    const typename A::Tree* tree = A::tree(p, t);
    if (tree->quadrants.elem_count == 0)
    {
      continue;
    }
    const auto index = static_cast<std::size_t>(t);
    s.trees.push_back(describeTree<D>(tree, s.lattice.rootOfTree[index], slots, index, problems));
    slots += static_cast<std::int64_t>(s.trees.back().presentNodes);
    maxLevel = std::max(maxLevel, static_cast<int>(tree->maxlevel));
    described += tree->quadrants.elem_count;
  }
  if (described != s.quadrants)
  {
    problems.add("the local trees hold ", described, " quadrants but local_num_quadrants is ",
                 s.quadrants);
    problems.raise<InvalidForest>();
  }

  ForestDescription& d = s.description;
  d.dimension = D;
  d.branchFactor = 2;
  d.maxLevels = maxLevel + 1;
  // A brick has a tree in every lattice cell: the ones not listed are other ranks'.
  d.missingTreesAreElsewhere = true;
  // p4est bumps its revision at every mesh change (refine, coarsen, balance,
  // partition): the same forest at the same revision has the same trees, and
  // Canopy's builder need not read them again. Nonzero, and another forest's
  // revisions are other numbers.
  const std::uint64_t revision =
      static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(p)) * 1000003u +
      static_cast<std::uint64_t>(p->revision);
  d.revision = revision != 0 ? revision : 1;
  const auto& axes = s.lattice.axes;
  d.rootGrid = {axes[0].data(), axes[1].data(), axes[2].data(),
                axes[0].size(), axes[1].size(), axes[2].size()};
  for (const DescribedTree& tree : s.trees)
  {
    TreeDescription td;
    td.rootIndex = tree.root;
    td.refinement = tree.refinement.data();
    td.numberOfNodes = tree.refinement.size();
    td.storageSlots = tree.slots.data();
    // Trees this rank has whole need no absent bytes.
    const bool split =
        std::any_of(tree.absent.begin(), tree.absent.end(), [](std::uint8_t a) { return a != 0; });
    td.absent = split ? tree.absent.data() : nullptr;
    d.trees.push_back(td);
  }
}

template <int D>
BasicP4estForest<D>::~BasicP4estForest() = default;
template <int D>
BasicP4estForest<D>::BasicP4estForest(BasicP4estForest&&) noexcept = default;
template <int D>
BasicP4estForest<D>& BasicP4estForest<D>::operator=(BasicP4estForest&&) noexcept = default;

template <int D>
void BasicP4estForest<D>::addQuadrantField(std::string name, ValueType type, const void* values,
                                           int components)
{
  FieldDescription field;
  field.name = std::move(name);
  field.type = type;
  field.components = components;
  field.layout = Layout::AoS;
  field.centering = Centering::LeavesOnly;
  field.data = values;
  field.numberOfTuples = Impl->quadrants;
  Impl->addField(std::move(field));
}

template <int D>
void BasicP4estForest<D>::addUserDataField(std::string name, ValueType type, std::size_t byteOffset,
                                           int components)
{
  using A = Api<D>;
  State& s = *Impl;
  const auto* p = s.forest;
  const std::size_t bytes = sizeOf(type) * static_cast<std::size_t>(std::max(components, 0));
  ProblemList problems(problemPrefix);
  if (p->data_size == 0)
  {
    problems.add("field '", name, "': the forest has no user data (data_size is 0)");
    problems.raise<InvalidForest>();
  }
  if (byteOffset + bytes > p->data_size)
  {
    problems.add("field '", name, "': ", bytes, " bytes at offset ", byteOffset,
                 " do not fit in the quadrants' ", p->data_size, " bytes of user data");
    problems.raise<InvalidForest>();
  }
  // One address per local quadrant, in local order: user_data lives in p4est's
  // memory pool, not at a fixed stride.
  std::vector<const void*> addresses;
  addresses.reserve(s.quadrants);
  for (p4est_topidx_t t = p->first_local_tree; t >= 0 && t <= p->last_local_tree; ++t)
  {
    const typename A::Tree* tree = A::tree(p, t);
    for (std::size_t i = 0; i < tree->quadrants.elem_count; ++i)
    {
      const auto* data = static_cast<const unsigned char*>(A::quadrant(tree, i)->p.user_data);
      addresses.push_back(data ? data + byteOffset : nullptr);
    }
  }
  FieldDescription field;
  field.name = std::move(name);
  field.type = type;
  field.components = components;
  field.layout = Layout::Indirect;
  field.centering = Centering::LeavesOnly;
  field.numberOfTuples = addresses.size();
  s.userDataAddresses.push_back(std::move(addresses));
  field.tupleAddresses = s.userDataAddresses.back().data();
  try
  {
    s.addField(std::move(field));
  }
  catch (...)
  {
    s.userDataAddresses.pop_back();
    throw;
  }
}

template <int D>
const ForestDescription& BasicP4estForest<D>::description() const
{
  const State& s = *Impl;
  const auto current = static_cast<std::size_t>(s.forest->local_num_quadrants);
  if (s.forest->revision != s.revision || current != s.quadrants)
  {
    ProblemList problems(problemPrefix);
    problems.add("it changed since it was described (revision ", s.revision, ", now ",
                 s.forest->revision, "; ", s.quadrants, " local quadrants, now ", current,
                 "): describe it again after refine, coarsen, balance or partition");
    problems.raise<InvalidForest>();
  }
  return s.description;
}

template <int D>
std::size_t BasicP4estForest<D>::numberOfQuadrants() const
{
  return Impl->quadrants;
}

template <int D>
std::size_t BasicP4estForest<D>::numberOfLocalTrees() const
{
  return Impl->trees.size();
}

template class BasicP4estForest<2>;
template class BasicP4estForest<3>;

} // namespace canopy
