// Canopy::p4est against real p4est/p8est forests on several ranks: a brick of
// trees refined around a circle (sphere), 2:1 balanced and partitioned, so that
// p4est splits trees between ranks. Every quadrant p4est_iterate visits on a
// rank must be a visible leaf of that rank's grid, at the same place, with the
// same values, and nothing else; the values are read in place.
#include <canopy/HtgBuilder.h>
#include <canopy/P4estForest.h>

#include "HtgWalk.h"

#include <gtest/gtest.h>
#include <mpi.h>
#include <p4est_bits.h>
#include <p4est_extended.h>
#include <p4est_iterate.h>
#include <p8est_bits.h>
#include <p8est_extended.h>
#include <p8est_iterate.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <map>
#include <tuple>

namespace
{

/// What the simulation keeps in each quadrant's user_data.
struct QuadrantData
{
  double density;
  double velocity[3];
  std::int32_t tag;
};

/// p4est and p8est behind one interface, as the bridge itself is.
template <int D>
struct Pxest;

template <>
struct Pxest<2>
{
  using Forest = p4est_t;
  using Connectivity = p4est_connectivity_t;
  using Quadrant = p4est_quadrant_t;
  using VolumeInfo = p4est_iter_volume_info_t;
  using Described = canopy::P4estForest;
  static constexpr int MaxLevel = P4EST_MAXLEVEL;
  static constexpr int Children = P4EST_CHILDREN;
  static Connectivity* brick(bool periodic)
  {
    return p4est_connectivity_new_brick(4, 3, periodic, periodic);
  }
  static Forest* create(Connectivity* c, p4est_init_t init)
  {
    return p4est_new_ext(MPI_COMM_WORLD, c, 0, 2, 1, sizeof(QuadrantData), init, nullptr);
  }
  static void refine(Forest* f, p4est_refine_t r, p4est_init_t init)
  {
    p4est_refine(f, 1, r, init);
  }
  static void balance(Forest* f, p4est_init_t init) { p4est_balance(f, P4EST_CONNECT_FULL, init); }
  static void partition(Forest* f) { p4est_partition(f, 0, nullptr); }
  static void iterate(Forest* f, p4est_iter_volume_t v, void* user)
  {
    p4est_iterate(f, nullptr, user, v, nullptr, nullptr);
  }
  static void destroy(Forest* f, Connectivity* c)
  {
    p4est_destroy(f);
    p4est_connectivity_destroy(c);
  }
  static std::array<p4est_qcoord_t, 3> position(const Quadrant* q) { return {{q->x, q->y, 0}}; }
  static sc_array_t* quadrants(Forest* f, p4est_topidx_t t)
  {
    return &p4est_tree_array_index(f->trees, t)->quadrants;
  }
  static const double* vertex(const Connectivity* c, p4est_topidx_t t, int corner)
  {
    return c->vertices + 3 * c->tree_to_vertex[t * Children + corner];
  }
};

template <>
struct Pxest<3>
{
  using Forest = p8est_t;
  using Connectivity = p8est_connectivity_t;
  using Quadrant = p8est_quadrant_t;
  using VolumeInfo = p8est_iter_volume_info_t;
  using Described = canopy::P8estForest;
  static constexpr int MaxLevel = P8EST_MAXLEVEL;
  static constexpr int Children = P8EST_CHILDREN;
  static Connectivity* brick(bool periodic)
  {
    return p8est_connectivity_new_brick(2, 3, 2, periodic, periodic, periodic);
  }
  static Forest* create(Connectivity* c, p8est_init_t init)
  {
    return p8est_new_ext(MPI_COMM_WORLD, c, 0, 1, 1, sizeof(QuadrantData), init, nullptr);
  }
  static void refine(Forest* f, p8est_refine_t r, p8est_init_t init)
  {
    p8est_refine(f, 1, r, init);
  }
  static void balance(Forest* f, p8est_init_t init) { p8est_balance(f, P8EST_CONNECT_FULL, init); }
  static void partition(Forest* f) { p8est_partition(f, 0, nullptr); }
  static void iterate(Forest* f, p8est_iter_volume_t v, void* user)
  {
    p8est_iterate(f, nullptr, user, v, nullptr, nullptr, nullptr);
  }
  static void destroy(Forest* f, Connectivity* c)
  {
    p8est_destroy(f);
    p8est_connectivity_destroy(c);
  }
  static std::array<p4est_qcoord_t, 3> position(const Quadrant* q) { return {{q->x, q->y, q->z}}; }
  static sc_array_t* quadrants(Forest* f, p4est_topidx_t t)
  {
    return &p8est_tree_array_index(f->trees, t)->quadrants;
  }
  static const double* vertex(const Connectivity* c, p4est_topidx_t t, int corner)
  {
    return c->vertices + 3 * c->tree_to_vertex[t * Children + corner];
  }
};

/// Lower and upper corner of a quadrant in vertex coordinates.
template <int D, typename Forest>
std::array<double, 6> quadrantBox(const Forest* forest, p4est_topidx_t tree,
                                  const typename Pxest<D>::Quadrant* q)
{
  const double* lo = Pxest<D>::vertex(forest->connectivity, tree, 0);
  const double* hi = Pxest<D>::vertex(forest->connectivity, tree, Pxest<D>::Children - 1);
  const auto p = Pxest<D>::position(q);
  const double root = static_cast<double>(p4est_qcoord_t(1) << Pxest<D>::MaxLevel);
  const double length = static_cast<double>(p4est_qcoord_t(1) << (Pxest<D>::MaxLevel - q->level));
  std::array<double, 6> box{};
  for (int a = 0; a < 3; ++a)
  {
    if (a >= D)
    {
      box[2 * a] = box[2 * a + 1] = lo[a];
      continue;
    }
    const double size = hi[a] - lo[a];
    box[2 * a] = lo[a] + size * (p[a] / root);
    box[2 * a + 1] = lo[a] + size * ((p[a] + length) / root);
  }
  return box;
}

/// The field a quadrant carries: a function of where it is.
double densityAt(const std::array<double, 6>& box)
{
  return std::sin(box[0] + 0.3) * std::cos(0.7 * box[2]) + 0.1 * box[4] + 0.05 * box[1];
}

/// Refine near a circle (sphere) through the brick, to `maxLevel`.
template <int D>
int refineNearFront(typename Pxest<D>::Forest* forest, p4est_topidx_t tree,
                    typename Pxest<D>::Quadrant* q)
{
  constexpr int maxLevel = D == 2 ? 6 : 3;
  if (q->level >= maxLevel)
  {
    return 0;
  }
  const auto box = quadrantBox<D>(forest, tree, q);
  const double center[3] = {2.1, 1.4, 1.0};
  const double radius = 1.2;
  // Distance from the box to the front: refine boxes the circle crosses.
  double nearest = 0;
  double farthest = 0;
  for (int a = 0; a < D; ++a)
  {
    const double lo = box[2 * a] - center[a];
    const double hi = box[2 * a + 1] - center[a];
    const double near = lo > 0 ? lo : (hi < 0 ? -hi : 0);
    const double far = std::max(std::abs(lo), std::abs(hi));
    nearest += near * near;
    farthest += far * far;
  }
  return std::sqrt(nearest) <= radius && std::sqrt(farthest) >= radius;
}

template <int D>
void initializeQuadrant(typename Pxest<D>::Forest* forest, p4est_topidx_t tree,
                        typename Pxest<D>::Quadrant* q)
{
  auto* data = static_cast<QuadrantData*>(q->p.user_data);
  const auto box = quadrantBox<D>(forest, tree, q);
  data->density = densityAt(box);
  for (int a = 0; a < 3; ++a)
  {
    data->velocity[a] = box[2 * a] + 10.0 * a;
  }
  data->tag = q->level;
}

/// What p4est_iterate says this rank owns, keyed by box.
struct Reference
{
  std::map<std::array<double, 6>, std::tuple<double, double, int>> quadrants; // density, vx, level
  std::vector<double> densityByLocalIndex;
};

template <int D>
void recordQuadrant(typename Pxest<D>::VolumeInfo* info, void* user)
{
  auto* reference = static_cast<Reference*>(user);
  const auto* data = static_cast<const QuadrantData*>(info->quad->p.user_data);
  const auto box = quadrantBox<D>(info->p4est, info->treeid, info->quad);
  reference->quadrants[box] = {data->density, data->velocity[0], info->quad->level};
  reference->densityByLocalIndex.push_back(data->density);
}

/// A forest as the simulation in the issue: brick, refined at a front, balanced, partitioned.
template <int D>
struct Simulation
{
  typename Pxest<D>::Connectivity* connectivity;
  typename Pxest<D>::Forest* forest;
  explicit Simulation(bool periodic = false)
  {
    connectivity = Pxest<D>::brick(periodic);
    forest = Pxest<D>::create(connectivity, &initializeQuadrant<D>);
    Pxest<D>::refine(forest, &refineNearFront<D>, &initializeQuadrant<D>);
    Pxest<D>::balance(forest, &initializeQuadrant<D>);
    Pxest<D>::partition(forest);
  }
  ~Simulation() { Pxest<D>::destroy(forest, connectivity); }
  Reference reference()
  {
    Reference r;
    Pxest<D>::iterate(forest, &recordQuadrant<D>, &r);
    return r;
  }
};

int rankCount()
{
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

template <int D>
void checkEveryQuadrantIsALeafWithItsValues(bool periodic)
{
  Simulation<D> simulation(periodic);
  Reference reference = simulation.reference();
  typename Pxest<D>::Described described(simulation.forest);
  described.template addQuadrantField<double>("density", reference.densityByLocalIndex.data());
  described.template addUserDataField<double>("velocity", offsetof(QuadrantData, velocity), 3);
  // No ASSERT before the collectives below: a failing rank must not leave the others waiting.
  EXPECT_EQ(described.numberOfQuadrants(), reference.quadrants.size());
  auto htg = canopy::buildHyperTreeGrid(described.description());
  vtkDataArray* density = htg->GetCellData()->GetArray("density");
  vtkDataArray* velocity = htg->GetCellData()->GetArray("velocity");
  EXPECT_NE(density, nullptr);
  EXPECT_NE(velocity, nullptr);
  std::size_t leaves = 0;
  if (density && velocity)
    canopy::testing::forEachVisibleLeaf(
        htg,
        [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor)
        {
          ++leaves;
          std::array<double, 6> box;
          cursor->GetBounds(box.data());
          const auto found = reference.quadrants.find(box);
          ASSERT_NE(found, reference.quadrants.end())
              << "a leaf at (" << box[0] << ", " << box[2] << ", " << box[4]
              << ") is not a quadrant of this rank";
          const vtkIdType cell = cursor->GetGlobalNodeIndex();
          EXPECT_EQ(density->GetComponent(cell, 0), std::get<0>(found->second));
          EXPECT_EQ(velocity->GetComponent(cell, 0), std::get<1>(found->second));
          EXPECT_EQ(static_cast<int>(cursor->GetLevel()), std::get<2>(found->second));
        });
  EXPECT_EQ(leaves, reference.quadrants.size());
  // Every quadrant of the whole forest on exactly one rank.
  long local = static_cast<long>(leaves);
  long global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(global, static_cast<long>(simulation.forest->global_num_quadrants));
  // With more than one rank, p4est splits some tree: absent parts are exercised.
  int split = 0;
  for (const auto& tree : described.description().trees)
  {
    split |= tree.absent != nullptr;
  }
  int anySplit = 0;
  MPI_Allreduce(&split, &anySplit, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  if (rankCount() > 1)
  {
    EXPECT_EQ(anySplit, 1) << "the partition should split a tree between ranks";
  }
}

TEST(P4estForest, EveryQuadrantIsAVisibleLeafWithItsValues2D)
{
  checkEveryQuadrantIsALeafWithItsValues<2>(false);
}

TEST(P4estForest, PeriodicBrick2D)
{
  checkEveryQuadrantIsALeafWithItsValues<2>(true);
}

TEST(P8estForest, EveryOctantIsAVisibleLeafWithItsValues3D)
{
  checkEveryQuadrantIsALeafWithItsValues<3>(false);
}

template <int D>
void checkValuesAreReadInPlace()
{
  Simulation<D> simulation;
  Reference reference = simulation.reference();
  if (reference.quadrants.empty())
  {
    GTEST_SKIP() << "this rank owns no quadrant";
  }
  typename Pxest<D>::Described described(simulation.forest);
  described.template addQuadrantField<double>("density", reference.densityByLocalIndex.data());
  described.template addUserDataField<double>("density_in_quadrant",
                                              offsetof(QuadrantData, density));
  auto htg = canopy::buildHyperTreeGrid(described.description());
  // The first local quadrant: find its cell by its box.
  typename Pxest<D>::Quadrant* first = nullptr;
  p4est_topidx_t firstTree = simulation.forest->first_local_tree;
  for (p4est_topidx_t t = firstTree; t <= simulation.forest->last_local_tree && !first; ++t)
  {
    sc_array_t* quadrants = Pxest<D>::quadrants(simulation.forest, t);
    if (quadrants->elem_count > 0)
    {
      first = static_cast<typename Pxest<D>::Quadrant*>(sc_array_index(quadrants, 0));
      firstTree = t;
    }
  }
  ASSERT_NE(first, nullptr);
  const auto box = quadrantBox<D>(simulation.forest, firstTree, first);
  vtkIdType cell = -1;
  canopy::testing::forEachVisibleLeaf(htg,
                                      [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor)
                                      {
                                        std::array<double, 6> b;
                                        cursor->GetBounds(b.data());
                                        if (b == box)
                                        {
                                          cell = cursor->GetGlobalNodeIndex();
                                        }
                                      });
  ASSERT_GE(cell, 0);
  // The simulation changes its values after the grid was built: the grid sees them.
  reference.densityByLocalIndex[0] = 12345.5;
  static_cast<QuadrantData*>(first->p.user_data)->density = -777.25;
  EXPECT_EQ(htg->GetCellData()->GetArray("density")->GetComponent(cell, 0), 12345.5);
  EXPECT_EQ(htg->GetCellData()->GetArray("density_in_quadrant")->GetComponent(cell, 0), -777.25);
}

TEST(P4estForest, ValuesAreReadInPlace2D)
{
  checkValuesAreReadInPlace<2>();
}

TEST(P8estForest, ValuesAreReadInPlace3D)
{
  checkValuesAreReadInPlace<3>();
}

template <typename Throwing>
std::string invalidMessage(Throwing&& action)
{
  try
  {
    action();
  }
  catch (const canopy::InvalidForest& error)
  {
    return error.what();
  }
  return "";
}

TEST(P4estForest, NonBrickConnectivitiesAreRefusedNamingWhy)
{
  // The disk: five trees, four of them trapezoids around a square.
  p4est_connectivity_t* disk = p4est_connectivity_new_disk(0, 0);
  p4est_t* forest = p4est_new(MPI_COMM_WORLD, disk, 0, nullptr, nullptr);
  const std::string message = invalidMessage([&] { canopy::P4estForest described(forest); });
  EXPECT_NE(message.find("not an unrotated axis-aligned box"), std::string::npos) << message;
  p4est_destroy(forest);
  p4est_connectivity_destroy(disk);

  // Six trees around a point, turned against each other; and a band out of the plane.
  for (p4est_connectivity_t* connectivity :
       {p4est_connectivity_new_star(), p4est_connectivity_new_moebius()})
  {
    forest = p4est_new(MPI_COMM_WORLD, connectivity, 0, nullptr, nullptr);
    const std::string why = invalidMessage([&] { canopy::P4estForest described(forest); });
    EXPECT_NE(why.find("p4est forest: tree"), std::string::npos) << why;
    p4est_destroy(forest);
    p4est_connectivity_destroy(connectivity);
  }
}

TEST(P8estForest, RotatedCubesAreRefused)
{
  p8est_connectivity_t* rotcubes = p8est_connectivity_new_rotcubes();
  p8est_t* forest = p8est_new(MPI_COMM_WORLD, rotcubes, 0, nullptr, nullptr);
  const std::string message = invalidMessage([&] { canopy::P8estForest described(forest); });
  EXPECT_FALSE(message.empty());
  EXPECT_NE(message.find("p4est forest:"), std::string::npos) << message;
  p8est_destroy(forest);
  p8est_connectivity_destroy(rotcubes);
}

TEST(P4estForest, ADescriptionOfAChangedForestIsRefused)
{
  Simulation<2> simulation;
  canopy::P4estForest described(simulation.forest);
  EXPECT_NO_THROW(described.description());
  // The simulation adapts its mesh and forgets to describe it again.
  p4est_refine(
      simulation.forest, 0,
      [](p4est_t*, p4est_topidx_t, p4est_quadrant_t* q) -> int { return q->level < 7; },
      initializeQuadrant<2>);
  const std::string message = invalidMessage([&] { described.description(); });
  EXPECT_NE(message.find("changed since it was described"), std::string::npos) << message;
}

TEST(P4estForest, UserDataFieldsMustFitInTheQuadrantData)
{
  Simulation<2> simulation;
  canopy::P4estForest described(simulation.forest);
  const std::string message = invalidMessage(
      [&] { described.addUserDataField<double>("too_far", sizeof(QuadrantData) - 4); });
  EXPECT_NE(message.find("do not fit"), std::string::npos) << message;
  const std::string duplicate = invalidMessage(
      [&]
      {
        described.addUserDataField<double>("density", offsetof(QuadrantData, density));
        described.addUserDataField<double>("density", offsetof(QuadrantData, density));
      });
  EXPECT_NE(duplicate.find("already described"), std::string::npos) << duplicate;
}

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  // p4est's own logging at errors only; sc's MPI abort handler stays p4est's.
  sc_init(MPI_COMM_WORLD, 1, 1, nullptr, SC_LP_ERROR);
  p4est_init(nullptr, SC_LP_ERROR);
  ::testing::InitGoogleTest(&argc, argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0)
  {
    // One report, from rank 0; failures on other ranks still fail the exit code.
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  int failed = RUN_ALL_TESTS();
  int anyFailed = 0;
  MPI_Allreduce(&failed, &anyFailed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  sc_finalize();
  MPI_Finalize();
  return anyFailed;
}
