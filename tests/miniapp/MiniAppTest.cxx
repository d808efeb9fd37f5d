// The mini-app's numerics and mesh, on one MPI rank: conservation, faces seen
// the same from both sides (neighbours across levels and trees), refinement
// following the objects and coarsening behind them, the exact solution of the
// accuracy mode (its order of convergence: miniapp.exact_solution_order_np*), the
// blocks of --blocks (in situ: miniapp.blocks_*).
#include "AmrForest.h"
#include "ExactSolution.h"
#include "MiniAppOptions.h"
#include "Simulation.h"

#include <canopy/ForestValidation.h>

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

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

/// The periodic Gaussian at a point, summed directly over its images: an
/// evaluation independent of TranslatedGaussian's erf sums.
double periodicGaussianAt(const std::array<double, 3>& x, int dimension,
                          const std::array<double, 3>& center, double sigma)
{
  double value = 1.0;
  for (int a = 0; a < dimension; ++a)
  {
    double sum = 0;
    for (int k = -4; k <= 4; ++k)
    {
      const double s = x[a] - center[a] + k;
      sum += std::exp(-s * s / (2 * sigma * sigma));
    }
    value *= sum;
  }
  return value;
}

/// The exact cell averages against 10-point Gauss-Legendre quadrature of the
/// translated, periodic profile, on cells across the periodic boundary and after
/// the center has wrapped around.
TEST(MiniAppExactSolution, CellAveragesMatchQuadratureOfTheTranslatedProfile)
{
  // numpy.polynomial.legendre.leggauss(10), the positive half, on [-1, 1].
  const double nodes[5] = {0.14887433898163122, 0.4333953941292472, 0.6794095682990244,
                           0.8650633666889845, 0.9739065285171717};
  const double weights[5] = {0.295524224714753, 0.2692667193099965, 0.219086362515982,
                             0.14945134915058036, 0.06667134430868807};
  std::vector<std::pair<double, double>> rule; // on [0, 1]
  for (int i = 0; i < 5; ++i)
    for (int sign = -1; sign <= 1; sign += 2)
      rule.emplace_back(0.5 + 0.5 * sign * nodes[i], 0.5 * weights[i]);
  // The constants are right: the rule integrates degree 19 exactly.
  double moment = 0;
  for (const auto& [x, w] : rule)
    moment += w * std::pow(x, 19);
  ASSERT_NEAR(moment, 1.0 / 20, 1e-15);

  const std::array<double, 3> center{{0.3, 0.4, 0.45}};
  const double sigma = 0.15;
  const std::array<double, 3> velocity{{1.0, -0.5, 0.25}};
  const miniamr::TranslatedGaussian exact(2, center, sigma, velocity);
  const double time = 0.9; // the center has crossed x = 1 and y = 0
  const std::array<double, 3> moved{
      {center[0] + velocity[0] * time, center[1] + velocity[1] * time, 0.0}};
  const double h = 1.0 / 16;
  for (auto [i, j] : {std::pair{0, 0}, std::pair{15, 3}, std::pair{3, 15}, std::pair{7, 9}})
  {
    const std::array<double, 3> low{{i * h, j * h, 0.0}};
    double quadrature = 0;
    for (const auto& [x, wx] : rule)
      for (const auto& [y, wy] : rule)
        quadrature +=
            wx * wy * periodicGaussianAt({{low[0] + x * h, low[1] + y * h, 0.0}}, 2, moved, sigma);
    EXPECT_NEAR(exact.cellAverage(low, {{h, h, 1.0}}, time), quadrature, 1e-13)
        << "cell " << i << ", " << j;
  }
}

/// Summed over a mesh, the cell averages give the profile's integral over the
/// periodic domain, (2 pi sigma^2)^(d/2): no mass lost to the periodic images.
TEST(MiniAppExactSolution, CellAveragesSumToTheIntegral)
{
  for (int dimension : {2, 3})
  {
    const auto exact = miniamr::TranslatedGaussian::standard(dimension, {{1.0, 1.0, 1.0}});
    const int cells = 12;
    const double h = 1.0 / cells;
    double total = 0;
    for (int k = 0; k < (dimension == 3 ? cells : 1); ++k)
      for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i)
          total += exact.cellAverage({{i * h, j * h, k * h}}, {{h, h, h}}, 0.37) *
                   std::pow(h, dimension);
    EXPECT_NEAR(total, exact.integral(), 1e-14) << dimension << "D";
    EXPECT_NEAR(exact.integral(), std::pow(2 * std::acos(-1.0) * 0.15 * 0.15, 0.5 * dimension),
                1e-15);
  }
}

miniamr::MiniAppOptions parse(std::vector<std::string> arguments)
{
  arguments.insert(arguments.begin(), "canopy_miniamr");
  std::vector<char*> argv;
  for (auto& argument : arguments)
    argv.push_back(argument.data());
  return miniamr::parseOptions(static_cast<int>(argv.size()), argv.data());
}

/// --exact-solution runs on a fixed, uniform mesh at the finest level, starts
/// from the exact cell averages and lands on --end-time.
TEST(MiniAppExactSolution, FixedUniformMeshFromTheExactCellAverages)
{
  const auto options = parse({"--exact-solution", "gaussian", "--roots", "4", "--max-level", "2",
                              "--end-time", "0.1", "--no-insitu"});
  EXPECT_TRUE(options.objects.empty());
  EXPECT_EQ(options.velocity, "uniform");
  miniamr::Simulation simulation(options, MPI_COMM_WORLD);
  const auto exact = miniamr::TranslatedGaussian::standard(2, options.uniformVelocity);
  EXPECT_NEAR(simulation.totalMass(), exact.integral(), 1e-14);
  const auto start = simulation.errorsAgainstExact();
  EXPECT_EQ(start.l1, 0.0);
  EXPECT_EQ(start.max, 0.0);
  ASSERT_GT(simulation.plannedSteps(), 1);
  for (int step = 0; step < simulation.plannedSteps(); ++step)
  {
    simulation.advance();
    ASSERT_EQ(simulation.globalLeaves(), 16 * 16) << "step " << step;
    for (const auto& tree : simulation.forest().trees())
      for (const auto& node : tree.nodes)
      {
        if (node.firstChild < 0)
        {
          ASSERT_EQ(node.key.level, 2);
        }
      }
  }
  EXPECT_NEAR(simulation.time(), 0.1, 1e-15);
  const auto end = simulation.errorsAgainstExact();
  EXPECT_GT(end.l1, 0.0);
  EXPECT_GE(end.max, end.l1); // the L1 error is a volume average over the unit domain
}

TEST(MiniAppExactSolution, ContradictoryOptionsAreRefused)
{
  for (const auto& extra :
       std::vector<std::vector<std::string>>{{"--object", "sphere:0.5,0.5,0.1,0,0"},
                                             {"--diffusion", "0.001"},
                                             {"--velocity", "swirl"},
                                             {"--steps", "3", "--end-time", "0.1"}})
  {
    std::vector<std::string> arguments{"--exact-solution", "gaussian"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    EXPECT_THROW(parse(arguments), std::invalid_argument) << extra[0];
  }
  EXPECT_THROW(parse({"--exact-solution", "square"}), std::invalid_argument);
  const auto given = parse({"--exact-solution", "gaussian", "--velocity", "uniform:-1,0.5"});
  EXPECT_EQ(given.uniformVelocity[0], -1.0);
  EXPECT_EQ(given.uniformVelocity[1], 0.5);
}

/// --blocks N: 0 (off) or a power of the branch factor from the branch factor to 64;
/// the blocks' cells count towards the finest cells per axis.
TEST(MiniAppBlocks, OnlyPowersOfTheBranchFactorAreAccepted)
{
  EXPECT_EQ(parse({}).blocks, 0);
  for (const std::string n : {"0", "2", "4", "8", "16", "64"})
    EXPECT_EQ(parse({"--blocks", n}).blocks, std::stoi(n));
  for (const std::string n : {"1", "3", "6", "12", "128", "-8", "8.5"})
    EXPECT_THROW(parse({"--blocks", n}), std::invalid_argument) << n;
  EXPECT_EQ(parse({"--branch-factor", "3", "--blocks", "9"}).blocks, 9);
  EXPECT_THROW(parse({"--branch-factor", "3", "--blocks", "8"}), std::invalid_argument);
  // 64 roots x 2^10 x 32 = 2^21 finest cells per axis: too many with the blocks' cells.
  EXPECT_NO_THROW(parse({"--roots", "64", "--max-level", "10"}));
  EXPECT_THROW(parse({"--roots", "64", "--max-level", "10", "--blocks", "32"}),
               std::invalid_argument);
}

/// With --blocks the simulation keeps a block per leaf, as a block-structured code
/// does: the description Canopy gets is a valid block forest of the expected size,
/// every block's scalar averages to its leaf's value and stays within the range of
/// the leaf's and its face neighbours' values, the velocity is the swirl at each
/// cell's centre, level and rank the leaf's, and the ghost cells are NaN.
TEST(MiniAppBlocks, BlocksHoldTheLeavesFieldsAtTheirCellCentres)
{
  constexpr double pi = 3.14159265358979323846;
  for (auto [dimension, branchFactor, n] :
       {std::tuple{2, 2, 8}, std::tuple{3, 2, 4}, std::tuple{2, 3, 9}})
  {
    SCOPED_TRACE(std::to_string(dimension) + "D, branch factor " + std::to_string(branchFactor) +
                 ", blocks of " + std::to_string(n));
    auto options = optionsFor(dimension, branchFactor, 4, branchFactor == 2 ? 3 : 2);
    options.blocks = n;
    miniamr::Simulation simulation(options, MPI_COMM_WORLD);
    simulation.sampleBlocks();
    simulation.advance();
    // The blocks are sampled for one step: described before they are sampled again,
    // they would be stale.
    EXPECT_THROW(simulation.describeForCanopy(), std::logic_error);
    simulation.sampleBlocks();
    const auto description = simulation.describeForCanopy();
    EXPECT_EQ(description.blockCellsPerSide, n);
    const auto counts = canopy::validateForest(description);
    const auto leaves = static_cast<std::size_t>(simulation.globalLeaves());
    std::size_t children = 1, cells = 1;
    for (int a = 0; a < dimension; ++a)
    {
      children *= static_cast<std::size_t>(branchFactor);
      cells *= static_cast<std::size_t>(n);
    }
    std::size_t inside = 0; // cells of one block at all its levels below the leaf
    for (std::size_t level = children; level <= cells; level *= children)
      inside += level;
    EXPECT_EQ(counts.numberOfBlocks, leaves);
    EXPECT_EQ(counts.totalCells,
              static_cast<std::size_t>(simulation.globalNodes()) + leaves * inside);
    ASSERT_EQ(simulation.ownBlocks(), leaves);

    const std::size_t withGhosts = simulation.blockValuesPerVariable();
    ASSERT_EQ(withGhosts, static_cast<std::size_t>(std::pow(n + 4, dimension)));
    const auto& forest = simulation.forest();
    std::size_t index = 0;
    std::vector<miniamr::AmrForest::FaceNeighbour> across;
    for (std::size_t t = 0; t < forest.trees().size(); ++t)
      for (const auto& node : forest.trees()[t].nodes)
      {
        if (node.firstChild >= 0)
          continue;
        const double u = simulation.valueOf(static_cast<std::int32_t>(t), node.leaf);
        double low = u, high = u;
        for (int axis = 0; axis < dimension; ++axis)
          for (int side = -1; side <= 1; side += 2)
          {
            forest.faceNeighbours(node.key, axis, side, across);
            for (const auto& neighbour : across)
            {
              const double v = simulation.valueOf(neighbour.leaf.tree, neighbour.node->leaf);
              low = std::min(low, v);
              high = std::max(high, v);
            }
          }
        const auto lowCorner = forest.cellLow(node.key);
        double sum = 0;
        int outside = 0;
        double velocityError = 0;
        bool levelAndRank = true;
        for (int k = 0; k < (dimension == 3 ? n : 1); ++k)
          for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
            {
              const double scalar = simulation.blockValue(index, 0, i, j, k);
              sum += scalar;
              outside += scalar < low - 1e-15 || scalar > high + 1e-15;
              const int cell[3] = {i, j, k};
              double x[3] = {0, 0, 0};
              for (int a = 0; a < dimension; ++a)
                x[a] = lowCorner[a] + (cell[a] + 0.5) * (forest.cellSize(a, node.key.level) / n);
              const double sx = std::sin(pi * x[0]), sy = std::sin(pi * x[1]);
              const double swirl[3] = {sx * sx * std::sin(2 * pi * x[1]),
                                       -sy * sy * std::sin(2 * pi * x[0]),
                                       dimension == 3 ? 0.5 : 0.0};
              for (int c = 0; c < 3; ++c)
                velocityError =
                    std::max(velocityError,
                             std::abs(simulation.blockValue(index, 1 + c, i, j, k) - swirl[c]));
              levelAndRank = levelAndRank &&
                             simulation.blockValue(index, 4, i, j, k) == node.key.level &&
                             simulation.blockValue(index, 5, i, j, k) == 0.0;
            }
        ASSERT_NEAR(sum / static_cast<double>(cells), u, 1e-14) << "leaf " << index;
        ASSERT_EQ(outside, 0) << "leaf " << index;
        ASSERT_LT(velocityError, 1e-15) << "leaf " << index;
        ASSERT_TRUE(levelAndRank) << "leaf " << index;
        const double* block = simulation.blockArray(index);
        std::size_t nan = 0;
        for (std::size_t v = 0; v < 6 * withGhosts; ++v)
          nan += std::isnan(block[v]);
        ASSERT_EQ(nan, 6 * (withGhosts - cells)) << "leaf " << index << ": ghosts only";
        ++index;
      }
    EXPECT_EQ(index, leaves);
  }
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
