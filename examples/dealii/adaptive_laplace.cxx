// A deal.II program with Canopy in situ: the adaptive Laplace problem of deal.II's
// step-40 (-div grad u = f, f = 2 or -1 across a wavy line, u = 0 on the boundary),
// FE_Q(2) on a parallel::distributed::Triangulation, Trilinos CG + AMG, Kelly's
// error estimator, refine_and_coarsen_fixed_number and a repartition every cycle.
// Where step-40 writes VTU files with DataOut, Canopy's shipped pipelines run on
// the mesh as deal.II holds it: the solution's cell averages, the error
// indicators and the owner of each cell, without writing a mesh file.
// The Canopy glue is marked below (docs/dealii.md shows it beside DataOut).
//
//   mpirun -np 3 canopy_dealii_laplace [--dimension 2|3] [--cycles N] [output-dir]
#include <deal.II/base/function.h>
#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/grid_refinement.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/numerics/error_estimator.h>
#include <deal.II/numerics/vector_tools.h>

// ---- Canopy glue (1 of 3): the headers ----
#include <canopy/DealIIForest.h>
#include <canopy/InSitu.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace
{

using namespace dealii;

template <int dim>
class LaplaceProblem
{
public:
  explicit LaplaceProblem(MPI_Comm comm)
      : comm(comm), triangulation(comm), fe(2), dofs(triangulation)
  {
    // A box of 2 x 1 (x 1) unit cells, as subdivided_hyper_rectangle makes it.
    Point<dim> upper;
    std::vector<unsigned int> repetitions(dim, 1);
    for (int a = 0; a < dim; ++a)
      upper[a] = 1;
    upper[0] = 2;
    repetitions[0] = 2;
    GridGenerator::subdivided_hyper_rectangle(triangulation, repetitions, Point<dim>(), upper);
    triangulation.refine_global(dim == 2 ? 4 : 2);
  }

  /// Distributes DoFs, assembles and solves (step-40's setup, assemble, solve).
  void solve()
  {
    dofs.distribute_dofs(fe);
    const IndexSet owned = dofs.locally_owned_dofs();
    const IndexSet relevant = DoFTools::extract_locally_relevant_dofs(dofs);
    solution.reinit(owned, relevant, comm);
    constraints.clear();
    constraints.reinit(relevant);
    DoFTools::make_hanging_node_constraints(dofs, constraints);
    VectorTools::interpolate_boundary_values(dofs, 0, Functions::ZeroFunction<dim>(), constraints);
    constraints.close();
    DynamicSparsityPattern pattern(relevant);
    DoFTools::make_sparsity_pattern(dofs, pattern, constraints, false);
    SparsityTools::distribute_sparsity_pattern(pattern, owned, comm, relevant);
    TrilinosWrappers::SparseMatrix matrix;
    matrix.reinit(owned, owned, pattern, comm);
    TrilinosWrappers::MPI::Vector rhs(owned, comm);

    const QGauss<dim> quadrature(fe.degree + 1);
    FEValues<dim> values(fe, quadrature,
                         update_values | update_gradients | update_quadrature_points |
                             update_JxW_values);
    const unsigned int n = fe.n_dofs_per_cell();
    FullMatrix<double> cellMatrix(n, n);
    Vector<double> cellRhs(n);
    std::vector<types::global_dof_index> indices(n);
    for (const auto& cell : dofs.active_cell_iterators())
    {
      if (!cell->is_locally_owned())
        continue;
      cellMatrix = 0;
      cellRhs = 0;
      values.reinit(cell);
      for (unsigned int q = 0; q < quadrature.size(); ++q)
      {
        const Point<dim> p = values.quadrature_point(q);
        const double f = p[1] > 0.5 + 0.25 * std::sin(4.0 * numbers::PI * p[0]) ? 2 : -1;
        for (unsigned int i = 0; i < n; ++i)
        {
          for (unsigned int j = 0; j < n; ++j)
            cellMatrix(i, j) += values.shape_grad(i, q) * values.shape_grad(j, q) * values.JxW(q);
          cellRhs(i) += f * values.shape_value(i, q) * values.JxW(q);
        }
      }
      cell->get_dof_indices(indices);
      constraints.distribute_local_to_global(cellMatrix, cellRhs, indices, matrix, rhs);
    }
    matrix.compress(VectorOperation::add);
    rhs.compress(VectorOperation::add);

    TrilinosWrappers::MPI::Vector owned_solution(owned, comm);
    SolverControl control(dofs.n_dofs(), 1e-10 * rhs.l2_norm());
    SolverCG<TrilinosWrappers::MPI::Vector> cg(control);
    TrilinosWrappers::PreconditionAMG amg;
    TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic = true;
    data.higher_order_elements = true;
    amg.initialize(matrix, data);
    cg.solve(matrix, owned_solution, rhs, amg);
    constraints.distribute(owned_solution);
    solution = owned_solution;
  }

  /// Kelly's indicators for the current solution (one float per active cell).
  void estimate()
  {
    error.reinit(triangulation.n_active_cells());
    KellyErrorEstimator<dim>::estimate(dofs, QGauss<dim - 1>(fe.degree + 1), {}, solution, error);
  }

  /// Refines 30% and coarsens 3% of the cells by error; p4est repartitions.
  void adapt()
  {
    parallel::distributed::GridRefinement::refine_and_coarsen_fixed_number(triangulation, error,
                                                                           0.3, 0.03);
    triangulation.execute_coarsening_and_refinement();
  }

  MPI_Comm comm;
  parallel::distributed::Triangulation<dim> triangulation;
  FE_Q<dim> fe;
  DoFHandler<dim> dofs;
  AffineConstraints<double> constraints;
  TrilinosWrappers::MPI::Vector solution; // with the locally relevant (ghost) DoFs
  Vector<float> error;                    // by active_cell_index, as Kelly fills it
};

/// What the program knows of its own mesh and solution, for the test to compare
/// Canopy's outputs with (tests/dealii/dealii_laplace_check.py).
template <int dim>
void report(const LaplaceProblem<dim>& problem, int cycle, double errorAtLeast)
{
  long flagged = 0;
  double errorSum = 0;
  for (const auto& cell : problem.triangulation.active_cell_iterators())
  {
    if (!cell->is_locally_owned())
      continue;
    const float e = problem.error[cell->active_cell_index()];
    flagged += e >= errorAtLeast;
    errorSum += e;
  }
  flagged = Utilities::MPI::sum(flagged, problem.comm);
  errorSum = Utilities::MPI::sum(errorSum, problem.comm);
  // The integral of u, by deal.II's own quadrature.
  const double integral =
      VectorTools::compute_mean_value(problem.dofs, QGauss<dim>(3), problem.solution, 0) *
      2.0; // the domain's volume
  if (Utilities::MPI::this_mpi_process(problem.comm) == 0)
  {
    std::printf("dealii_laplace: cycle %d: %llu cells, %ld with error >= %g\n", cycle,
                static_cast<unsigned long long>(problem.triangulation.n_global_active_cells()),
                flagged, errorAtLeast);
    std::printf("dealii_laplace: cycle %d: integral of u %.17g, error sum %.17g\n", cycle, integral,
                errorSum);
  }
}

template <int dim>
void run(int cycles, int every, double errorAtLeast, const std::string& output)
{
  LaplaceProblem<dim> problem(MPI_COMM_WORLD);

  // ---- Canopy glue (2 of 3): open, with the shipped pipelines by name ----
  const std::string frequency = "--frequency=" + std::to_string(every);
  canopy::InSituOptions options;
  if (dim == 2)
    options.scripts = {{"surface_image.py", {frequency, "--color-by=u"}}};
  else
    options.scripts = {
        {"slice_image.py", {frequency, "--color-by=u", "--contour-field=u", "--contour-count=1"}}};
  char range[64];
  std::snprintf(range, sizeof range, "--value-range=%.17g,1e30", errorAtLeast);
  options.scripts.push_back(
      {"selection_extract.py", {frequency, "--selection=range", "--value-field=error", range}});
  options.scripts.push_back({"data_extracts.py", {frequency}});
  options.outputDirectory = output;
  canopy::InSitu insitu(MPI_COMM_WORLD, options);
  Vector<float> owner(problem.triangulation.n_active_cells());

  for (int cycle = 0; cycle < cycles; ++cycle)
  {
    if (cycle > 0)
      problem.adapt();
    problem.solve();
    problem.estimate();
    if (cycle % every == 0)
      report(problem, cycle, errorAtLeast);
    owner.reinit(problem.triangulation.n_active_cells());
    owner = static_cast<float>(Utilities::MPI::this_mpi_process(MPI_COMM_WORLD));

    // ---- Canopy glue (3 of 3): describe the mesh as it is now, run what is due ----
    if (insitu.willExecute(cycle, cycle))
    {
      canopy::DealIIForest<dim> described(problem.triangulation);
      described.addCellAverages("u", problem.dofs, problem.solution);
      described.addCellVector("error", problem.error);
      described.addCellVector("owner", owner);
      const canopy::StepReport result = insitu.execute(cycle, cycle, described.description());
      for (const std::string& failure : result.failures)
        std::fprintf(stderr, "canopy: %s\n", failure.c_str());
    }
  }
  insitu.close();
}

} // namespace

int main(int argc, char** argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  int dimension = 2;
  int cycles = 6;
  int every = 1;
  double errorAtLeast = -1; // the selection's threshold: 1e-5 in 2D, 1e-3 in 3D
  std::string output = "dealii-output";
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--dimension" && i + 1 < argc)
      dimension = std::atoi(argv[++i]);
    else if (arg == "--cycles" && i + 1 < argc)
      cycles = std::atoi(argv[++i]);
    else if (arg == "--every" && i + 1 < argc)
      every = std::atoi(argv[++i]);
    else if (arg == "--error-at-least" && i + 1 < argc)
      errorAtLeast = std::atof(argv[++i]);
    else
      output = arg;
  }
  if (dimension == 3)
    run<3>(cycles, every, errorAtLeast < 0 ? 1e-3 : errorAtLeast, output);
  else
    run<2>(cycles, every, errorAtLeast < 0 ? 1e-5 : errorAtLeast, output);
  return 0;
}
