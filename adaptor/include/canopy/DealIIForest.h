// Canopy::dealii: this rank's locally owned active cells of a deal.II
// triangulation described for Canopy, with cell vectors read in place.
//
//   canopy::DealIIForest<dim> described(triangulation);      // after refinement/repartition
//   described.addCellVector("error", estimated_error_per_cell); // indexed by active_cell_index()
//   described.addCellAverages("u", dof_handler, locally_relevant_solution);
//   insitu.execute(step, time, described.description());
//
// What it describes. A parallel::distributed::Triangulation<dim> (or a serial or
// parallel::shared Triangulation<dim>), dim 2 or 3, whose coarse cells are
// axis-aligned boxes tiling a rectilinear lattice (GridGenerator::hyper_cube,
// hyper_rectangle, subdivided_hyper_rectangle, and any such mesh), refined
// isotropically, with no manifold that moves vertices. Each coarse cell is a
// Canopy tree (deal.II's child numbering is Canopy's: x fastest, then y, then z);
// each locally owned active cell is a leaf of the rank's grid. Ghost and artificial
// cells are not described: the parts of a tree that other ranks own are absent, as
// with p4est, and coarse cells with no locally owned cell are left out. Anything
// else is refused before anything is built: InvalidForest lists every problem
// (which coarse cell is not a box, which cell is refined anisotropically, which
// vertex a manifold moved...).
//
// Fields. Cell vectors are read where deal.II keeps them: a Vector<T> indexed by
// active_cell_index() (what KellyErrorEstimator fills), or a distributed vector
// indexed by global_active_cell_index() through its locally owned part. A
// finite-element solution is shown by its average over each cell, computed by
// Canopy with deal.II's FEValues into a buffer this object owns: the one copy,
// made when addCellAverages is called (so describe the mesh only on the steps
// where InSitu::willExecute says a pipeline runs).
//
// Lifetime. The description borrows the triangulation and every vector: it is
// valid until the mesh changes (execute_coarsening_and_refinement, repartition,
// clear, destruction); describe it again after every such change. description()
// throws InvalidForest if the triangulation changed since it was described. The
// vectors must stay alive and unresized while a grid built from the description is
// in use; their values are read when the grid is read (a change is seen).
#pragma once

#include <canopy/ForestDescription.h>
#include <canopy/ForestValidation.h>

#include <deal.II/base/config.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/la_parallel_vector.h>
#include <deal.II/lac/vector.h>
#ifdef DEAL_II_WITH_PETSC
#include <deal.II/lac/petsc_vector.h>
#endif
#ifdef DEAL_II_WITH_TRILINOS
#include <deal.II/lac/trilinos_vector.h>
#endif

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace canopy
{

/// This rank's locally owned active cells of a deal.II triangulation (dim 2 or 3).
template <int dim>
class DealIIForest
{
public:
  /// Describes the locally owned part of `triangulation` (not collective: each
  /// rank describes its own). `triangulation`: borrowed, not modified; must stay
  /// unchanged while the description is used (this object watches its signals).
  /// Throws InvalidForest, listing every problem, when the coarse mesh is not a
  /// lattice of axis-aligned boxes, a cell is refined anisotropically, a vertex
  /// is not where isotropic refinement of the boxes puts it (a curved manifold),
  /// or the triangulation is empty or fully distributed; nothing is kept.
  explicit DealIIForest(const dealii::Triangulation<dim>& triangulation);
  ~DealIIForest();
  DealIIForest(DealIIForest&&) noexcept;
  DealIIForest& operator=(DealIIForest&&) noexcept;
  DealIIForest(const DealIIForest&) = delete;
  DealIIForest& operator=(const DealIIForest&) = delete;

  /// A cell vector indexed by active_cell_index() (n_active_cells() entries,
  /// ghost and artificial cells' entries unread), T double or float. `values`:
  /// borrowed, read in place, never written; keep it alive and unresized while a
  /// grid built from the description is in use. Throws InvalidForest for a wrong
  /// size, an empty or duplicate name.
  template <typename T>
  void addCellVector(std::string name, const dealii::Vector<T>& values);

  /// A distributed cell vector indexed by global_active_cell_index() (e.g.
  /// reinit(triangulation.global_active_cell_index_partitioner().lock())), read
  /// in place through its locally owned part; T double or float. Borrowed as
  /// above. Throws InvalidForest when a locally owned cell's index is not in the
  /// vector's locally owned range.
  template <typename T>
  void addCellVector(std::string name, const dealii::LinearAlgebra::distributed::Vector<T>& values);
#ifdef DEAL_II_WITH_PETSC
  /// As above, for a PETSc MPI vector indexed by global_active_cell_index().
  void addCellVector(std::string name, const dealii::PETScWrappers::MPI::Vector& values);
#endif
#ifdef DEAL_II_WITH_TRILINOS
  /// As above, for a Trilinos MPI vector indexed by global_active_cell_index().
  void addCellVector(std::string name, const dealii::TrilinosWrappers::MPI::Vector& values);
#endif

  /// A finite-element field shown by its average over each locally owned cell
  /// (Gauss quadrature of degree + 1, exact for the FE's polynomials on boxes):
  /// fe.n_components() components, computed now into a buffer this object owns
  /// (the only copy Canopy makes; call it on the steps that execute). `dofs`:
  /// a DoFHandler of the described triangulation (not hp), read now only.
  /// `solution`: indexed by DoF, read now only; with more than one rank it must
  /// hold the ghost entries of the locally relevant DoFs (as DataOut needs).
  /// VectorType: Vector<double|float>, LinearAlgebra::distributed::Vector<double|float>,
  /// PETScWrappers::MPI::Vector, TrilinosWrappers::MPI::Vector.
  template <typename VectorType>
  void addCellAverages(std::string name, const dealii::DoFHandler<dim>& dofs,
                       const VectorType& solution);

  /// The description for canopy::GridBuilder or InSitu::execute: valid while this
  /// object lives and the mesh is unchanged. Throws InvalidForest if the
  /// triangulation changed since it was described.
  const ForestDescription& description() const;

  /// Locally owned active cells (the tuples of every field).
  std::size_t numberOfCells() const;
  /// Coarse cells with a locally owned cell; those shared with other ranks have absent parts.
  std::size_t numberOfLocalTrees() const;
  /// Bytes describing wrote into memory: the tables this object keeps (refinement,
  /// absent and slot bytes, address tables, cell averages) and the scratch tables
  /// it used while walking the mesh. For cost accounting (docs/benchmarks.md).
  std::size_t memoryWritten() const;

private:
  void addLocalPart(std::string name, ValueType type, const void* localValues,
                    std::size_t valueBytes, const std::vector<std::uint32_t>& localIndexOfCell);
  /// Each owned cell's place in a distributed vector's local array (`localOf` of
  /// its global_active_cell_index), refusing cells outside the vector's `owned` set.
  std::vector<std::uint32_t>
  localIndicesOf(const dealii::IndexSet& owned,
                 const std::function<std::int64_t(dealii::types::global_dof_index)>& localOf,
                 const std::string& name) const;

  struct State;
  std::unique_ptr<State> Impl;
};

extern template class DealIIForest<2>;
extern template class DealIIForest<3>;

} // namespace canopy
