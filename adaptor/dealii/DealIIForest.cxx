#include <canopy/DealIIForest.h>

// Internal to Canopy (adaptor/common, not installed): validateForest's problem list.
#include "ProblemList.h"

#include <deal.II/base/index_set.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/fully_distributed_tria.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/fe_values.h>

#include <boost/signals2/connection.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>

namespace canopy
{
namespace
{

/// Every message names the deal.II bridge: the problem is in the triangulation,
/// not in a description the simulation wrote.
constexpr const char* problemPrefix = "deal.II triangulation: ";

/// At most this many cells named per kind of problem; the rest are counted.
constexpr std::size_t namedProblems = 5;

/// Counts one kind of problem, names the first few, and says how many more.
class ProblemKind
{
public:
  explicit ProblemKind(std::string more) : More(std::move(more)) {}
  template <typename... Parts>
  void add(ProblemList& problems, const Parts&... parts)
  {
    if (this->Count++ < namedProblems)
    {
      problems.add(parts...);
    }
  }
  void finish(ProblemList& problems) const
  {
    if (this->Count > namedProblems)
    {
      problems.add("... and ", this->Count - namedProblems, " more ", this->More);
    }
  }

private:
  std::string More;
  std::size_t Count = 0;
};

template <int dim>
using Box = std::array<std::array<double, 3>, 2>; // lower, upper corner

/// Corner v of a box in deal.II's (and Canopy's) lexicographic order: bit a of v
/// says lower (0) or upper (1) along axis a.
template <int dim>
double cornerCoordinate(const Box<dim>& box, unsigned int v, int a)
{
  return ((v >> a) & 1U) ? box[1][a] : box[0][a];
}

/// Whether the cell's vertices are exactly (to rounding) the corners of `box`.
template <int dim, typename Cell>
bool verticesAreBox(const Cell& cell, const Box<dim>& box)
{
  for (unsigned int v = 0; v < dealii::GeometryInfo<dim>::vertices_per_cell; ++v)
  {
    const dealii::Point<dim> p = cell->vertex(v);
    for (int a = 0; a < dim; ++a)
    {
      const double expected = cornerCoordinate<dim>(box, v, a);
      const double size = box[1][a] - box[0][a];
      if (std::abs(p[a] - expected) > 1e-10 * size)
      {
        return false;
      }
    }
  }
  return true;
}

/// The root grid: the lattice of the coarse cells' corners, each coarse cell's root.
struct CoarseLattice
{
  std::array<std::vector<double>, 3> axes;
  std::vector<std::int64_t> rootOfCoarseCell; ///< by level-0 cell index
  std::vector<std::array<std::array<double, 3>, 2>> boxOfCoarseCell;
};

template <int dim>
CoarseLattice latticeOf(const dealii::Triangulation<dim>& tria, ProblemList& problems)
{
  CoarseLattice lattice;
  const std::size_t coarse = tria.n_cells(0);
  lattice.boxOfCoarseCell.resize(coarse);
  lattice.rootOfCoarseCell.assign(coarse, -1);
  ProblemKind notBoxes("coarse cells that are not axis-aligned boxes");
  constexpr unsigned int last = dealii::GeometryInfo<dim>::vertices_per_cell - 1;
  for (const auto& cell : tria.cell_iterators_on_level(0))
  {
    const auto c = static_cast<std::size_t>(cell->index());
    if (cell->reference_cell() != dealii::ReferenceCells::get_hypercube<dim>())
    {
      notBoxes.add(problems, "coarse cell ", c, " is a ", cell->reference_cell().to_string(),
                   ", not a ", dim == 2 ? "quadrilateral" : "hexahedron");
      continue;
    }
    Box<dim> box{};
    for (int a = 0; a < dim; ++a)
    {
      box[0][a] = cell->vertex(0)[a];
      box[1][a] = cell->vertex(last)[a];
    }
    bool ok = true;
    for (int a = 0; a < dim; ++a)
    {
      ok = ok && box[1][a] > box[0][a];
    }
    if (!ok || !verticesAreBox<dim>(cell, box))
    {
      notBoxes.add(problems, "coarse cell ", c,
                   " is not an axis-aligned box with its vertices in lexicographic order "
                   "(rotated, mirrored, skewed or curved coarse cells are not supported)");
      continue;
    }
    lattice.boxOfCoarseCell[c] = box;
  }
  notBoxes.finish(problems);
  problems.raiseIfAny<InvalidForest>();

  for (int a = 0; a < 3; ++a)
  {
    auto& axis = lattice.axes[static_cast<std::size_t>(a)];
    if (a >= dim)
    {
      axis.push_back(0.0); // a 2D mesh lies in the z = 0 plane
      continue;
    }
    for (const auto& box : lattice.boxOfCoarseCell)
    {
      axis.push_back(box[0][a]);
      axis.push_back(box[1][a]);
    }
    std::sort(axis.begin(), axis.end());
    axis.erase(std::unique(axis.begin(), axis.end()), axis.end());
  }
  std::array<std::size_t, 3> cells{{1, 1, 1}};
  for (int a = 0; a < dim; ++a)
  {
    cells[a] = lattice.axes[a].size() - 1;
  }
  const std::size_t latticeCells = cells[0] * cells[1] * cells[2];
  std::vector<std::int64_t> coarseAtRoot(latticeCells, -1);
  ProblemKind notLattice("coarse cells off the lattice");
  for (std::size_t c = 0; c < coarse; ++c)
  {
    const auto& box = lattice.boxOfCoarseCell[c];
    std::array<std::size_t, 3> ijk{{0, 0, 0}};
    bool oneCell = true;
    for (int a = 0; a < dim; ++a)
    {
      const auto& axis = lattice.axes[a];
      ijk[a] = static_cast<std::size_t>(std::lower_bound(axis.begin(), axis.end(), box[0][a]) -
                                        axis.begin());
      oneCell = oneCell && ijk[a] + 1 < axis.size() && axis[ijk[a] + 1] == box[1][a];
    }
    if (!oneCell)
    {
      notLattice.add(problems, "coarse cell ", c,
                     " spans several cells of the lattice of coarse-cell corners (the coarse "
                     "mesh is not a rectilinear lattice of boxes)");
      continue;
    }
    const std::size_t root = ijk[0] + cells[0] * (ijk[1] + cells[1] * ijk[2]);
    if (coarseAtRoot[root] >= 0)
    {
      notLattice.add(problems, "coarse cells ", coarseAtRoot[root], " and ", c,
                     " occupy the same lattice cell");
      continue;
    }
    coarseAtRoot[root] = static_cast<std::int64_t>(c);
    lattice.rootOfCoarseCell[c] = static_cast<std::int64_t>(root);
  }
  notLattice.finish(problems);
  if (problems.empty() && coarse != latticeCells)
  {
    problems.add("the ", coarse, " coarse cells do not tile the ", latticeCells,
                 "-cell lattice of their corners (Canopy needs a box of boxes, as "
                 "subdivided_hyper_rectangle makes)");
  }
  problems.raiseIfAny<InvalidForest>();
  return lattice;
}

/// One coarse cell described breadth-first down to this rank's cells.
struct DescribedTree
{
  std::int64_t root = 0;
  std::vector<std::uint8_t> refinement;
  std::vector<std::uint8_t> absent;
  std::vector<std::int64_t> slots;
  bool split = false;
};

} // namespace

template <int dim>
struct DealIIForest<dim>::State
{
  const dealii::Triangulation<dim>* tria = nullptr;
  const dealii::parallel::distributed::Triangulation<dim>* distributed = nullptr;
  long p4estRevision = 0;
  std::size_t activeCells = 0;
  /// Set by the triangulation's signals when the mesh changes or goes away.
  bool changed = false;
  std::vector<boost::signals2::scoped_connection> connections;

  CoarseLattice lattice;
  std::vector<DescribedTree> trees;
  /// The locally owned active cells in slot order (= active_cell_index order):
  /// (level, index) and their active and global active indices.
  std::vector<std::pair<int, int>> ownedCells;
  std::vector<std::uint32_t> activeIndex;
  /// Indirect fields' address tables, and cell averages: Canopy's own memory.
  std::deque<std::vector<const void*>> addressTables;
  std::deque<std::vector<double>> averages;
  ForestDescription description;
  /// The per-level tables the constructor walked the mesh with (freed since).
  std::size_t scratchBytes = 0;

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
    problems.raiseIfAny<InvalidForest>();
    description.fields.push_back(std::move(field));
  }

  bool stale() const
  {
    if (changed || tria->n_active_cells() != activeCells)
    {
      return true;
    }
    return distributed && distributed->get_p4est()->revision != p4estRevision;
  }
};

template <int dim>
DealIIForest<dim>::DealIIForest(const dealii::Triangulation<dim>& triangulation)
    : Impl(std::make_unique<State>())
{
  ProblemList problems(problemPrefix);
  State& s = *Impl;
  s.tria = &triangulation;
  if (dynamic_cast<const dealii::parallel::fullydistributed::Triangulation<dim>*>(&triangulation))
  {
    problems.add("a parallel::fullydistributed::Triangulation keeps only part of the coarse "
                 "mesh on each rank; use parallel::distributed::Triangulation");
    problems.raise<InvalidForest>();
  }
  if (triangulation.n_levels() == 0 || triangulation.n_cells(0) == 0)
  {
    problems.add("it is empty (no coarse cells)");
    problems.raise<InvalidForest>();
  }
  s.distributed =
      dynamic_cast<const dealii::parallel::distributed::Triangulation<dim>*>(&triangulation);
  s.p4estRevision = s.distributed ? s.distributed->get_p4est()->revision : 0;
  s.activeCells = triangulation.n_active_cells();
  s.lattice = latticeOf<dim>(triangulation, problems);

  // Which cells have a locally owned active cell at or below them, level by level
  // from the finest up: the others are another rank's (absent) or not described.
  const unsigned int levels = triangulation.n_levels();
  // A leaf's slot, by active_cell_index (-1: not locally owned).
  std::vector<std::int32_t> slotOfActive(triangulation.n_active_cells(), -1);
  std::vector<std::vector<std::uint8_t>> ownedBelow(levels);
  for (unsigned int l = 0; l < levels; ++l)
  {
    ownedBelow[l].assign(triangulation.n_raw_cells(l), 0);
  }
  for (const auto& cell : triangulation.active_cell_iterators())
  {
    if (cell->is_locally_owned())
    {
      slotOfActive[cell->active_cell_index()] = static_cast<std::int32_t>(s.ownedCells.size());
      s.ownedCells.emplace_back(cell->level(), cell->index());
      s.activeIndex.push_back(cell->active_cell_index());
      ownedBelow[cell->level()][cell->index()] = 1;
    }
  }
  for (unsigned int l = levels; l-- > 1;)
  {
    for (const auto& cell : triangulation.cell_iterators_on_level(l))
    {
      if (ownedBelow[l][cell->index()])
      {
        ownedBelow[l - 1][cell->parent()->index()] = 1;
      }
    }
  }

  // Each coarse cell with an owned cell, breadth-first. Leaves take the slots of
  // their cells (active_cell_index order); refined nodes take the slots after all
  // leaves, so leaves-only fields are in active_cell_index order.
  constexpr unsigned int children = dealii::GeometryInfo<dim>::max_children_per_cell;
  ProblemKind anisotropic("anisotropically refined cells");
  ProblemKind moved("cells whose vertices are not the corners of their box");
  std::int64_t nextRefinedSlot = static_cast<std::int64_t>(s.ownedCells.size());
  int maxLevel = 0;
  struct Node
  {
    typename dealii::Triangulation<dim>::cell_iterator cell;
    Box<dim> box;
  };
  std::vector<Node> level;
  std::vector<Node> next;
  for (const auto& coarse : triangulation.cell_iterators_on_level(0))
  {
    if (!ownedBelow[0][coarse->index()])
    {
      continue;
    }
    DescribedTree tree;
    tree.root = s.lattice.rootOfCoarseCell[static_cast<std::size_t>(coarse->index())];
    level.assign(1, Node{coarse, s.lattice.boxOfCoarseCell[coarse->index()]});
    while (!level.empty())
    {
      next.clear();
      for (const Node& node : level)
      {
        const auto& cell = node.cell;
        const bool owned = ownedBelow[cell->level()][cell->index()] != 0;
        const bool refined = owned && cell->has_children();
        tree.refinement.push_back(refined);
        tree.absent.push_back(!owned);
        tree.split = tree.split || !owned;
        if (!owned)
        {
          tree.slots.push_back(-1);
          continue;
        }
        if (!refined)
        {
          tree.slots.push_back(slotOfActive[cell->active_cell_index()]);
          maxLevel = std::max(maxLevel, cell->level());
          if (!verticesAreBox<dim>(cell, node.box))
          {
            moved.add(problems, "cell ", cell->level(), ".", cell->index(), " (coarse cell ",
                      coarse->index(),
                      "): its vertices are not the corners of the box isotropic refinement "
                      "gives it (a manifold or a vertex move curved the mesh)");
          }
          continue;
        }
        tree.slots.push_back(nextRefinedSlot++);
        if (cell->refinement_case() != dealii::RefinementCase<dim>::isotropic_refinement ||
            cell->n_children() != children)
        {
          anisotropic.add(problems, "cell ", cell->level(), ".", cell->index(), " (coarse cell ",
                          coarse->index(),
                          ") is refined anisotropically (Canopy needs isotropic refinement)");
          continue;
        }
        for (unsigned int c = 0; c < children; ++c)
        {
          Box<dim> box = node.box;
          for (int a = 0; a < dim; ++a)
          {
            const double middle = 0.5 * (node.box[0][a] + node.box[1][a]);
            ((c >> a) & 1U ? box[0][a] : box[1][a]) = middle;
          }
          next.push_back(Node{cell->child(c), box});
        }
      }
      level.swap(next);
    }
    s.trees.push_back(std::move(tree));
  }
  for (unsigned int l = 0; l < levels; ++l)
  {
    s.scratchBytes += ownedBelow[l].size();
  }
  s.scratchBytes += slotOfActive.size() * sizeof(std::int32_t);
  s.scratchBytes += (level.capacity() + next.capacity()) * sizeof(Node);
  anisotropic.finish(problems);
  moved.finish(problems);
  problems.raiseIfAny<InvalidForest>();

  ForestDescription& d = s.description;
  d.dimension = dim;
  d.branchFactor = 2;
  d.maxLevels = maxLevel + 1;
  // Every coarse cell is a tree somewhere: those not listed hold other ranks' cells.
  d.missingTreesAreElsewhere = true;
  // p4est bumps its revision at every mesh change deal.II makes through it
  // (refinement, coarsening, repartition): the same forest at the same revision
  // has the same trees, and Canopy's builder need not read them again. A serial
  // triangulation has no such counter: 0, and the builder compares each tree's
  // bytes instead (it keeps the unchanged ones either way).
  if (s.distributed)
  {
    const std::uint64_t revision =
        static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(s.distributed->get_p4est())) *
            1000003u +
        static_cast<std::uint64_t>(s.p4estRevision) * 7919u +
        static_cast<std::uint64_t>(s.activeCells);
    d.revision = revision != 0 ? revision : 1;
  }
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
    td.absent = tree.split ? tree.absent.data() : nullptr;
    d.trees.push_back(td);
  }

  // Any change to the mesh (refinement, repartition, clear, destruction) makes
  // this description stale; description() then refuses it.
  State* state = &s;
  const auto mark = [state]() { state->changed = true; };
  s.connections.emplace_back(triangulation.signals.any_change.connect(mark));
  s.connections.emplace_back(triangulation.signals.clear.connect(mark));
  s.connections.emplace_back(triangulation.signals.post_distributed_repartition.connect(mark));
}

template <int dim>
DealIIForest<dim>::~DealIIForest() = default;
template <int dim>
DealIIForest<dim>::DealIIForest(DealIIForest&&) noexcept = default;
template <int dim>
DealIIForest<dim>& DealIIForest<dim>::operator=(DealIIForest&&) noexcept = default;

template <int dim>
void DealIIForest<dim>::addLocalPart(std::string name, ValueType type, const void* localValues,
                                     std::size_t valueBytes,
                                     const std::vector<std::uint32_t>& localIndexOfCell)
{
  State& s = *Impl;
  FieldDescription field;
  field.name = std::move(name);
  field.type = type;
  field.components = 1;
  field.centering = Centering::LeavesOnly;
  field.numberOfTuples = s.ownedCells.size();
  // Owned cells at local entries 0, 1, 2, ... in order (a serial mesh's vector, a
  // distributed vector's locally owned part): the array itself. Otherwise (ghost
  // and artificial cells' entries in between): one address per cell, into it.
  bool inOrder = true;
  for (std::size_t k = 0; k < localIndexOfCell.size() && inOrder; ++k)
  {
    inOrder = localIndexOfCell[k] == k;
  }
  if (inOrder)
  {
    field.layout = Layout::AoS;
    field.data = localValues;
    s.addField(std::move(field));
    return;
  }
  std::vector<const void*> addresses(localIndexOfCell.size());
  const auto* bytes = static_cast<const unsigned char*>(localValues);
  for (std::size_t k = 0; k < addresses.size(); ++k)
  {
    addresses[k] = bytes + static_cast<std::size_t>(localIndexOfCell[k]) * valueBytes;
  }
  field.layout = Layout::Indirect;
  s.addressTables.push_back(std::move(addresses));
  field.tupleAddresses = s.addressTables.back().data();
  try
  {
    s.addField(std::move(field));
  }
  catch (...)
  {
    s.addressTables.pop_back();
    throw;
  }
}

template <int dim>
std::vector<std::uint32_t> DealIIForest<dim>::localIndicesOf(
    const dealii::IndexSet& owned,
    const std::function<std::int64_t(dealii::types::global_dof_index)>& localOf,
    const std::string& name) const
{
  const State& s = *Impl;
  std::vector<std::uint32_t> local(s.ownedCells.size());
  ProblemList problems(problemPrefix);
  ProblemKind outside("cells outside the vector's locally owned range");
  for (std::size_t k = 0; k < local.size(); ++k)
  {
    const typename dealii::Triangulation<dim>::active_cell_iterator cell(
        s.tria, s.ownedCells[k].first, s.ownedCells[k].second);
    const auto global =
        static_cast<dealii::types::global_dof_index>(cell->global_active_cell_index());
    if (!owned.is_element(global))
    {
      outside.add(problems, "field '", name, "': locally owned cell ", s.ownedCells[k].first, ".",
                  s.ownedCells[k].second, " has global_active_cell_index ", global,
                  ", not in the vector's locally owned range (index the vector by "
                  "global_active_cell_index, e.g. with "
                  "global_active_cell_index_partitioner())");
      continue;
    }
    local[k] = static_cast<std::uint32_t>(localOf(global));
  }
  outside.finish(problems);
  problems.raiseIfAny<InvalidForest>();
  return local;
}

template <int dim>
template <typename T>
void DealIIForest<dim>::addCellVector(std::string name, const dealii::Vector<T>& values)
{
  State& s = *Impl;
  if (values.size() != s.activeCells)
  {
    ProblemList problems(problemPrefix);
    problems.add("field '", name, "': the vector has ", values.size(),
                 " entries, the triangulation ", s.activeCells,
                 " active cells (a cell vector is indexed by active_cell_index)");
    problems.raise<InvalidForest>();
  }
  addLocalPart(std::move(name), valueTypeOf<T>(), values.begin(), sizeof(T), s.activeIndex);
}

template <int dim>
template <typename T>
void DealIIForest<dim>::addCellVector(std::string name,
                                      const dealii::LinearAlgebra::distributed::Vector<T>& values)
{
  const dealii::IndexSet owned = values.locally_owned_elements();
  const auto first = static_cast<std::int64_t>(values.get_partitioner()->local_range().first);
  const auto local = localIndicesOf(
      owned,
      [first](dealii::types::global_dof_index global)
      { return static_cast<std::int64_t>(global) - first; },
      name);
  addLocalPart(std::move(name), valueTypeOf<T>(), values.begin(), sizeof(T), local);
}

#ifdef DEAL_II_WITH_PETSC
template <int dim>
void DealIIForest<dim>::addCellVector(std::string name,
                                      const dealii::PETScWrappers::MPI::Vector& values)
{
  static_assert(sizeof(PetscScalar) == sizeof(double), "Canopy reads real PETSc vectors");
  const auto first = static_cast<std::int64_t>(values.local_range().first);
  const auto local = localIndicesOf(
      values.locally_owned_elements(),
      [first](dealii::types::global_dof_index global)
      { return static_cast<std::int64_t>(global) - first; },
      name);
  // The local part of a standard (VECMPI) vector is PETSc's own array: it stays
  // where it is between VecGetArrayRead and later reads, as every zero-copy
  // PETSc consumer relies on.
  const PetscScalar* array = nullptr;
  VecGetArrayRead(static_cast<const Vec&>(values), &array);
  const PetscScalar* localValues = array;
  VecRestoreArrayRead(static_cast<const Vec&>(values), &array);
  addLocalPart(std::move(name), ValueType::Float64, localValues, sizeof(double), local);
}
#endif

#ifdef DEAL_II_WITH_TRILINOS
template <int dim>
void DealIIForest<dim>::addCellVector(std::string name,
                                      const dealii::TrilinosWrappers::MPI::Vector& values)
{
  // Epetra's map gives each entry's place in the local array, ghosted vectors included
  // (whose owned entries need not come first).
  const auto& map = values.trilinos_vector().Map();
  const auto local = localIndicesOf(
      values.locally_owned_elements(),
      [&map](dealii::types::global_dof_index global)
      {
        return static_cast<std::int64_t>(
            map.LID(static_cast<dealii::TrilinosWrappers::types::int_type>(global)));
      },
      name);
  addLocalPart(std::move(name), ValueType::Float64, values.begin(), sizeof(double), local);
}
#endif

template <int dim>
template <typename VectorType>
void DealIIForest<dim>::addCellAverages(std::string name, const dealii::DoFHandler<dim>& dofs,
                                        const VectorType& solution)
{
  using Number = typename VectorType::value_type;
  State& s = *Impl;
  ProblemList problems(problemPrefix);
  if (&dofs.get_triangulation() != s.tria)
  {
    problems.add("field '", name, "': the DoFHandler is not on the described triangulation");
    problems.raise<InvalidForest>();
  }
  if (dofs.has_hp_capabilities() && dofs.get_fe_collection().size() > 1)
  {
    problems.add("field '", name, "': hp DoFHandlers (several finite elements) are not supported");
  }
  if (dofs.n_dofs() == 0 || solution.size() != dofs.n_dofs())
  {
    problems.add("field '", name, "': the solution has ", solution.size(), " entries, the ",
                 "DoFHandler ", dofs.n_dofs(), " DoFs (distribute_dofs, then size the vector)");
  }
  if constexpr (!std::is_same_v<VectorType, dealii::Vector<Number>>)
  {
    if (dealii::Utilities::MPI::n_mpi_processes(s.tria->get_communicator()) > 1 &&
        !solution.has_ghost_elements())
    {
      problems.add("field '", name,
                   "': the solution has no ghost entries; pass the vector with the locally "
                   "relevant DoFs (as DataOut needs), after update_ghost_values()");
    }
  }
  problems.raiseIfAny<InvalidForest>();

  const dealii::FiniteElement<dim>& fe = dofs.get_fe();
  const unsigned int components = fe.n_components();
  const dealii::QGauss<dim> quadrature(fe.degree + 1);
  dealii::FEValues<dim> values(fe, quadrature, dealii::update_values | dealii::update_JxW_values);
  std::vector<dealii::Vector<Number>> atPoints(quadrature.size(),
                                               dealii::Vector<Number>(components));
  std::vector<double> averages(s.ownedCells.size() * components, 0.0);
  for (std::size_t k = 0; k < s.ownedCells.size(); ++k)
  {
    const typename dealii::DoFHandler<dim>::active_cell_iterator cell(
        s.tria, s.ownedCells[k].first, s.ownedCells[k].second, &dofs);
    values.reinit(cell);
    values.get_function_values(solution, atPoints);
    double volume = 0;
    double* average = averages.data() + k * components;
    for (unsigned int q = 0; q < quadrature.size(); ++q)
    {
      const double weight = values.JxW(q);
      volume += weight;
      for (unsigned int c = 0; c < components; ++c)
      {
        average[c] += weight * static_cast<double>(atPoints[q][c]);
      }
    }
    for (unsigned int c = 0; c < components; ++c)
    {
      average[c] /= volume;
    }
  }
  s.averages.push_back(std::move(averages));
  FieldDescription field =
      FieldDescription::aos(std::move(name), s.averages.back().data(), s.ownedCells.size(),
                            static_cast<int>(components), Centering::LeavesOnly);
  try
  {
    s.addField(std::move(field));
  }
  catch (...)
  {
    s.averages.pop_back();
    throw;
  }
}

template <int dim>
const ForestDescription& DealIIForest<dim>::description() const
{
  const State& s = *Impl;
  if (s.stale())
  {
    ProblemList problems(problemPrefix);
    problems.add("it changed since it was described (", s.activeCells, " active cells, now ",
                 s.changed ? std::string("changed or cleared")
                           : std::to_string(s.tria->n_active_cells()),
                 "): describe it again after refinement, coarsening or repartition");
    problems.raise<InvalidForest>();
  }
  return s.description;
}

template <int dim>
std::size_t DealIIForest<dim>::numberOfCells() const
{
  return Impl->ownedCells.size();
}

template <int dim>
std::size_t DealIIForest<dim>::numberOfLocalTrees() const
{
  return Impl->trees.size();
}

template <int dim>
std::size_t DealIIForest<dim>::memoryWritten() const
{
  const State& s = *Impl;
  std::size_t bytes = s.scratchBytes;
  for (const DescribedTree& tree : s.trees)
  {
    bytes += tree.refinement.size() + tree.absent.size() + tree.slots.size() * sizeof(std::int64_t);
  }
  bytes += s.ownedCells.size() * (sizeof(std::pair<int, int>) + sizeof(std::uint32_t));
  for (const auto& table : s.addressTables)
  {
    bytes += table.size() * sizeof(const void*);
  }
  for (const auto& values : s.averages)
  {
    bytes += values.size() * sizeof(double);
  }
  for (const auto& axis : s.lattice.axes)
  {
    bytes += axis.size() * sizeof(double);
  }
  bytes += s.lattice.rootOfCoarseCell.size() * sizeof(std::int64_t) +
           s.lattice.boxOfCoarseCell.size() * sizeof(s.lattice.boxOfCoarseCell[0]);
  return bytes + s.description.trees.size() * sizeof(TreeDescription) +
         s.description.fields.size() * sizeof(FieldDescription);
}

template class DealIIForest<2>;
template class DealIIForest<3>;

// The vector types the header promises (member templates are instantiated one by one).
#define CANOPY_DEALII_VECTORS(dim)                                                                 \
  template void DealIIForest<dim>::addCellVector(std::string, const dealii::Vector<double>&);      \
  template void DealIIForest<dim>::addCellVector(std::string, const dealii::Vector<float>&);       \
  template void DealIIForest<dim>::addCellVector(                                                  \
      std::string, const dealii::LinearAlgebra::distributed::Vector<double>&);                     \
  template void DealIIForest<dim>::addCellVector(                                                  \
      std::string, const dealii::LinearAlgebra::distributed::Vector<float>&);                      \
  template void DealIIForest<dim>::addCellAverages(std::string, const dealii::DoFHandler<dim>&,    \
                                                   const dealii::Vector<double>&);                 \
  template void DealIIForest<dim>::addCellAverages(std::string, const dealii::DoFHandler<dim>&,    \
                                                   const dealii::Vector<float>&);                  \
  template void DealIIForest<dim>::addCellAverages(                                                \
      std::string, const dealii::DoFHandler<dim>&,                                                 \
      const dealii::LinearAlgebra::distributed::Vector<double>&);                                  \
  template void DealIIForest<dim>::addCellAverages(                                                \
      std::string, const dealii::DoFHandler<dim>&,                                                 \
      const dealii::LinearAlgebra::distributed::Vector<float>&);
CANOPY_DEALII_VECTORS(2)
CANOPY_DEALII_VECTORS(3)
#undef CANOPY_DEALII_VECTORS

#ifdef DEAL_II_WITH_PETSC
template void DealIIForest<2>::addCellAverages(std::string, const dealii::DoFHandler<2>&,
                                               const dealii::PETScWrappers::MPI::Vector&);
template void DealIIForest<3>::addCellAverages(std::string, const dealii::DoFHandler<3>&,
                                               const dealii::PETScWrappers::MPI::Vector&);
#endif
#ifdef DEAL_II_WITH_TRILINOS
template void DealIIForest<2>::addCellAverages(std::string, const dealii::DoFHandler<2>&,
                                               const dealii::TrilinosWrappers::MPI::Vector&);
template void DealIIForest<3>::addCellAverages(std::string, const dealii::DoFHandler<3>&,
                                               const dealii::TrilinosWrappers::MPI::Vector&);
#endif

} // namespace canopy
