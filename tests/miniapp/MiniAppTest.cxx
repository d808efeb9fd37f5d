// The mini-app's numerics and mesh, on one MPI rank: conservation, faces seen
// the same from both sides (neighbours across levels and trees), refinement
// following the objects and coarsening behind them.
#include "AmrForest.h"
#include "MiniAppOptions.h"
#include "Simulation.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <map>
#include <tuple>
#include <utility>

namespace
{

miniamr::MiniAppOptions optionsFor(int dimension, int branchFactor, int roots, int maxLevel)
{
  miniamr::MiniAppOptions o;
  o.dimension = dimension;
  o.branchFactor = branchFactor;
  o.roots = {{roots, roots, roots}};
  o.maxLevel = maxLevel;
  o.noInSitu = true;
  miniamr::MovingObject sphere;
  sphere.center = {{0.3, 0.35, 0.4}};
  sphere.radius = 0.15;
  sphere.velocity = {{1.0, 0.5, 0.25}};
  o.objects = {sphere};
  return o;
}

struct Case
{
  int dimension;
  int branchFactor;
  int roots;
  int maxLevel;
  double diffusion;
};

class Conservation : public ::testing::TestWithParam<Case>
{
};

TEST_P(Conservation, TotalMassChangesOnlyByRoundOff)
{
  const Case c = GetParam();
  auto options = optionsFor(c.dimension, c.branchFactor, c.roots, c.maxLevel);
  options.diffusion = c.diffusion;
  miniamr::Simulation simulation(options, MPI_COMM_WORLD);
  const double initial = simulation.totalMass();
  ASSERT_GT(initial, 0.0);
  const auto leavesBefore = simulation.globalLeaves();
  for (int step = 0; step < 12; ++step)
  {
    simulation.advance();
    EXPECT_LT(std::abs(simulation.totalMass() - initial) / initial, 1e-12) << "step " << step;
  }
  // The mesh did adapt (the sphere moved), so regridding was exercised too.
  EXPECT_NE(simulation.globalLeaves(), leavesBefore);
}

INSTANTIATE_TEST_SUITE_P(MiniApp, Conservation,
                         ::testing::Values(Case{2, 2, 8, 5, 0.0}, Case{2, 3, 6, 3, 0.0},
                                           Case{2, 2, 8, 5, 0.002}, Case{3, 2, 4, 3, 0.0},
                                           Case{3, 3, 3, 2, 0.001}));

/// Every face of every leaf, seen from the leaf across, comes back with the
/// same area: the flux both sides compute is the same face.
TEST(MiniAppMesh, FacesAgreeFromBothSides)
{
  for (auto [dimension, branchFactor] : {std::pair{2, 2}, std::pair{3, 2}, std::pair{2, 3}})
  {
    miniamr::Simulation simulation(
        optionsFor(dimension, branchFactor, 3, dimension == 3 || branchFactor == 3 ? 3 : 5),
        MPI_COMM_WORLD);
    simulation.advance();
    const auto& forest = simulation.forest();
    std::vector<miniamr::AmrForest::FaceNeighbour> across, back;
    std::size_t faces = 0;
    std::size_t levelJumps = 0;
    for (const auto& tree : forest.trees())
      for (const auto& node : tree.nodes)
      {
        if (node.firstChild >= 0)
          continue;
        for (int axis = 0; axis < dimension; ++axis)
          for (int side = -1; side <= 1; side += 2)
          {
            forest.faceNeighbours(node.key, axis, side, across);
            ASSERT_FALSE(across.empty());
            double area = 0;
            for (const auto& neighbour : across)
            {
              area += neighbour.area;
              ASSERT_LT(neighbour.node->firstChild, 0) << "neighbours are leaves";
              levelJumps += neighbour.node->key.level != node.key.level;
              forest.faceNeighbours(neighbour.node->key, axis, -side, back);
              int found = 0;
              for (const auto& b : back)
                if (b.node->key == node.key)
                {
                  ++found;
                  EXPECT_EQ(b.area, neighbour.area);
                  // The flux's velocity is read at the same point to the last bit,
                  // also across the periodic boundary and for sizes like 1/3.
                  EXPECT_EQ(forest.faceCenter(b, axis), forest.faceCenter(neighbour, axis));
                }
              EXPECT_EQ(found, 1) << "the face is seen once from the other side";
              ++faces;
            }
            // The finer leaves across cover this leaf's face exactly when they are
            // finer; a coarser or equal leaf's face is measured on this leaf.
            double own = 1.0;
            for (int a = 0; a < dimension; ++a)
              if (a != axis)
                own *= forest.cellSize(a, node.key.level);
            EXPECT_NEAR(area, own, 1e-15);
          }
      }
    EXPECT_GT(faces, 1000u);
    EXPECT_GT(levelJumps, 100u) << "the test must cross refinement levels";
  }
}

double distanceToSurface(const miniamr::MovingObject& sphere, const std::array<double, 3>& x)
{
  double r2 = 0;
  for (int a = 0; a < 2; ++a)
    r2 += (x[a] - sphere.center[a]) * (x[a] - sphere.center[a]);
  return std::abs(std::sqrt(r2) - sphere.radius);
}

/// A sphere crossing the domain: the leaves its surface crosses are refined
/// to the finest level at every step, and
/// where it was, far from the blob, the mesh is coarse again.
TEST(MiniAppMesh, RefinementFollowsTheObjectAndCoarsensBehindIt)
{
  auto options = optionsFor(2, 2, 8, 6);
  options.objects[0].center = {{0.2, 0.2, 0.0}};
  options.objects[0].radius = 0.1;
  options.objects[0].velocity = {{1.0, 0.0, 0.0}}; // 0.01 per step along x
  options.velocity = "uniform";
  options.uniformVelocity = {{0.0, 0.0, 0.0}}; // the blob stays where it is (y ~ 0.72)
  miniamr::Simulation simulation(options, MPI_COMM_WORLD);
  for (int step = 0; step < 40; ++step)
  {
    simulation.advance();
    const auto sphere = simulation.objects().at(0, simulation.objectClock());
    std::size_t crossing = 0;
    for (const auto& tree : simulation.forest().trees())
      for (const auto& node : tree.nodes)
      {
        if (node.firstChild >= 0)
          continue;
        auto low = simulation.forest().cellLow(node.key);
        std::array<double, 3> high = low;
        for (int a = 0; a < 2; ++a)
          high[a] += simulation.forest().cellSize(a, node.key.level);
        if (simulation.objects().surfaceCrosses(low, high, simulation.objectClock()))
        {
          ++crossing;
          EXPECT_EQ(node.key.level, options.maxLevel)
              << "step " << step << ": a leaf on the surface is too coarse";
        }
      }
    EXPECT_GT(crossing, 20u);
    (void)sphere;
  }
  // The sphere started at x = 0.2 and is now at x = 0.6: around its start, away
  // from its current surface and from the blob, no fine leaf is left.
  miniamr::MovingObject start = options.objects[0];
  const auto now = simulation.objects().at(0, simulation.objectClock());
  ASSERT_NEAR(now.center[0], 0.6, 1e-12);
  std::size_t checked = 0;
  for (const auto& tree : simulation.forest().trees())
    for (const auto& node : tree.nodes)
    {
      if (node.firstChild >= 0)
        continue;
      const auto c = simulation.forest().cellCenter(node.key);
      if (distanceToSurface(start, c) < 0.02 && distanceToSurface(now, c) > 0.15 && c[1] < 0.4)
      {
        ++checked;
        EXPECT_LE(node.key.level, 2) << "left behind at level " << node.key.level;
      }
    }
  EXPECT_GT(checked, 0u);
}

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  const int result = RUN_ALL_TESTS();
  MPI_Finalize();
  return result;
}

TEST(MiniAppOptions, ARootGridThatCannotFitIsRefusedUpFront)
{
  // 65536 x 65536 roots used to be accepted and die of bad_alloc after 35 s.
  const char* argv[] = {"canopy_miniamr", "--roots", "65536", "--max-level", "0"};
  try
  {
    miniamr::parseOptions(5, const_cast<char**>(argv));
    FAIL() << "--roots 65536 was accepted";
  }
  catch (const std::invalid_argument& error)
  {
    EXPECT_NE(std::string(error.what()).find("4294967296 root cells need about"), std::string::npos)
        << error.what();
  }
}
