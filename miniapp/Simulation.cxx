#include "Simulation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <tuple>

namespace miniamr
{
namespace
{

constexpr double Pi = 3.14159265358979323846;

std::vector<double> uniformPoints(int cells)
{
  std::vector<double> points(static_cast<std::size_t>(cells) + 1);
  for (int i = 0; i <= cells; ++i)
    points[static_cast<std::size_t>(i)] = static_cast<double>(i) / cells;
  return points;
}

} // namespace

Simulation::Simulation(const MiniAppOptions& options, MPI_Comm communicator)
    : Options(options), Communicator(communicator),
      Forest(options.dimension, options.branchFactor, options.roots, options.maxLevel),
      Objects(options.objects, options.dimension)
{
  if (!Options.exactSolution.empty())
    Exact = TranslatedGaussian::standard(Options.dimension, Options.uniformVelocity);
  MPI_Comm_rank(Communicator, &Rank);
  MPI_Comm_size(Communicator, &Size);
  RootX = uniformPoints(Forest.roots()[0]);
  RootY = uniformPoints(Forest.roots()[1]);
  RootZ = Options.dimension == 3 ? uniformPoints(Forest.roots()[2]) : std::vector<double>{0.0};

  // Start from contiguous, equal shares of roots; refine level by level around
  // the objects and the initial blob, sampling the initial condition each time.
  const auto trees = Forest.trees().size();
  Owner.resize(trees);
  for (std::size_t t = 0; t < trees; ++t)
    Owner[t] = static_cast<int>(t * static_cast<std::size_t>(Size) / trees);
  afterTopologyChange();
  sampleInitialValues();
  for (int level = 0; level < Options.maxLevel; ++level)
    regrid(true, false);
  repartitionIfImbalanced(true);
  Repartitions = 0;
  Dt = computeTimeStep();
  if (Options.endTime > 0)
  {
    // Shorten the step so that a whole number of them lands on the end time
    // (the margin keeps an exact quotient from rounding up to one step more).
    Options.steps = static_cast<int>(std::ceil(Options.endTime / Dt * (1 - 1e-12)));
    Dt = Options.endTime / Options.steps;
  }
}

std::array<double, 3> Simulation::cellSizes(int level) const
{
  std::array<double, 3> size{{1.0, 1.0, 1.0}};
  for (int a = 0; a < Options.dimension; ++a)
    size[a] = Forest.cellSize(a, level);
  return size;
}

double Simulation::initialCellValue(const NodeKey& key) const
{
  if (Exact)
    return Exact->cellAverage(Forest.cellLow(key), cellSizes(key.level), 0.0);
  return initialValue(Forest.cellCenter(key));
}

void Simulation::sampleInitialValues()
{
  forEachOwnLeaf([this](const Tree::Node& node, std::size_t index)
                 { Scalar[index] = initialCellValue(node.key); });
}

Simulation::ExactErrors Simulation::errorsAgainstExact() const
{
  if (!Exact)
    throw std::logic_error("errorsAgainstExact needs --exact-solution");
  ExactErrors local;
  forEachOwnLeaf(
      [&](const Tree::Node& node, std::size_t index)
      {
        const double exact =
            Exact->cellAverage(Forest.cellLow(node.key), cellSizes(node.key.level), Time);
        const double error = std::abs(Scalar[index] - exact);
        local.l1 += error * Forest.cellVolume(node.key.level);
        local.max = std::max(local.max, error);
      });
  ExactErrors global;
  MPI_Allreduce(&local.l1, &global.l1, 1, MPI_DOUBLE, MPI_SUM, Communicator);
  MPI_Allreduce(&local.max, &global.max, 1, MPI_DOUBLE, MPI_MAX, Communicator);
  return global;
}

double Simulation::initialValue(const std::array<double, 3>& x) const
{
  // A smooth blob the swirl carries around.
  const double center[3] = {0.5, 0.72, 0.5};
  double r2 = 0;
  for (int a = 0; a < Options.dimension; ++a)
    r2 += (x[a] - center[a]) * (x[a] - center[a]);
  return std::exp(-r2 / (0.12 * 0.12));
}

std::array<double, 3> Simulation::velocityAt(const std::array<double, 3>& x) const
{
  if (Options.velocity == "uniform")
    return Options.uniformVelocity;
  // LeVeque's swirl: divergence free, no flow through the walls.
  const double sx = std::sin(Pi * x[0]);
  const double sy = std::sin(Pi * x[1]);
  return {{sx * sx * std::sin(2 * Pi * x[1]), -sy * sy * std::sin(2 * Pi * x[0]),
           Options.dimension == 3 ? 0.5 : 0.0}};
}

double Simulation::computeTimeStep() const
{
  double finest = 1.0;
  for (int a = 0; a < Options.dimension; ++a)
    finest = std::min(finest, Forest.cellSize(a, Options.maxLevel));
  double speed = 0;
  if (Options.velocity == "uniform")
    for (int a = 0; a < Options.dimension; ++a)
      speed += std::abs(Options.uniformVelocity[a]);
  else
    speed = Options.dimension == 3 ? 2.5 : 2.0;
  // Upwind advection and explicit diffusion together: their rates add up.
  const double rate =
      speed / finest + 2.0 * Options.dimension * Options.diffusion / (finest * finest);
  // Nothing moves or diffuses: any step is stable; take one a unit speed would allow.
  return rate > 0 ? Options.cfl / rate : Options.cfl * finest;
}

double Simulation::valueAcross(const AmrForest::FaceNeighbour& neighbour) const
{
  const auto tree = static_cast<std::size_t>(neighbour.leaf.tree);
  if (Owner[tree] == Rank)
    return Scalar[static_cast<std::size_t>(LeafOffset[tree] + neighbour.node->leaf)];
  return Halo.ghost(neighbour.leaf.tree, neighbour.node->leaf);
}

double Simulation::valueOf(std::int32_t tree, std::int32_t leaf) const
{
  const auto t = static_cast<std::size_t>(tree);
  return Owner[t] == Rank ? Scalar[static_cast<std::size_t>(LeafOffset[t] + leaf)]
                          : std::numeric_limits<double>::quiet_NaN();
}

void Simulation::advance()
{
  Halo.exchange(Communicator, Scalar);
  std::vector<double> next(Scalar.size());
  std::vector<AmrForest::FaceNeighbour> across;
  forEachOwnLeaf(
      [&](const Tree::Node& node, std::size_t index)
      {
        const double u = Scalar[index];
        double outflow = 0.0;
        // Each leaf sums the fluxes through its own faces; both sides of a face
        // compute it from the finer cell's geometry, so they agree to the last bit
        // (conservation), and the result does not depend on the partition.
        for (int axis = 0; axis < Options.dimension; ++axis)
          for (int side = -1; side <= 1; side += 2)
          {
            Forest.faceNeighbours(node.key, axis, side, across);
            for (const auto& neighbour : across)
            {
              const double v = valueAcross(neighbour);
              const double normal = velocityAt(Forest.faceCenter(neighbour, axis))[axis] * side;
              double flux = normal * (normal > 0 ? u : v) * neighbour.area;
              if (Options.diffusion > 0)
              {
                const double distance = 0.5 * (Forest.cellSize(axis, node.key.level) +
                                               Forest.cellSize(axis, neighbour.node->key.level));
                flux += -Options.diffusion * (v - u) / distance * neighbour.area;
              }
              outflow += flux;
            }
          }
        next[index] = u - Dt * outflow / Forest.cellVolume(node.key.level);
      });
  Scalar.swap(next);
  Time += Dt;
  Step += 1;
  // The exact solution is compared on a fixed mesh: no regrid, no transfer error.
  if (!Exact && Step % Options.regridEvery == 0)
  {
    // Gradients refine or coarsen one level per regrid; the objects' surfaces are
    // refined to the finest level at once (they move faster than one level a step).
    regrid(false, false);
    while (regrid(false, true))
    {
    }
    repartitionIfImbalanced(false);
  }
}

std::vector<std::int8_t> Simulation::ownWishes(bool objectsOnly) const
{
  std::vector<std::int8_t> wishes(Scalar.size(), 0);
  std::vector<AmrForest::FaceNeighbour> across;
  forEachOwnLeaf(
      [&](const Tree::Node& node, std::size_t index)
      {
        if (Exact)
        {
          // A uniform mesh at the finest level, whatever the profile looks like.
          wishes[index] = node.key.level < Options.maxLevel ? 1 : 0;
          return;
        }
        auto low = Forest.cellLow(node.key);
        auto high = low;
        for (int a = 0; a < Options.dimension; ++a)
          high[a] += Forest.cellSize(a, node.key.level);
        if (Objects.surfaceCrosses(low, high, objectClock()))
        {
          wishes[index] = node.key.level < Options.maxLevel ? 1 : 0;
          return;
        }
        if (objectsOnly)
          return;
        double jump = 0;
        for (int axis = 0; axis < Options.dimension; ++axis)
          for (int side = -1; side <= 1; side += 2)
          {
            Forest.faceNeighbours(node.key, axis, side, across);
            for (const auto& neighbour : across)
              jump = std::max(jump, std::abs(valueAcross(neighbour) - Scalar[index]));
          }
        wishes[index] = jump > Options.refineGradient ? 1 : jump < Options.coarsenGradient ? -1 : 0;
      });
  return wishes;
}

bool Simulation::regrid(bool initial, bool objectsOnly)
{
  // Gradient wishes read neighbours' values; object wishes are geometry only.
  if (!objectsOnly)
    Halo.exchange(Communicator, Scalar);
  const auto mine = ownWishes(objectsOnly);
  if (objectsOnly)
  {
    int local = std::any_of(mine.begin(), mine.end(), [](std::int8_t w) { return w > 0; });
    int any = 0;
    MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, Communicator);
    if (!any)
      return false;
  }
  // Every rank rebuilds every tree, so every rank needs every wish: owners are
  // contiguous in rank order, so gathering in rank order gives tree order.
  int count = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<std::size_t>(Size)), offsets(static_cast<std::size_t>(Size));
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, Communicator);
  std::exclusive_scan(counts.begin(), counts.end(), offsets.begin(), 0);
  std::vector<std::int8_t> all(static_cast<std::size_t>(offsets.back() + counts.back()));
  MPI_Allgatherv(mine.data(), count, MPI_INT8_T, all.data(), counts.data(), offsets.data(),
                 MPI_INT8_T, Communicator);
  std::vector<std::vector<std::int8_t>> wishes(Forest.trees().size());
  std::size_t next = 0;
  for (std::size_t t = 0; t < wishes.size(); ++t)
  {
    const auto leaves = static_cast<std::size_t>(Forest.trees()[t].leafCount);
    wishes[t].assign(all.begin() + static_cast<std::ptrdiff_t>(next),
                     all.begin() + static_cast<std::ptrdiff_t>(next + leaves));
    next += leaves;
  }

  // Conservative transfer: refined leaves' children take the parent's value
  // (piecewise constant), a coarsened family's parent the mean of its children
  // (equal volumes): the mass of each tree is unchanged.
  std::vector<double> values;
  values.reserve(Scalar.size());
  Forest.regrid(wishes,
                [&](std::size_t t, const Tree&, const Tree&)
                {
                  if (Owner[t] != Rank)
                    return;
                  const auto offset = LeafOffset[t];
                  for (const auto& origin : Forest.lastOrigins())
                  {
                    if (origin.oldChildren.empty())
                    {
                      values.push_back(Scalar[static_cast<std::size_t>(offset + origin.oldLeaf)]);
                      continue;
                    }
                    double sum = 0;
                    for (auto child : origin.oldChildren)
                      sum += Scalar[static_cast<std::size_t>(offset + child)];
                    values.push_back(sum / static_cast<double>(origin.oldChildren.size()));
                  }
                });
  Scalar.swap(values);
  afterTopologyChange();
  if (initial)
    sampleInitialValues();
  return true;
}

double Simulation::imbalance() const
{
  std::vector<std::int64_t> load(static_cast<std::size_t>(Size), 0);
  for (std::size_t t = 0; t < Owner.size(); ++t)
    load[static_cast<std::size_t>(Owner[t])] += Forest.trees()[t].leafCount;
  const double mean = static_cast<double>(Forest.totalLeaves()) / Size;
  return static_cast<double>(*std::max_element(load.begin(), load.end())) / mean;
}

void Simulation::repartitionIfImbalanced(bool force)
{
  if (!force && imbalance() <= Options.repartitionImbalance)
    return;
  // Contiguous ranges of trees (the root grid's order), balanced by leaf count.
  const double total = static_cast<double>(Forest.totalLeaves());
  std::vector<int> owner(Owner.size());
  double before = 0;
  for (std::size_t t = 0; t < Owner.size(); ++t)
  {
    const double leaves = Forest.trees()[t].leafCount;
    owner[t] = std::min(Size - 1, static_cast<int>((before + 0.5 * leaves) * Size / total));
    before += leaves;
  }
  if (owner == Owner)
    return;
  // Move the values of trees that change owner (every rank knows both owners).
  std::vector<int> sendCounts(static_cast<std::size_t>(Size), 0);
  std::vector<int> receiveCounts(static_cast<std::size_t>(Size), 0);
  for (std::size_t t = 0; t < Owner.size(); ++t)
  {
    const int leaves = Forest.trees()[t].leafCount;
    if (Owner[t] == Rank)
      sendCounts[static_cast<std::size_t>(owner[t])] += leaves;
    if (owner[t] == Rank)
      receiveCounts[static_cast<std::size_t>(Owner[t])] += leaves;
  }
  std::vector<int> sendOffsets(static_cast<std::size_t>(Size)),
      receiveOffsets(static_cast<std::size_t>(Size));
  std::exclusive_scan(sendCounts.begin(), sendCounts.end(), sendOffsets.begin(), 0);
  std::exclusive_scan(receiveCounts.begin(), receiveCounts.end(), receiveOffsets.begin(), 0);
  std::vector<double> received(
      static_cast<std::size_t>(receiveOffsets.back() + receiveCounts.back()));
  MPI_Alltoallv(Scalar.data(), sendCounts.data(), sendOffsets.data(), MPI_DOUBLE, received.data(),
                receiveCounts.data(), receiveOffsets.data(), MPI_DOUBLE, Communicator);
  Scalar.swap(received);
  Owner = owner;
  Repartitions += 1;
  afterTopologyChange();
}

void Simulation::afterTopologyChange()
{
  const auto& trees = Forest.trees();
  OwnTrees.clear();
  LeafOffset.assign(trees.size(), -1);
  std::int64_t leaves = 0;
  for (std::size_t t = 0; t < trees.size(); ++t)
    if (Owner[t] == Rank)
    {
      OwnTrees.push_back(static_cast<std::int32_t>(t));
      LeafOffset[t] = leaves;
      leaves += trees[t].leafCount;
    }
  Scalar.resize(static_cast<std::size_t>(leaves), 0.0);
  Velocity.assign(3 * static_cast<std::size_t>(leaves), 0.0);
  Level.assign(static_cast<std::size_t>(leaves), 0);
  RankField.assign(static_cast<std::size_t>(leaves), static_cast<double>(Rank));
  std::vector<HaloExchange::Remote> remote;
  std::vector<AmrForest::FaceNeighbour> across;
  forEachOwnLeaf(
      [&](const Tree::Node& node, std::size_t index)
      {
        const auto v = velocityAt(Forest.cellCenter(node.key));
        std::copy(v.begin(), v.end(), Velocity.begin() + static_cast<std::ptrdiff_t>(3 * index));
        Level[index] = node.key.level;
        for (int axis = 0; axis < Options.dimension; ++axis)
          for (int side = -1; side <= 1; side += 2)
          {
            Forest.faceNeighbours(node.key, axis, side, across);
            for (const auto& neighbour : across)
              if (Owner[static_cast<std::size_t>(neighbour.leaf.tree)] != Rank)
                remote.push_back({Owner[static_cast<std::size_t>(neighbour.leaf.tree)],
                                  neighbour.leaf.tree, neighbour.node->leaf});
          }
      });
  Halo.plan(Communicator, remote,
            [this](std::int32_t tree, std::int32_t leaf) {
              return static_cast<std::size_t>(LeafOffset[static_cast<std::size_t>(tree)] + leaf);
            });
}

double Simulation::totalMass() const
{
  double local = 0;
  forEachOwnLeaf([&](const Tree::Node& node, std::size_t index)
                 { local += Scalar[index] * Forest.cellVolume(node.key.level); });
  double total = 0;
  MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, Communicator);
  return total;
}

std::array<double, 3> Simulation::limitedSlopes(const Tree::Node& node, double u) const
{
  std::array<double, 3> slopes{{0, 0, 0}};
  std::vector<AmrForest::FaceNeighbour> across;
  double low = u, high = u; // the range of the leaf's and its face neighbours' values
  for (int axis = 0; axis < Options.dimension; ++axis)
  {
    const double size = Forest.cellSize(axis, node.key.level);
    double sided[2] = {0, 0}; // towards -axis, then +axis
    for (int side = -1; side <= 1; side += 2)
    {
      // The leaves across the face, as one: area-weighted means of their values
      // and of their centres' distances along the axis.
      Forest.faceNeighbours(node.key, axis, side, across);
      double area = 0, value = 0, distance = 0;
      for (const auto& neighbour : across)
      {
        const double v = valueAcross(neighbour);
        low = std::min(low, v);
        high = std::max(high, v);
        area += neighbour.area;
        value += neighbour.area * v;
        distance +=
            neighbour.area * 0.5 * (size + Forest.cellSize(axis, neighbour.node->key.level));
      }
      sided[side > 0] = side * (value / area - u) / (distance / area);
    }
    // minmod: the smaller one-sided slope, none at an extremum.
    if (sided[0] * sided[1] > 0)
      slopes[static_cast<std::size_t>(axis)] =
          std::abs(sided[0]) < std::abs(sided[1]) ? sided[0] : sided[1];
  }
  // The axes' slopes add up towards a block's corners: scale them down where the
  // corner cells would leave [low, high] (no new extremum, no negative value).
  const int n = std::max(1, Options.blocks);
  double reach = 0; // the largest change from u in any cell of the block
  for (int axis = 0; axis < Options.dimension; ++axis)
    reach += std::abs(slopes[static_cast<std::size_t>(axis)]) * (n - 1) / (2.0 * n) *
             Forest.cellSize(axis, node.key.level);
  const double room = std::min(high - u, u - low);
  if (reach > room)
  {
    const double scale = room / reach;
    for (auto& slope : slopes)
      slope *= scale;
  }
  return slopes;
}

std::size_t Simulation::blockOffset(int i, int j, int k) const
{
  const auto extent = static_cast<std::size_t>(Options.blocks + 2 * BlockGhosts);
  const auto g = static_cast<std::size_t>(BlockGhosts);
  const std::size_t jj = Options.dimension >= 2 ? static_cast<std::size_t>(j) + g : 0;
  const std::size_t kk = Options.dimension >= 3 ? static_cast<std::size_t>(k) + g : 0;
  return static_cast<std::size_t>(i) + g + extent * (jj + extent * kk);
}

double Simulation::blockValue(std::size_t index, int variable, int i, int j, int k) const
{
  return Blocks[index]
               [static_cast<std::size_t>(variable) * BlockExtentValues + blockOffset(i, j, k)];
}

void Simulation::sampleBlocks()
{
  if (Options.blocks <= 0)
    return;
  // Neighbours' current values (the halo holds the last exchange's otherwise).
  Halo.exchange(Communicator, Scalar);
  const int n = Options.blocks;
  const int d = Options.dimension;
  std::size_t extentValues = 1;
  for (int a = 0; a < d; ++a)
    extentValues *= static_cast<std::size_t>(n + 2 * BlockGhosts);
  if (extentValues != BlockExtentValues)
    Blocks.clear();
  BlockExtentValues = extentValues;
  const std::size_t blockSize = BlockVariables * BlockExtentValues;
  // One allocation per leaf, kept while the leaf count allows; new ones start all
  // NaN, and only the interiors are written: the ghost cells stay NaN.
  const std::size_t leaves = Scalar.size();
  Blocks.resize(leaves);
  for (auto& block : Blocks)
    if (!block)
    {
      block.reset(new double[blockSize]);
      std::fill(block.get(), block.get() + blockSize, std::numeric_limits<double>::quiet_NaN());
    }
  BlockTables.assign(4, std::vector<const double*>(leaves));
  const int nj = d >= 2 ? n : 1;
  const int nk = d >= 3 ? n : 1;
  forEachOwnLeaf(
      [&](const Tree::Node& node, std::size_t index)
      {
        double* block = Blocks[index].get();
        const int variables[4] = {BlockScalar, BlockVelocity, BlockLevel, BlockRank};
        for (std::size_t f = 0; f < 4; ++f)
          BlockTables[f][index] =
              block + static_cast<std::size_t>(variables[f]) * BlockExtentValues;
        const double u = Scalar[index];
        const auto slope = limitedSlopes(node, u);
        const auto low = Forest.cellLow(node.key);
        const auto size = cellSizes(node.key.level);
        for (int k = 0; k < nk; ++k)
          for (int j = 0; j < nj; ++j)
            for (int i = 0; i < n; ++i)
            {
              const int cell[3] = {i, j, k};
              std::array<double, 3> x{{0, 0, 0}};
              double value = u;
              for (int a = 0; a < d; ++a)
              {
                // Centre offsets from the leaf's centre as (2 i + 1 - n) / 2n: exactly
                // opposite for mirrored cells, so the block's mean is u.
                const double offset = (2.0 * cell[a] + 1 - n) / (2.0 * n) * size[a];
                value += slope[static_cast<std::size_t>(a)] * offset;
                x[a] = low[a] + (cell[a] + 0.5) * (size[a] / n);
              }
              const auto v = velocityAt(x);
              const std::size_t at = blockOffset(i, j, k);
              block[BlockScalar * BlockExtentValues + at] = value;
              for (std::size_t c = 0; c < 3; ++c)
                block[(BlockVelocity + c) * BlockExtentValues + at] = v[c];
              block[BlockLevel * BlockExtentValues + at] = node.key.level;
              block[BlockRank * BlockExtentValues + at] = Rank;
            }
      });
  BlocksSampledAt = Step;
}

canopy::ForestDescription Simulation::describeForCanopy() const
{
  canopy::ForestDescription forest;
  forest.dimension = Options.dimension;
  forest.branchFactor = Options.branchFactor;
  forest.maxLevels = Options.maxLevel + 1;
  forest.rootGrid = {RootX.data(), RootY.data(), RootZ.data(),
                     RootX.size(), RootY.size(), RootZ.size()};
  for (auto tree : OwnTrees)
  {
    const auto& t = Forest.trees()[static_cast<std::size_t>(tree)];
    forest.trees.push_back({t.rootIndex, t.refinement.data(), t.nodes.size(), nullptr, nullptr});
  }
  // Every root cell has a tree, on some rank: faces between ranks' trees are
  // inside the domain (a 3D surface draws none there unless a mask shows one).
  forest.missingTreesAreElsewhere = true;
  using canopy::Centering;
  using canopy::FieldDescription;
  const std::size_t leaves = Scalar.size();
  if (Options.blocks > 0)
  {
    if (BlocksSampledAt != Step)
      throw std::logic_error("describeForCanopy with --blocks: sampleBlocks() first, every step");
    // Each leaf a block of n^d cells, blocks in leaf order (the default block order:
    // present leaves breadth-first, tree by tree), so no blockIndex map. The cells
    // become log_bf(n) levels below the leaves.
    forest.blockCellsPerSide = Options.blocks;
    for (int n = 1; n < Options.blocks; n *= Options.branchFactor)
      forest.maxLevels += 1;
    const auto strides = canopy::BlockStrides::variableOutermost<double>(
        Options.dimension, Options.blocks, BlockGhosts);
    const std::size_t blocks = ownBlocks();
    forest.fields = {
        FieldDescription::blocks("scalar", BlockTables[0].data(), blocks, strides),
        FieldDescription::blocks("velocity", BlockTables[1].data(), blocks, strides, 3),
        FieldDescription::blocks("level", BlockTables[2].data(), blocks, strides),
        FieldDescription::blocks("rank", BlockTables[3].data(), blocks, strides)};
    return forest;
  }
  forest.fields = {
      FieldDescription::aos("scalar", Scalar.data(), leaves, 1, Centering::LeavesOnly),
      FieldDescription::aos("velocity", Velocity.data(), leaves, 3, Centering::LeavesOnly),
      FieldDescription::aos("level", Level.data(), leaves, 1, Centering::LeavesOnly),
      FieldDescription::aos("rank", RankField.data(), leaves, 1, Centering::LeavesOnly)};
  return forest;
}

std::uint64_t Simulation::borrowedArraysChecksum() const
{
  std::uint64_t hash = 1469598103934665603ULL; // FNV-1a
  auto add = [&hash](const void* data, std::size_t bytes)
  {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i)
      hash = (hash ^ p[i]) * 1099511628211ULL;
  };
  add(Scalar.data(), Scalar.size() * sizeof(double));
  add(Velocity.data(), Velocity.size() * sizeof(double));
  add(Level.data(), Level.size() * sizeof(double));
  add(RankField.data(), RankField.size() * sizeof(double));
  add(RootX.data(), RootX.size() * sizeof(double));
  add(RootY.data(), RootY.size() * sizeof(double));
  add(RootZ.data(), RootZ.size() * sizeof(double));
  for (const auto& block : Blocks)
    add(block.get(), BlockVariables * BlockExtentValues * sizeof(double));
  for (const auto& table : BlockTables)
    add(table.data(), table.size() * sizeof(const double*));
  for (auto tree : OwnTrees)
  {
    const auto& refinement = Forest.trees()[static_cast<std::size_t>(tree)].refinement;
    add(refinement.data(), refinement.size());
  }
  return hash;
}

void Simulation::dump(const std::string& path) const
{
  // Rank 0 writes; every rank learns whether it can, so that all throw together.
  std::FILE* out = Rank == 0 ? std::fopen(path.c_str(), "w") : nullptr;
  int opened = Rank != 0 || out != nullptr ? 1 : 0;
  MPI_Bcast(&opened, 1, MPI_INT, 0, Communicator);
  if (!opened)
    throw std::runtime_error("cannot write " + path);
  // Five doubles per leaf: level, x, y, z, value.
  std::vector<double> mine;
  forEachOwnLeaf(
      [&](const Tree::Node& node, std::size_t index)
      {
        mine.insert(mine.end(),
                    {static_cast<double>(node.key.level), static_cast<double>(node.key.position[0]),
                     static_cast<double>(node.key.position[1]),
                     static_cast<double>(node.key.position[2]), Scalar[index]});
      });
  int count = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<std::size_t>(Size)), offsets(static_cast<std::size_t>(Size));
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, Communicator);
  if (Rank == 0)
    std::exclusive_scan(counts.begin(), counts.end(), offsets.begin(), 0);
  std::vector<double> all(Rank == 0 ? static_cast<std::size_t>(offsets.back() + counts.back()) : 0);
  MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE,
              0, Communicator);
  if (Rank != 0)
    return;
  std::vector<std::array<double, 5>> rows(all.size() / 5);
  for (std::size_t i = 0; i < rows.size(); ++i)
    std::copy(all.begin() + static_cast<std::ptrdiff_t>(5 * i),
              all.begin() + static_cast<std::ptrdiff_t>(5 * i + 5), rows[i].begin());
  std::sort(rows.begin(), rows.end());
  for (const auto& r : rows)
    std::fprintf(out, "%d %lld %lld %lld %.17g\n", static_cast<int>(r[0]),
                 static_cast<long long>(r[1]), static_cast<long long>(r[2]),
                 static_cast<long long>(r[3]), r[4]);
  std::fclose(out);
}

} // namespace miniamr
