// Canopy::dealii against real deal.II triangulations on 1, 2 and 3 MPI ranks:
// a parallel::distributed::Triangulation (and a serial one) on a lattice of
// boxes, refined adaptively around a circle (sphere) and repartitioned, so that
// coarse cells are split between ranks. Every locally owned active cell must be
// a visible leaf of the rank's grid with the same box, level and values, and
// nothing else; cell vectors are read in place; finite-element averages match the
// exact averages of the interpolated polynomials; unsupported meshes and stale
// descriptions are refused.
#include <canopy/DealIIForest.h>
#include <canopy/GridBuilder.h>
#include <canopy/HtgBuilder.h>

#include "HtgWalk.h"

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/partitioner.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/numerics/vector_tools.h>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>

#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <string>

namespace
{

using namespace dealii;

int rankCount()
{
  return static_cast<int>(Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD));
}

/// A cell's place: its centre (quantized; deal.II and VTK compute midpoints in
/// different orders) and its level.
using Key = std::array<long long, 4>;
Key keyOf(const std::array<double, 3>& centre, int level)
{
  Key key{};
  for (int a = 0; a < 3; ++a)
  {
    key[a] = std::llround(centre[a] * (1 << 24));
  }
  key[3] = level;
  return key;
}

template <int dim>
std::array<double, 3> centreOf(const typename Triangulation<dim>::cell_iterator& cell)
{
  std::array<double, 3> c{{0, 0, 0}};
  const Point<dim> lo = cell->vertex(0);
  const Point<dim> hi = cell->vertex(GeometryInfo<dim>::vertices_per_cell - 1);
  for (int a = 0; a < dim; ++a)
  {
    c[a] = 0.5 * (lo[a] + hi[a]);
  }
  return c;
}

/// The scalar field the FE_Q(2) solution interpolates exactly (it is in Q2).
template <int dim>
double scalarAt(const Point<dim>& p)
{
  return p[0] * p[0] + p[0] * p[1] - 0.5 * p[1] + (dim == 3 ? p[2] * p[0] : 0.0);
}

/// Its exact average over a box: mean(x^2) = (a^2 + ab + b^2) / 3, products of
/// different axes average to products of means.
template <int dim>
double scalarAverage(const Point<dim>& lo, const Point<dim>& hi)
{
  std::array<double, 3> m{{0, 0, 0}};
  for (int a = 0; a < dim; ++a)
  {
    m[a] = 0.5 * (lo[a] + hi[a]);
  }
  const double xx = (lo[0] * lo[0] + lo[0] * hi[0] + hi[0] * hi[0]) / 3;
  return xx + m[0] * m[1] - 0.5 * m[1] + (dim == 3 ? m[2] * m[0] : 0.0);
}

/// The vector field the FESystem(FE_Q(1), dim) solution interpolates exactly.
template <int dim>
class VectorField : public Function<dim>
{
public:
  VectorField() : Function<dim>(dim) {}
  double value(const Point<dim>& p, const unsigned int c) const override
  {
    return p[c] + 2.0 * c + p[0] * p[1];
  }
};

template <int dim>
class ScalarField : public Function<dim>
{
public:
  double value(const Point<dim>& p, const unsigned int) const override { return scalarAt(p); }
};

/// Refine the cells a circle (sphere) crosses, `times` times.
template <int dim>
void refineAroundFront(Triangulation<dim>& tria, int times)
{
  Point<dim> centre;
  centre[0] = 1.1;
  centre[1] = 0.7;
  for (int t = 0; t < times; ++t)
  {
    for (const auto& cell : tria.active_cell_iterators())
    {
      if (!cell->is_locally_owned())
      {
        continue;
      }
      double nearest = 0;
      double farthest = 0;
      for (int a = 0; a < dim; ++a)
      {
        const double lo = cell->vertex(0)[a] - centre[a];
        const double hi = cell->vertex(GeometryInfo<dim>::vertices_per_cell - 1)[a] - centre[a];
        const double near = lo > 0 ? lo : (hi < 0 ? -hi : 0);
        const double far = std::max(std::abs(lo), std::abs(hi));
        nearest += near * near;
        farthest += far * far;
      }
      if (std::sqrt(nearest) <= 0.6 && std::sqrt(farthest) >= 0.6)
      {
        cell->set_refine_flag();
      }
    }
    tria.execute_coarsening_and_refinement();
  }
}

/// A lattice of 3 x 2 (x 2) unequal boxes, refined once everywhere and then at the front.
template <int dim>
void makeMesh(Triangulation<dim>& tria, int frontLevels = 2)
{
  std::vector<std::vector<double>> spacing(dim);
  spacing[0] = {0.5, 0.25, 0.75};
  spacing[1] = {0.6, 0.8};
  if (dim == 3)
  {
    spacing[2] = {0.5, 0.5};
  }
  Point<dim> upper;
  for (int a = 0; a < dim; ++a)
  {
    for (double step : spacing[a])
    {
      upper[a] += step;
    }
  }
  GridGenerator::subdivided_hyper_rectangle(tria, spacing, Point<dim>(), upper);
  tria.refine_global(1);
  refineAroundFront(tria, frontLevels);
}

/// How global_active_cell_index() is distributed (a serial mesh: all on every rank).
template <int dim>
std::shared_ptr<const Utilities::MPI::Partitioner> cellPartitioner(const Triangulation<dim>& tria)
{
  if (const auto* parallel = dynamic_cast<const parallel::TriangulationBase<dim>*>(&tria))
  {
    return parallel->global_active_cell_index_partitioner().lock();
  }
  return std::make_shared<const Utilities::MPI::Partitioner>(
      complete_index_set(tria.n_active_cells()), tria.get_communicator());
}

/// What the test expects of each locally owned cell.
struct Expected
{
  double error = 0;                        // the Vector<double> by active_cell_index
  double global = 0;                       // the distributed vectors by global_active_cell_index
  double scalar = 0;                       // the FE_Q(2) average
  std::array<double, 3> vector{{0, 0, 0}}; // the FESystem average
  bool seen = false;
};

template <int dim, typename Tria>
void checkEveryOwnedCellIsALeaf()
{
  Tria tria(MPI_COMM_WORLD);
  makeMesh(tria);
  // A serial Triangulation's vectors are every rank's own (MPI_COMM_SELF).
  const MPI_Comm comm = tria.get_communicator();
  const bool distributed =
      rankCount() > 1 && std::is_same_v<Tria, parallel::distributed::Triangulation<dim>>;

  // Cell vectors: by active_cell_index (serial Vector) and by
  // global_active_cell_index (distributed vectors), values a function of place.
  Vector<double> error(tria.n_active_cells());
  Vector<float> level(tria.n_active_cells());
  const auto cellPartition = cellPartitioner(tria);
  LinearAlgebra::distributed::Vector<double> globalCells(cellPartition);
  const IndexSet ownedCells = cellPartition->locally_owned_range();
  TrilinosWrappers::MPI::Vector trilinosCells(ownedCells, comm);
  PETScWrappers::MPI::Vector petscCells(ownedCells, comm);
  std::map<Key, Expected> expected;
  for (const auto& cell : tria.active_cell_iterators())
  {
    if (!cell->is_locally_owned())
    {
      error[cell->active_cell_index()] = -1e300; // never read: not described
      continue;
    }
    const auto centre = centreOf<dim>(cell);
    Expected e;
    e.error = std::sin(3 * centre[0]) + centre[1] * centre[2] + 0.01 * cell->level();
    e.global = 10 + centre[0] - 2 * centre[1] + 4 * centre[2];
    const Point<dim> lo = cell->vertex(0);
    const Point<dim> hi = cell->vertex(GeometryInfo<dim>::vertices_per_cell - 1);
    e.scalar = scalarAverage<dim>(lo, hi);
    const double xy = 0.5 * (lo[0] + hi[0]) * 0.5 * (lo[1] + hi[1]);
    for (int c = 0; c < dim; ++c)
    {
      e.vector[c] = 0.5 * (lo[c] + hi[c]) + 2.0 * c + xy;
    }
    error[cell->active_cell_index()] = e.error;
    level[cell->active_cell_index()] = static_cast<float>(cell->level());
    globalCells[cell->global_active_cell_index()] = e.global;
    trilinosCells[cell->global_active_cell_index()] = e.global + 1;
    petscCells[cell->global_active_cell_index()] = e.global + 2;
    expected[keyOf(centre, cell->level())] = e;
  }
  trilinosCells.compress(VectorOperation::insert);
  // The same values with the ghost cells' entries: Epetra keeps them in one local
  // array whose owned entries need not come first.
  IndexSet relevantCells = ownedCells;
  for (const auto& cell : tria.active_cell_iterators())
  {
    if (cell->is_ghost())
    {
      relevantCells.add_index(cell->global_active_cell_index());
    }
  }
  TrilinosWrappers::MPI::Vector trilinosGhosted(ownedCells, relevantCells, comm);
  trilinosGhosted = trilinosCells;
  petscCells.compress(VectorOperation::insert);

  // Finite-element solutions, ghosted as DataOut needs them.
  FE_Q<dim> q2(2);
  DoFHandler<dim> scalarDofs(tria);
  scalarDofs.distribute_dofs(q2);
  const IndexSet owned = scalarDofs.locally_owned_dofs();
  const IndexSet relevant = DoFTools::extract_locally_relevant_dofs(scalarDofs);
  // deal.II's interpolate writes the DoFs of owned cells, ghost DoFs included.
  LinearAlgebra::distributed::Vector<double> scalar(owned, relevant, comm);
  VectorTools::interpolate(scalarDofs, ScalarField<dim>(), scalar);
  scalar.update_ghost_values();

  FESystem<dim> q1s(FE_Q<dim>(1), dim);
  DoFHandler<dim> vectorDofs(tria);
  vectorDofs.distribute_dofs(q1s);
  const IndexSet vOwned = vectorDofs.locally_owned_dofs();
  const IndexSet vRelevant = DoFTools::extract_locally_relevant_dofs(vectorDofs);
  TrilinosWrappers::MPI::Vector vectorOwned(vOwned, comm);
  VectorTools::interpolate(vectorDofs, VectorField<dim>(), vectorOwned);
  TrilinosWrappers::MPI::Vector vectorSolution(vOwned, vRelevant, comm);
  vectorSolution = vectorOwned;

  // No ASSERT and no exception before the collectives below: a failing rank must
  // not leave the others waiting.
  std::unique_ptr<canopy::DealIIForest<dim>> described;
  vtkSmartPointer<vtkHyperTreeGrid> htg = vtkSmartPointer<vtkHyperTreeGrid>::New();
  try
  {
    described = std::make_unique<canopy::DealIIForest<dim>>(tria);
    described->addCellVector("error", error);
    described->addCellVector("level", level);
    described->addCellVector("global", globalCells);
    described->addCellVector("trilinos", trilinosCells);
    described->addCellVector("trilinos_ghosted", trilinosGhosted);
    described->addCellVector("petsc", petscCells);
    described->addCellAverages("u", scalarDofs, scalar);
    described->addCellAverages("velocity", vectorDofs, vectorSolution);
    EXPECT_EQ(described->numberOfCells(), expected.size());
    htg = canopy::buildHyperTreeGrid(described->description());
  }
  catch (const std::exception& e)
  {
    ADD_FAILURE() << e.what();
  }
  vtkCellData* data = htg->GetCellData();
  const std::array<const char*, 8> names{
      {"error", "level", "global", "trilinos", "trilinos_ghosted", "petsc", "u", "velocity"}};
  bool arrays = true;
  for (const char* name : names)
  {
    EXPECT_NE(data->GetArray(name), nullptr) << name;
    arrays = arrays && data->GetArray(name) != nullptr;
  }
  std::size_t leaves = 0;
  if (arrays)
  {
    canopy::testing::forEachVisibleLeaf(
        htg,
        [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor)
        {
          ++leaves;
          std::array<double, 6> bounds;
          cursor->GetBounds(bounds.data());
          const std::array<double, 3> centre{{0.5 * (bounds[0] + bounds[1]),
                                              0.5 * (bounds[2] + bounds[3]),
                                              0.5 * (bounds[4] + bounds[5])}};
          const int cellLevel = static_cast<int>(cursor->GetLevel());
          const auto found = expected.find(keyOf(centre, cellLevel));
          ASSERT_NE(found, expected.end())
              << "a leaf at (" << centre[0] << ", " << centre[1] << ", " << centre[2] << "), level "
              << cellLevel << " is not a locally owned cell of this rank";
          Expected& e = found->second;
          EXPECT_FALSE(e.seen) << "two leaves for one cell";
          e.seen = true;
          const vtkIdType id = cursor->GetGlobalNodeIndex();
          EXPECT_EQ(data->GetArray("error")->GetComponent(id, 0), e.error);
          EXPECT_EQ(data->GetArray("level")->GetComponent(id, 0), cellLevel);
          EXPECT_EQ(data->GetArray("global")->GetComponent(id, 0), e.global);
          EXPECT_EQ(data->GetArray("trilinos")->GetComponent(id, 0), e.global + 1);
          EXPECT_EQ(data->GetArray("trilinos_ghosted")->GetComponent(id, 0), e.global + 1);
          EXPECT_EQ(data->GetArray("petsc")->GetComponent(id, 0), e.global + 2);
          EXPECT_NEAR(data->GetArray("u")->GetComponent(id, 0), e.scalar, 1e-12);
          for (int c = 0; c < dim; ++c)
          {
            EXPECT_NEAR(data->GetArray("velocity")->GetComponent(id, c), e.vector[c], 1e-12)
                << "component " << c;
          }
          // The box: the leaf's size is the cell's (centre and level matched already).
          const auto cellWidth = bounds[1] - bounds[0];
          EXPECT_GT(cellWidth, 0);
        });
  }
  EXPECT_EQ(leaves, expected.size());
  // Every active cell of the whole mesh is a leaf on exactly one rank.
  unsigned long all = Utilities::MPI::sum(static_cast<unsigned long>(leaves), comm);
  EXPECT_EQ(all, tria.n_global_active_cells());
  // With more than one rank some coarse cell is split: absent parts are exercised.
  int split = 0;
  for (const auto& tree :
       described ? described->description().trees : std::vector<canopy::TreeDescription>{})
  {
    split |= tree.absent != nullptr;
  }
  if (distributed)
  {
    EXPECT_EQ(Utilities::MPI::max(split, MPI_COMM_WORLD), 1)
        << "the partition should split a coarse cell between ranks";
  }
}

TEST(DealIIForest, EveryOwnedCellIsAVisibleLeafWithItsValues2D)
{
  checkEveryOwnedCellIsALeaf<2, parallel::distributed::Triangulation<2>>();
}

TEST(DealIIForest, EveryOwnedCellIsAVisibleLeafWithItsValues3D)
{
  checkEveryOwnedCellIsALeaf<3, parallel::distributed::Triangulation<3>>();
}

/// A serial Triangulation (every rank holds it all) through the same checks.
template <int dim>
struct SerialTriangulation : Triangulation<dim>
{
  explicit SerialTriangulation(MPI_Comm) {}
};

TEST(DealIIForest, SerialTriangulation2D)
{
  checkEveryOwnedCellIsALeaf<2, SerialTriangulation<2>>();
}

TEST(DealIIForest, SerialTriangulation3D)
{
  checkEveryOwnedCellIsALeaf<3, SerialTriangulation<3>>();
}

template <int dim>
void checkValuesAreReadInPlace()
{
  parallel::distributed::Triangulation<dim> tria(MPI_COMM_WORLD);
  makeMesh(tria, 1);
  Vector<double> error(tria.n_active_cells());
  LinearAlgebra::distributed::Vector<double> global(
      tria.global_active_cell_index_partitioner().lock());
  for (const auto& cell : tria.active_cell_iterators())
  {
    if (cell->is_locally_owned())
    {
      error[cell->active_cell_index()] = 1.0;
      global[cell->global_active_cell_index()] = 2.0;
    }
  }
  canopy::DealIIForest<dim> described(tria);
  described.addCellVector("error", error);
  described.addCellVector("global", global);
  auto htg = canopy::buildHyperTreeGrid(described.description());
  vtkDataArray* errorArray = htg->GetCellData()->GetArray("error");
  vtkDataArray* globalArray = htg->GetCellData()->GetArray("global");
  ASSERT_NE(errorArray, nullptr);
  ASSERT_NE(globalArray, nullptr);
  // The description points into the vectors (the grid reads through it; reading a
  // raw pointer from the grid's arrays would detach them from the simulation).
  const auto& fields = described.description().fields;
  ASSERT_EQ(fields.size(), 2u);
  // A distributed vector's locally owned part is the array itself.
  EXPECT_EQ(fields[1].layout, canopy::Layout::AoS);
  EXPECT_EQ(fields[1].data, static_cast<const void*>(global.begin()));
  if (rankCount() == 1)
  {
    // One rank: no ghost cells between, the whole Vector is the array.
    EXPECT_EQ(fields[0].layout, canopy::Layout::AoS);
    EXPECT_EQ(fields[0].data, static_cast<const void*>(error.begin()));
  }
  else
  {
    // Ghost and artificial cells' entries in between: one address per cell, into it.
    EXPECT_EQ(fields[0].layout, canopy::Layout::Indirect);
    for (std::size_t k = 0; k < fields[0].numberOfTuples; ++k)
    {
      const auto* address = static_cast<const double*>(fields[0].tupleAddresses[k]);
      EXPECT_TRUE(address >= error.begin() && address < error.end());
    }
  }
  // Changes after the build are seen through the grid: nothing was copied.
  for (const auto& cell : tria.active_cell_iterators())
  {
    if (cell->is_locally_owned())
    {
      error[cell->active_cell_index()] = 100.0 + cell->active_cell_index();
      global[cell->global_active_cell_index()] = -5.0 - cell->level();
    }
  }
  std::size_t leaves = 0;
  double errorSum = 0;
  double globalSum = 0;
  canopy::testing::forEachVisibleLeaf(htg,
                                      [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor)
                                      {
                                        ++leaves;
                                        const vtkIdType id = cursor->GetGlobalNodeIndex();
                                        errorSum += errorArray->GetComponent(id, 0);
                                        globalSum += globalArray->GetComponent(id, 0);
                                      });
  double expectedError = 0;
  double expectedGlobal = 0;
  for (const auto& cell : tria.active_cell_iterators())
  {
    if (cell->is_locally_owned())
    {
      expectedError += 100.0 + cell->active_cell_index();
      expectedGlobal += -5.0 - cell->level();
    }
  }
  EXPECT_EQ(leaves, described.numberOfCells());
  EXPECT_EQ(errorSum, expectedError);
  EXPECT_EQ(globalSum, expectedGlobal);
}

TEST(DealIIForest, ValuesAreReadInPlace2D)
{
  checkValuesAreReadInPlace<2>();
}

TEST(DealIIForest, ValuesAreReadInPlace3D)
{
  checkValuesAreReadInPlace<3>();
}

/// The message of the InvalidForest `make` throws ("" if none).
template <typename Make>
std::string refusal(Make&& make)
{
  try
  {
    make();
  }
  catch (const canopy::InvalidForest& e)
  {
    return e.what();
  }
  return "";
}

bool says(const std::string& message, const std::string& part)
{
  return message.find(part) != std::string::npos;
}

TEST(DealIIForest, UnsupportedMeshesAreRefused)
{
  {
    Triangulation<2> ball;
    GridGenerator::hyper_ball(ball);
    const std::string message = refusal([&] { canopy::DealIIForest<2> d(ball); });
    EXPECT_TRUE(says(message, "is not an axis-aligned box")) << message;
  }
  {
    Triangulation<3> rotated;
    GridGenerator::hyper_cube(rotated);
    GridTools::rotate(0.5, 2, rotated);
    const std::string message = refusal([&] { canopy::DealIIForest<3> d(rotated); });
    EXPECT_TRUE(says(message, "coarse cell 0 is not an axis-aligned box")) << message;
  }
  {
    Triangulation<2> l;
    GridGenerator::hyper_L(l);
    const std::string message = refusal([&] { canopy::DealIIForest<2> d(l); });
    EXPECT_TRUE(says(message, "do not tile")) << message;
  }
  {
    // Two problems in one mesh, both reported at once: an anisotropic
    // refinement and a vertex moved off its box.
    Triangulation<2> mesh;
    GridGenerator::subdivided_hyper_cube(mesh, 2);
    const auto refined = std::next(mesh.begin(0), 3);
    mesh.begin(0)->set_refine_flag(RefinementCase<2>::cut_x);
    refined->set_refine_flag();
    mesh.execute_coarsening_and_refinement();
    refined->child(0)->vertex(3)[1] += 0.01; // the coarse cell's centre, shared by its children
    const std::string message = refusal([&] { canopy::DealIIForest<2> d(mesh); });
    EXPECT_TRUE(says(message, "refined anisotropically")) << message;
    EXPECT_TRUE(says(message, "vertices are not the corners")) << message;
  }
  {
    Triangulation<2> square;
    GridGenerator::hyper_cube(square);
    square.refine_global(2);
    canopy::DealIIForest<2> described(square);
    Vector<double> tooShort(3);
    const std::string message = refusal([&] { described.addCellVector("e", tooShort); });
    EXPECT_TRUE(says(message, "field 'e': the vector has 3 entries")) << message;
  }
}

TEST(DealIIForest, StaleDescriptionIsRefused)
{
  parallel::distributed::Triangulation<2> tria(MPI_COMM_WORLD);
  makeMesh(tria, 1);
  canopy::DealIIForest<2> described(tria);
  EXPECT_NO_THROW(described.description());
  tria.refine_global(1);
  const std::string refined = refusal([&] { described.description(); });
  EXPECT_TRUE(says(refined, "changed since it was described")) << refined;

  canopy::DealIIForest<2> again(tria);
  EXPECT_NO_THROW(again.description());
  tria.repartition();
  const std::string repartitioned = refusal([&] { again.description(); });
  EXPECT_TRUE(says(repartitioned, "changed since it was described")) << repartitioned;

  // A description that outlives its serial triangulation is refused, not read.
  auto square = std::make_unique<Triangulation<2>>();
  GridGenerator::hyper_cube(*square);
  canopy::DealIIForest<2> orphan(*square);
  square.reset();
  const std::string gone = refusal([&] { orphan.description(); });
  EXPECT_TRUE(says(gone, "changed since it was described")) << gone;
}

/// Trees untouched by a refinement are kept by the builder (p::d: by p4est's
/// revision; serial: by their bytes).
template <typename Tria>
void checkUnchangedTreesAreKept()
{
  Tria tria(MPI_COMM_WORLD);
  GridGenerator::subdivided_hyper_cube(tria, 3);
  tria.refine_global(1);
  canopy::GridBuilder builder;
  {
    canopy::DealIIForest<2> described(tria);
    builder.build(described.description());
  }
  {
    canopy::DealIIForest<2> described(tria); // the same mesh again
    builder.build(described.description());
    EXPECT_EQ(builder.lastBuild().treesRebuilt, 0u);
  }
  // Refine inside coarse cell 4 (the centre) only.
  for (const auto& cell : tria.active_cell_iterators())
  {
    if (cell->is_locally_owned() && cell->parent()->index() == 4)
    {
      cell->set_refine_flag();
    }
  }
  tria.execute_coarsening_and_refinement();
  canopy::DealIIForest<2> described(tria);
  builder.build(described.description());
  const auto& reuse = builder.lastBuild();
  EXPECT_EQ(reuse.treesRebuilt + reuse.treesKept, described.numberOfLocalTrees());
  if (rankCount() == 1 || !std::is_same_v<Tria, parallel::distributed::Triangulation<2>>)
  {
    // Nothing moved between ranks: exactly the refined coarse cell is rebuilt.
    EXPECT_EQ(reuse.treesRebuilt, 1u);
    EXPECT_EQ(reuse.treesKept, described.numberOfLocalTrees() - 1);
  }
}

TEST(DealIIForest, UnchangedTreesAreKeptDistributed)
{
  checkUnchangedTreesAreKept<parallel::distributed::Triangulation<2>>();
}

TEST(DealIIForest, UnchangedTreesAreKeptSerial)
{
  checkUnchangedTreesAreKept<SerialTriangulation<2>>();
}

TEST(DealIIForest, DistributedSolutionWithoutGhostsIsRefused)
{
  parallel::distributed::Triangulation<2> tria(MPI_COMM_WORLD);
  makeMesh(tria, 1);
  FE_Q<2> fe(1);
  DoFHandler<2> dofs(tria);
  dofs.distribute_dofs(fe);
  LinearAlgebra::distributed::Vector<double> noGhosts(dofs.locally_owned_dofs(), MPI_COMM_WORLD);
  canopy::DealIIForest<2> described(tria);
  const std::string message = refusal([&] { described.addCellAverages("u", dofs, noGhosts); });
  if (rankCount() > 1)
  {
    EXPECT_TRUE(says(message, "has no ghost entries")) << message;
  }
  else
  {
    EXPECT_EQ(message, ""); // one rank: every DoF is owned
  }
}

} // namespace

int main(int argc, char** argv)
{
  // MPI, and PETSc, p4est and libsc as deal.II initializes them.
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  ::testing::InitGoogleTest(&argc, argv);
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) != 0)
  {
    // One report, from rank 0; failures on other ranks still fail the exit code.
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int failed = RUN_ALL_TESTS();
  return Utilities::MPI::max(failed, MPI_COMM_WORLD);
}
