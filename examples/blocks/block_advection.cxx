// A block-AMR simulation with Canopy in situ (docs/blocks.md), laid out as
// Athena++, Parthenon or FLASH lay out theirs: a quadtree (2D) or octree (3D) of
// blocks over a 2 x 2 (x 2) grid of root blocks, every leaf a block of 16^d cells
// with 2 ghost cells on each side, allocated on its own and holding its variables
// as [var][k][j][i] (density, then the velocity's components).
//
// A density (a disc and a Gaussian hump) turns with a solid-body rotation:
// first-order upwind, face ghosts filled from the neighbours each step (copies at
// the same level, injection from coarser blocks, averages of finer ones). Every
// few steps blocks are refined where the density jumps and coarsened where it is
// smooth (2:1 balanced), from decisions gathered from all ranks.
//
// MPI: blocks are ordered along the Morton curve (trees in order, each depth first)
// and every rank owns a contiguous range of that order, so trees are split between
// ranks. Each rank describes its part of each tree, the other ranks' parts absent.
// The mesh and every value are the same on any number of ranks.
//
// The Canopy lines are marked "---- Canopy (n of 4)"; docs/blocks.md quotes them.
//
//   mpirun -np 3 canopy_block_advection [--dimension 2|3] [--steps N] [--every N]
//       [--max-level L] [--regrid-every N] [--output DIR]
#include "BlockMesh.h"

// ---- Canopy (1 of 4): the header ----
#include <canopy/InSitu.h>

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{

using blocks::BlockKey;
using blocks::BlockMesh;
using blocks::CellsPerSide;
using blocks::GhostCells;
using blocks::Origin;
using blocks::Point;

constexpr int RootsPerAxis = 2; ///< root blocks along each axis: the domain is [0, 1]^d
const double Pi = std::acos(-1.0);
const double Omega = 2 * Pi;          ///< the rotation's angular speed: one turn per unit of time
constexpr double RefineAbove = 0.1;   ///< refine where the density jumps more from cell to cell
constexpr double CoarsenBelow = 0.02; ///< coarsen where it jumps less (all 2^d siblings)
constexpr double DenseFrom = 1.5;     ///< "dense": what the selection extract keeps

struct Options
{
  int dimension = 2;
  long steps = 500;
  long every = 100;  ///< run the pipelines every this many steps
  int maxLevel = -1; ///< levels of blocks below the roots (-1: 3 in 2D, 2 in 3D)
  int regridEvery = 5;
  std::string output = "blocks-output";
};

const char* const Usage =
    "usage: canopy_block_advection [--dimension 2|3] [--steps N] [--every N] [--max-level L]\n"
    "                              [--regrid-every N] [--output DIR]\n";

Options parseOptions(int argc, char** argv)
{
  Options o;
  for (int i = 1; i < argc; ++i)
  {
    const std::string key = argv[i];
    if (key == "--help" || key == "-h")
      throw std::invalid_argument("");
    if (i + 1 >= argc)
      throw std::invalid_argument(key + " needs a value");
    const std::string value = argv[++i];
    auto integer = [&](long low, long high)
    {
      char* end = nullptr;
      const long n = std::strtol(value.c_str(), &end, 10);
      if (value.empty() || *end != '\0' || n < low || n > high)
      {
        throw std::invalid_argument(key + ": an integer from " + std::to_string(low) + " to " +
                                    std::to_string(high) + ", not '" + value + "'");
      }
      return n;
    };
    if (key == "--dimension")
      o.dimension = static_cast<int>(integer(2, 3));
    else if (key == "--steps")
      o.steps = integer(0, 1000000);
    else if (key == "--every")
      o.every = integer(1, 1000000);
    else if (key == "--max-level")
      o.maxLevel = static_cast<int>(integer(0, 6));
    else if (key == "--regrid-every")
      o.regridEvery = static_cast<int>(integer(1, 1000000));
    else if (key == "--output")
      o.output = value;
    else
      throw std::invalid_argument("unknown option " + key);
  }
  if (o.maxLevel < 0)
  {
    o.maxLevel = o.dimension == 2 ? 3 : 2;
  }
  return o;
}

/// The initial density: 1, a disc (a ball in 3D) of 2 with a thin smooth edge, and
/// a Gaussian hump of height 1, in opposite quadrants (centred in z).
double initialDensity(const double x[3], int dimension)
{
  double disc = 0;
  double hump = 0;
  for (int a = 0; a < dimension; ++a)
  {
    const double toDisc = x[a] - (a == 0 ? 0.3 : a == 1 ? 0.7 : 0.5);
    const double toHump = x[a] - (a == 0 ? 0.7 : a == 1 ? 0.3 : 0.5);
    disc += toDisc * toDisc;
    hump += toHump * toHump;
  }
  return 1.0 + 0.5 * (1.0 - std::tanh((std::sqrt(disc) - 0.13) / 0.01)) +
         std::exp(-hump / (2 * 0.06 * 0.06));
}

/// Solid-body rotation about the domain's centre (about the z axis in 3D).
double velocity(const double x[3], int axis)
{
  return axis == 0 ? -Omega * (x[1] - 0.5) : axis == 1 ? Omega * (x[0] - 0.5) : 0.0;
}

/// The cells of one variable of a block, ghosts included: extent^d values, i fastest.
struct BlockShape
{
  int dimension;
  static constexpr int Extent = CellsPerSide + 2 * GhostCells;

  std::size_t valuesPerVariable() const
  {
    return dimension == 2 ? Extent * Extent : Extent * Extent * Extent;
  }
  std::size_t interiorCells() const
  {
    return dimension == 2 ? CellsPerSide * CellsPerSide
                          : CellsPerSide * CellsPerSide * CellsPerSide;
  }
  int kCells() const { return dimension == 2 ? 1 : CellsPerSide; }
  /// Where cell (i, j, k) of the interior is (negative or >= CellsPerSide: a ghost).
  std::size_t at(int i, int j, int k) const
  {
    return static_cast<std::size_t>((i + GhostCells) + Extent * (j + GhostCells) +
                                    (dimension == 3 ? Extent * Extent * (k + GhostCells) : 0));
  }
};

/// Read access to the interior densities of a block, this rank's or a copy of another's.
struct DensityView
{
  const double* first = nullptr; ///< interior cell (0, 0, 0)
  std::size_t stride[3] = {0, 0, 0};
  double at(const std::int64_t index[3]) const
  {
    return first[static_cast<std::size_t>(index[0]) * stride[0] +
                 static_cast<std::size_t>(index[1]) * stride[1] +
                 static_cast<std::size_t>(index[2]) * stride[2]];
  }
};

/// Per rank, the blocks to send it or to receive from it (sorted, the same lists on
/// both sides: every rank computes them from the same mesh).
using BlockLists = std::vector<std::vector<std::int64_t>>;

class BlockAdvection
{
public:
  BlockAdvection(const Options& options, MPI_Comm communicator)
      : Dimension(options.dimension), Shape{options.dimension},
        Mesh(options.dimension, {RootsPerAxis, RootsPerAxis, RootsPerAxis}, options.maxLevel),
        Communicator(communicator)
  {
    MPI_Comm_rank(communicator, &Rank);
    MPI_Comm_size(communicator, &Ranks);
    partition();
    planGhostExchange();
    Blocks.resize(static_cast<std::size_t>(EndBlock - FirstBlock));
    // Refine the root blocks down to the initial density, a level at a time.
    for (int level = 0; level <= Mesh.maxLevel(); ++level)
    {
      for (std::int64_t b = FirstBlock; b < EndBlock; ++b)
      {
        std::vector<double>& block = allocate(b);
        forEachCell(b, [&](int i, int j, int k, const double x[3])
                    { block[Shape.at(i, j, k)] = initialDensity(x, Dimension); });
      }
      if (level < Mesh.maxLevel())
      {
        regrid();
      }
    }
    // The time step: stable (upwind, CFL 0.8) on the finest blocks the mesh may have.
    TimeStep = 0.8 * cellSize(Mesh.maxLevel()) / Omega;
  }

  int dimension() const { return Dimension; }
  const BlockMesh& mesh() const { return Mesh; }
  double timeStep() const { return TimeStep; }
  std::int64_t firstBlock() const { return FirstBlock; }
  std::int64_t endBlock() const { return EndBlock; }
  /// This rank's blocks, in Morton order: block FirstBlock + n is blocks()[n].
  const std::vector<std::vector<double>>& blocks() const { return Blocks; }
  std::size_t valuesPerVariable() const { return Shape.valuesPerVariable(); }

  /// One step of first-order upwind: density -= dt div(velocity density).
  void advance()
  {
    exchangeGhosts();
    std::vector<double> updated(Shape.interiorCells());
    for (std::int64_t b = FirstBlock; b < EndBlock; ++b)
    {
      std::vector<double>& block = Blocks[static_cast<std::size_t>(b - FirstBlock)];
      const double h = cellSize(Mesh.block(b).level);
      std::size_t n = 0;
      forEachCell(b,
                  [&](int i, int j, int k, const double x[3])
                  {
                    const int cell[3] = {i, j, k};
                    double change = 0;
                    for (int a = 0; a < Dimension; ++a)
                    {
                      int lower[3] = {i, j, k};
                      int upper[3] = {i, j, k};
                      --lower[a];
                      ++upper[a];
                      double face[3] = {x[0], x[1], x[2]};
                      face[a] = x[a] - 0.5 * h;
                      const double uLower = velocity(face, a);
                      face[a] = x[a] + 0.5 * h;
                      const double uUpper = velocity(face, a);
                      const double here = block[Shape.at(cell[0], cell[1], cell[2])];
                      const double below = block[Shape.at(lower[0], lower[1], lower[2])];
                      const double above = block[Shape.at(upper[0], upper[1], upper[2])];
                      change += uUpper * (uUpper > 0 ? here : above) -
                                uLower * (uLower > 0 ? below : here);
                    }
                    updated[n++] = block[Shape.at(i, j, k)] - TimeStep / h * change;
                  });
      n = 0;
      forEachCell(b, [&](int i, int j, int k, const double*)
                  { block[Shape.at(i, j, k)] = updated[n++]; });
    }
  }

  /// What one regrid did: blocks made by refining a block, and by coarsening 2^d.
  struct Regrid
  {
    std::int64_t refined = 0;
    std::int64_t coarsened = 0;
  };

  /// Refines blocks where the density jumps, coarsens where it is smooth; the
  /// decisions of all ranks are gathered, so every rank adapts the same mesh.
  Regrid regrid()
  {
    exchangeGhosts();
    std::vector<int> mine;
    for (std::int64_t b = FirstBlock; b < EndBlock; ++b)
    {
      const std::vector<double>& block = Blocks[static_cast<std::size_t>(b - FirstBlock)];
      double jump = 0;
      forEachCell(b,
                  [&](int i, int j, int k, const double*)
                  {
                    for (int a = 0; a < Dimension; ++a)
                    {
                      int lower[3] = {i, j, k};
                      int upper[3] = {i, j, k};
                      --lower[a];
                      ++upper[a];
                      jump = std::max(
                          jump, 0.5 * std::abs(block[Shape.at(upper[0], upper[1], upper[2])] -
                                               block[Shape.at(lower[0], lower[1], lower[2])]));
                    }
                  });
      mine.push_back(jump > RefineAbove ? 1 : jump < CoarsenBelow ? -1 : 0);
    }
    std::vector<int> counts(static_cast<std::size_t>(Ranks));
    std::vector<int> offsets(static_cast<std::size_t>(Ranks));
    for (int r = 0; r < Ranks; ++r)
    {
      offsets[static_cast<std::size_t>(r)] =
          static_cast<int>(firstBlockOf(r, Mesh.numberOfBlocks()));
      counts[static_cast<std::size_t>(r)] =
          static_cast<int>(firstBlockOf(r + 1, Mesh.numberOfBlocks())) -
          offsets[static_cast<std::size_t>(r)];
    }
    std::vector<int> change(static_cast<std::size_t>(Mesh.numberOfBlocks()));
    MPI_Allgatherv(mine.data(), static_cast<int>(mine.size()), MPI_INT, change.data(),
                   counts.data(), offsets.data(), MPI_INT, Communicator);

    const BlockMesh before = Mesh;
    const std::int64_t oldCount = before.numberOfBlocks();
    const std::vector<Origin> origins = Mesh.adapt(change);
    const std::int64_t newCount = Mesh.numberOfBlocks();
    Regrid done;
    for (std::int64_t n = 0; n < newCount; ++n)
    {
      const Origin& origin = origins[static_cast<std::size_t>(n)];
      if (origin.kind == Origin::Kind::Covers)
        ++done.coarsened;
      else if (Mesh.block(n).level > before.block(origin.block).level)
        ++done.refined;
    }

    // Each new block is made by its new owner from the old blocks it comes from.
    BlockLists send(static_cast<std::size_t>(Ranks));
    BlockLists receive(static_cast<std::size_t>(Ranks));
    std::vector<std::set<std::int64_t>> sending(static_cast<std::size_t>(Ranks));
    std::vector<std::set<std::int64_t>> receiving(static_cast<std::size_t>(Ranks));
    for (std::int64_t n = 0; n < newCount; ++n)
    {
      const int to = ownerOf(n, newCount);
      const Origin& origin = origins[static_cast<std::size_t>(n)];
      const int sources = origin.kind == Origin::Kind::Covers ? Mesh.childrenPerBlock() : 1;
      for (std::int64_t s = origin.block; s < origin.block + sources; ++s)
      {
        const int from = ownerOf(s, oldCount);
        if (from == Rank && to != Rank)
          sending[static_cast<std::size_t>(to)].insert(s);
        if (to == Rank && from != Rank)
          receiving[static_cast<std::size_t>(from)].insert(s);
      }
    }
    for (int r = 0; r < Ranks; ++r)
    {
      send[static_cast<std::size_t>(r)].assign(sending[static_cast<std::size_t>(r)].begin(),
                                               sending[static_cast<std::size_t>(r)].end());
      receive[static_cast<std::size_t>(r)].assign(receiving[static_cast<std::size_t>(r)].begin(),
                                                  receiving[static_cast<std::size_t>(r)].end());
    }
    const std::int64_t oldFirst = FirstBlock;
    std::vector<std::vector<double>> old = std::move(Blocks);
    const std::map<std::int64_t, std::vector<double>> received = exchange(
        send, receive,
        [&](std::int64_t b) { return old[static_cast<std::size_t>(b - oldFirst)].data(); });
    auto oldDensity = [&](std::int64_t b)
    {
      if (b >= oldFirst && b < oldFirst + static_cast<std::int64_t>(old.size()))
        return ownView(old[static_cast<std::size_t>(b - oldFirst)]);
      return copyView(received.at(b));
    };

    partition();
    Blocks.assign(static_cast<std::size_t>(EndBlock - FirstBlock), {});
    for (std::int64_t n = FirstBlock; n < EndBlock; ++n)
    {
      std::vector<double>& block = allocate(n);
      const Origin& origin = origins[static_cast<std::size_t>(n)];
      const BlockKey& key = Mesh.block(n);
      const Point corner = Mesh.corner(key);
      const std::int64_t cell = Mesh.cellSide(key.level);
      forEachCell(n,
                  [&](int i, int j, int k, const double*)
                  {
                    const int index[3] = {i, j, k};
                    double value = 0;
                    if (origin.kind == Origin::Kind::Inside)
                    {
                      // Injection: the value of the old cell holding this cell.
                      const BlockKey& from = before.block(origin.block);
                      const Point fromCorner = before.corner(from);
                      std::int64_t at[3] = {0, 0, 0};
                      for (int a = 0; a < Dimension; ++a)
                        at[a] = (corner[a] + cell * index[a] + cell / 2 - fromCorner[a]) /
                                before.cellSide(from.level);
                      value = oldDensity(origin.block).at(at);
                    }
                    else
                    {
                      // Restriction: the mean of the 2^d cells of the child holding it.
                      int child = 0;
                      for (int a = 0; a < Dimension; ++a)
                        child |= (index[a] >= CellsPerSide / 2) << a;
                      const DensityView fine = oldDensity(origin.block + child);
                      for (int c = 0; c < Mesh.childrenPerBlock(); ++c)
                      {
                        std::int64_t at[3] = {0, 0, 0};
                        for (int a = 0; a < Dimension; ++a)
                          at[a] = 2 * (index[a] % (CellsPerSide / 2)) + ((c >> a) & 1);
                        value += fine.at(at);
                      }
                      value /= Mesh.childrenPerBlock();
                    }
                    block[Shape.at(i, j, k)] = value;
                  });
    }
    planGhostExchange();
    return done;
  }

  /// What the simulation knows of its density, over all ranks (on rank 0).
  struct Totals
  {
    long long dense = 0; ///< cells with density >= DenseFrom
    double mass = 0;     ///< sum of density x cell volume
    double minimum = std::numeric_limits<double>::infinity();
    double maximum = -std::numeric_limits<double>::infinity();
  };
  Totals totals() const
  {
    Totals mine;
    for (std::int64_t b = FirstBlock; b < EndBlock; ++b)
    {
      const std::vector<double>& block = Blocks[static_cast<std::size_t>(b - FirstBlock)];
      const double volume = std::pow(cellSize(Mesh.block(b).level), Dimension);
      forEachCell(b,
                  [&](int i, int j, int k, const double*)
                  {
                    const double density = block[Shape.at(i, j, k)];
                    mine.dense += density >= DenseFrom;
                    mine.mass += density * volume;
                    mine.minimum = std::min(mine.minimum, density);
                    mine.maximum = std::max(mine.maximum, density);
                  });
    }
    Totals all;
    MPI_Reduce(&mine.dense, &all.dense, 1, MPI_LONG_LONG, MPI_SUM, 0, Communicator);
    MPI_Reduce(&mine.mass, &all.mass, 1, MPI_DOUBLE, MPI_SUM, 0, Communicator);
    MPI_Reduce(&mine.minimum, &all.minimum, 1, MPI_DOUBLE, MPI_MIN, 0, Communicator);
    MPI_Reduce(&mine.maximum, &all.maximum, 1, MPI_DOUBLE, MPI_MAX, 0, Communicator);
    return all;
  }

private:
  /// Block b's first block on rank r of `count` blocks: equal contiguous ranges.
  std::int64_t firstBlockOf(int r, std::int64_t count) const { return count * r / Ranks; }
  int ownerOf(std::int64_t b, std::int64_t count) const
  {
    int r = static_cast<int>(b * Ranks / count);
    while (firstBlockOf(r + 1, count) <= b)
      ++r;
    while (firstBlockOf(r, count) > b)
      --r;
    return r;
  }
  void partition()
  {
    FirstBlock = firstBlockOf(Rank, Mesh.numberOfBlocks());
    EndBlock = firstBlockOf(Rank + 1, Mesh.numberOfBlocks());
  }

  double cellSize(int level) const { return 1.0 / (RootsPerAxis * CellsPerSide * (1 << level)); }
  double coordinate(std::int64_t units) const
  {
    return static_cast<double>(units) / static_cast<double>(RootsPerAxis * Mesh.blockSide(0));
  }

  /// Calls visit(i, j, k, centre) for every interior cell of block b, i fastest.
  template <typename Visit>
  void forEachCell(std::int64_t b, Visit&& visit) const
  {
    const BlockKey& key = Mesh.block(b);
    const Point corner = Mesh.corner(key);
    const std::int64_t cell = Mesh.cellSide(key.level);
    double x[3] = {0, 0, 0};
    for (int k = 0; k < Shape.kCells(); ++k)
    {
      x[2] = Dimension == 3 ? coordinate(corner[2] + cell * k + cell / 2) : 0.0;
      for (int j = 0; j < CellsPerSide; ++j)
      {
        x[1] = coordinate(corner[1] + cell * j + cell / 2);
        for (int i = 0; i < CellsPerSide; ++i)
        {
          x[0] = coordinate(corner[0] + cell * i + cell / 2);
          visit(i, j, k, x);
        }
      }
    }
  }

  /// A new block's array: velocity set, density 0, ghost cells NaN until filled
  /// (edge and corner ghosts never are: the scheme reads face neighbours only).
  std::vector<double>& allocate(std::int64_t b)
  {
    std::vector<double>& block = Blocks[static_cast<std::size_t>(b - FirstBlock)];
    block.assign(static_cast<std::size_t>(1 + Dimension) * Shape.valuesPerVariable(),
                 std::numeric_limits<double>::quiet_NaN());
    forEachCell(
        b,
        [&](int i, int j, int k, const double x[3])
        {
          block[Shape.at(i, j, k)] = 0.0;
          for (int a = 0; a < Dimension; ++a)
            block[static_cast<std::size_t>(1 + a) * Shape.valuesPerVariable() + Shape.at(i, j, k)] =
                velocity(x, a);
        });
    return block;
  }

  DensityView ownView(const std::vector<double>& block) const
  {
    const std::size_t e = BlockShape::Extent;
    return {block.data() + Shape.at(0, 0, 0), {1, e, e * e}};
  }
  static DensityView copyView(const std::vector<double>& interior)
  {
    const std::size_t n = CellsPerSide;
    return {interior.data(), {1, n, n * n}};
  }
  DensityView densityOf(std::int64_t b) const
  {
    if (b >= FirstBlock && b < EndBlock)
      return ownView(Blocks[static_cast<std::size_t>(b - FirstBlock)]);
    return copyView(Neighbours.at(b));
  }

  /// Sends the interior densities of the blocks listed for each rank, receives those
  /// listed from each rank (MPI_Alltoallv).
  std::map<std::int64_t, std::vector<double>>
  exchange(const BlockLists& send, const BlockLists& receive,
           const std::function<const double*(std::int64_t)>& blockArray) const
  {
    const std::size_t cells = Shape.interiorCells();
    std::vector<int> sendCounts(static_cast<std::size_t>(Ranks));
    std::vector<int> sendOffsets(static_cast<std::size_t>(Ranks));
    std::vector<int> receiveCounts(static_cast<std::size_t>(Ranks));
    std::vector<int> receiveOffsets(static_cast<std::size_t>(Ranks));
    std::vector<double> outgoing;
    std::size_t incoming = 0;
    for (std::size_t r = 0; r < static_cast<std::size_t>(Ranks); ++r)
    {
      sendOffsets[r] = static_cast<int>(outgoing.size());
      for (std::int64_t b : send[r])
      {
        const double* block = blockArray(b);
        for (int k = 0; k < Shape.kCells(); ++k)
          for (int j = 0; j < CellsPerSide; ++j)
            for (int i = 0; i < CellsPerSide; ++i)
              outgoing.push_back(block[Shape.at(i, j, k)]);
      }
      sendCounts[r] = static_cast<int>(outgoing.size()) - sendOffsets[r];
      receiveOffsets[r] = static_cast<int>(incoming);
      receiveCounts[r] = static_cast<int>(receive[r].size() * cells);
      incoming += receive[r].size() * cells;
    }
    std::vector<double> arrived(incoming);
    MPI_Alltoallv(outgoing.data(), sendCounts.data(), sendOffsets.data(), MPI_DOUBLE,
                  arrived.data(), receiveCounts.data(), receiveOffsets.data(), MPI_DOUBLE,
                  Communicator);
    std::map<std::int64_t, std::vector<double>> blocks;
    const double* next = arrived.data();
    for (const std::vector<std::int64_t>& from : receive)
    {
      for (std::int64_t b : from)
      {
        blocks[b].assign(next, next + cells);
        next += cells;
      }
    }
    return blocks;
  }

  /// Calls visit(axis, upper, lo, hi) for each face of block b inside the domain,
  /// with the box its ghost layers cover.
  template <typename Visit>
  void forEachInnerFace(std::int64_t b, Visit&& visit) const
  {
    const BlockKey& key = Mesh.block(b);
    const Point corner = Mesh.corner(key);
    const std::int64_t side = Mesh.blockSide(key.level);
    const std::int64_t depth = GhostCells * Mesh.cellSide(key.level);
    for (int a = 0; a < Dimension; ++a)
    {
      for (int upper = 0; upper < 2; ++upper)
      {
        if (upper ? corner[a] + side == Mesh.domain()[a] : corner[a] == 0)
          continue; // the domain's boundary
        Point lo = corner;
        Point hi = corner;
        for (int t = 0; t < Dimension; ++t)
          hi[t] += side;
        lo[a] = upper ? corner[a] + side : corner[a] - depth;
        hi[a] = upper ? corner[a] + side + depth : corner[a];
        visit(a, upper, lo, hi);
      }
    }
  }

  /// Which blocks of other ranks this rank reads ghost values from, and which of its
  /// blocks other ranks read (the blocks across each face, as deep as the ghosts).
  void planGhostExchange()
  {
    std::vector<std::set<std::int64_t>> sending(static_cast<std::size_t>(Ranks));
    std::vector<std::set<std::int64_t>> receiving(static_cast<std::size_t>(Ranks));
    const std::int64_t count = Mesh.numberOfBlocks();
    std::vector<std::int64_t> across;
    for (std::int64_t b = 0; b < count; ++b)
    {
      const int owner = ownerOf(b, count);
      forEachInnerFace(b,
                       [&](int, int, const Point& lo, const Point& hi)
                       {
                         across.clear();
                         Mesh.blocksOverlapping(lo, hi, across);
                         for (std::int64_t n : across)
                         {
                           const int neighbour = ownerOf(n, count);
                           if (owner == Rank && neighbour != Rank)
                             receiving[static_cast<std::size_t>(neighbour)].insert(n);
                           if (neighbour == Rank && owner != Rank)
                             sending[static_cast<std::size_t>(owner)].insert(n);
                         }
                       });
    }
    SendGhosts.assign(static_cast<std::size_t>(Ranks), {});
    ReceiveGhosts.assign(static_cast<std::size_t>(Ranks), {});
    for (std::size_t r = 0; r < static_cast<std::size_t>(Ranks); ++r)
    {
      SendGhosts[r].assign(sending[r].begin(), sending[r].end());
      ReceiveGhosts[r].assign(receiving[r].begin(), receiving[r].end());
    }
  }

  /// The mean density over the cube of side `size` centred at `centre` (units):
  /// the value of the cell holding it when that cell is as large or larger
  /// (a copy at the same level, injection from a coarser block), else the mean of
  /// its 2^d halves (the average of a finer block's cells).
  double meanDensity(const Point& centre, std::int64_t size) const
  {
    const std::int64_t b = Mesh.locate(centre);
    const BlockKey& key = Mesh.block(b);
    const std::int64_t cell = Mesh.cellSide(key.level);
    if (cell >= size)
    {
      const Point corner = Mesh.corner(key);
      std::int64_t at[3] = {0, 0, 0};
      for (int a = 0; a < Dimension; ++a)
        at[a] = (centre[a] - corner[a]) / cell;
      return densityOf(b).at(at);
    }
    double sum = 0;
    for (int c = 0; c < Mesh.childrenPerBlock(); ++c)
    {
      Point half = centre;
      for (int a = 0; a < Dimension; ++a)
        half[a] += ((c >> a) & 1) ? size / 4 : -size / 4;
      sum += meanDensity(half, size / 2);
    }
    return sum / Mesh.childrenPerBlock();
  }

  /// Fills the face ghost layers of this rank's blocks: from the neighbours across
  /// inner faces, as copies of the boundary cells on the domain's boundary (outflow).
  void exchangeGhosts()
  {
    Neighbours = exchange(SendGhosts, ReceiveGhosts,
                          [&](std::int64_t b)
                          { return Blocks[static_cast<std::size_t>(b - FirstBlock)].data(); });
    for (std::int64_t b = FirstBlock; b < EndBlock; ++b)
    {
      std::vector<double>& block = Blocks[static_cast<std::size_t>(b - FirstBlock)];
      const BlockKey& key = Mesh.block(b);
      const Point corner = Mesh.corner(key);
      const std::int64_t cell = Mesh.cellSide(key.level);
      for (int a = 0; a < Dimension; ++a)
      {
        for (int upper = 0; upper < 2; ++upper)
        {
          const bool boundary =
              upper ? corner[a] + Mesh.blockSide(key.level) == Mesh.domain()[a] : corner[a] == 0;
          for (int g = 0; g < GhostCells; ++g)
          {
            // The face's cells (t, u) in the two other axes' order.
            for (int u = 0; u < (Dimension == 3 ? CellsPerSide : 1); ++u)
            {
              for (int t = 0; t < CellsPerSide; ++t)
              {
                int index[3] = {0, 0, 0};
                index[a] = upper ? CellsPerSide + g : -1 - g;
                index[(a + 1) % Dimension] = t;
                if (Dimension == 3)
                  index[(a + 2) % 3] = u;
                double& ghost = block[Shape.at(index[0], index[1], index[2])];
                if (boundary)
                {
                  index[a] = upper ? CellsPerSide - 1 : 0;
                  ghost = block[Shape.at(index[0], index[1], index[2])];
                  continue;
                }
                Point centre{{0, 0, 0}};
                for (int d = 0; d < Dimension; ++d)
                  centre[d] = corner[d] + cell * index[d] + cell / 2;
                ghost = meanDensity(centre, cell);
              }
            }
          }
        }
      }
    }
  }

  int Dimension;
  BlockShape Shape;
  BlockMesh Mesh;
  MPI_Comm Communicator;
  int Rank = 0;
  int Ranks = 1;
  double TimeStep = 0;
  std::int64_t FirstBlock = 0;
  std::int64_t EndBlock = 0;
  std::vector<std::vector<double>> Blocks;                ///< [var][k][j][i] each, ghosts included
  std::map<std::int64_t, std::vector<double>> Neighbours; ///< other ranks' interiors
  BlockLists SendGhosts;
  BlockLists ReceiveGhosts;
};

// ---- Canopy (2 of 4): the shipped pipelines, by name ----
canopy::InSituOptions insituOptions(const Options& o)
{
  const std::string frequency = "--frequency=" + std::to_string(o.every);
  canopy::InSituOptions options;
  if (o.dimension == 2)
  {
    options.scripts = {
        {"surface_image.py", {frequency, "--color-by=density", "--image-size=800x800"}}};
  }
  else
  {
    // 3D: slices through the ball and the hump, and the dense region with its
    // upper half (z > 0.5) cut away.
    options.scripts = {
        {"slice_image.py", {frequency, "--color-by=density", "--slices=x=0.3,y=0.3,z=0.5"}},
        {"surface_image.py",
         {frequency, "--color-by=density", "--select-field=density", "--select-range=1.5,1e30",
          "--cut-away=0,1,0,1,0.5,1", "--file-prefix=region"}}};
  }
  options.scripts.push_back(
      {"selection_extract.py",
       {frequency, "--selection=range", "--value-field=density", "--value-range=1.5,1e30"}});
  options.scripts.push_back({"data_extracts.py", {frequency}});
  options.outputDirectory = o.output;
  return options;
}

// ---- Canopy (3 of 4): each tree this rank has blocks of, breadth-first ----
/// A tree's nodes breadth-first (the root, its children x fastest, ...): refined
/// or not, absent (another rank's part: a leaf here, described by its coarsest
/// node), and for this rank's blocks their place in its block list.
struct TreeTables
{
  std::vector<std::vector<std::uint8_t>> refinement, absent;
  std::vector<std::vector<std::int64_t>> blockIndex;
  std::vector<canopy::TreeDescription> trees;
};

TreeTables describeTrees(const BlockMesh& mesh, std::int64_t first, std::int64_t end)
{
  TreeTables tables;
  std::vector<int> described;
  for (int t = 0; t < mesh.numberOfTrees(); ++t)
  {
    const std::vector<BlockMesh::Node>& nodes = mesh.nodesOfTree(t);
    if (nodes[0].endBlock <= first || nodes[0].firstBlock >= end)
      continue; // no block of this tree here: another rank has it all
    std::vector<std::uint8_t> refinement, absent;
    std::vector<std::int64_t> blockIndex;
    std::vector<std::int32_t> queue{0};
    for (std::size_t q = 0; q < queue.size(); ++q)
    {
      const BlockMesh::Node& node = nodes[static_cast<std::size_t>(queue[q])];
      const bool here = node.firstBlock < end && node.endBlock > first; // some blocks are
      const bool refined = here && node.firstChild >= 0;
      refinement.push_back(refined);
      absent.push_back(!here);
      blockIndex.push_back(here && !refined ? node.firstBlock - first : -1);
      for (int c = 0; refined && c < mesh.childrenPerBlock(); ++c)
        queue.push_back(node.firstChild + c);
    }
    tables.refinement.push_back(std::move(refinement));
    tables.absent.push_back(std::move(absent));
    tables.blockIndex.push_back(std::move(blockIndex));
    described.push_back(t);
  }
  for (std::size_t n = 0; n < described.size(); ++n)
  {
    canopy::TreeDescription tree;
    tree.rootIndex = described[n];
    tree.refinement = tables.refinement[n].data();
    tree.numberOfNodes = tables.refinement[n].size();
    tree.absent = tables.absent[n].data();
    tree.blockIndex = tables.blockIndex[n].data();
    tables.trees.push_back(tree);
  }
  return tables;
}

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  Options options;
  try
  {
    options = parseOptions(argc, argv);
  }
  catch (const std::invalid_argument& error)
  {
    if (rank == 0)
      std::fprintf(stderr, "%s%s%s", error.what(), *error.what() ? "\n" : "", Usage);
    MPI_Finalize();
    return *error.what() ? 2 : 0;
  }
  BlockAdvection simulation(options, MPI_COMM_WORLD);
  const int dimension = options.dimension;
  // The root grid: 2 root blocks along each axis of [0, 1]^d (2D: the xy-plane).
  const std::vector<double> axis{0.0, 0.5, 1.0};
  const std::vector<double> flat{0.0};
  const std::vector<double>& z = dimension == 3 ? axis : flat;
  long failures = 0;

  canopy::InSitu insitu(MPI_COMM_WORLD, insituOptions(options));
  for (long step = 0; step <= options.steps; ++step)
  {
    const double time = simulation.timeStep() * static_cast<double>(step);
    if (step > 0)
    {
      simulation.advance();
      if (step % options.regridEvery == 0)
      {
        const long long before = simulation.mesh().numberOfBlocks();
        const BlockAdvection::Regrid done = simulation.regrid();
        if (rank == 0 && (done.refined || done.coarsened))
          std::printf("block_advection: step %ld: regrid: %lld -> %lld blocks, %lld made by "
                      "refining, %lld by coarsening\n",
                      step, before, static_cast<long long>(simulation.mesh().numberOfBlocks()),
                      static_cast<long long>(done.refined), static_cast<long long>(done.coarsened));
      }
    }
    if (step % options.every == 0)
    {
      const BlockAdvection::Totals all = simulation.totals();
      if (rank == 0)
      {
        const BlockMesh& mesh = simulation.mesh();
        std::string levels;
        for (int level = 0; level <= mesh.maxLevel(); ++level)
        {
          long long count = 0;
          for (std::int64_t b = 0; b < mesh.numberOfBlocks(); ++b)
            count += mesh.block(b).level == level;
          levels += (level ? ", " : "") + std::to_string(count);
        }
        std::printf("block_advection: step %ld: %lld blocks (by level %s), %lld cells, %lld with "
                    "density >= %g\n",
                    step, static_cast<long long>(mesh.numberOfBlocks()), levels.c_str(),
                    static_cast<long long>(mesh.numberOfBlocks()) *
                        static_cast<long long>(std::pow(CellsPerSide, dimension)),
                    all.dense, DenseFrom);
        // Full precision: the test compares Canopy's extracts with these.
        std::printf("block_advection: step %ld: mass %.17g, density from %.17g to %.17g\n", step,
                    all.mass, all.minimum, all.maximum);
        std::fflush(stdout);
      }
    }

    // ---- Canopy (4 of 4): describe this rank's blocks where they are, run what is due ----
    if (insitu.willExecute(step, time))
    {
      canopy::ForestDescription forest;
      forest.dimension = dimension;
      forest.maxLevels = simulation.mesh().maxLevel() + 1 + 4; // levels of blocks, 16 = 2^4 cells
      forest.rootGrid = {axis.data(), axis.data(), z.data(), axis.size(), axis.size(), z.size()};
      forest.blockCellsPerSide = 16;
      forest.missingTreesAreElsewhere = true; // other ranks have the rest of the trees
      const TreeTables tables =
          describeTrees(simulation.mesh(), simulation.firstBlock(), simulation.endBlock());
      forest.trees = tables.trees;
      std::vector<const double*> density, velocity; // where each block's variables begin
      for (const std::vector<double>& block : simulation.blocks())
      {
        density.push_back(block.data());
        velocity.push_back(block.data() + simulation.valuesPerVariable());
      }
      const auto strides = canopy::BlockStrides::variableOutermost<double>(dimension, 16, 2);
      forest.fields = {canopy::FieldDescription::blocks<double>("density", density.data(),
                                                                density.size(), strides),
                       canopy::FieldDescription::blocks<double>(
                           "velocity", velocity.data(), velocity.size(), strides, dimension)};
      const canopy::StepReport report = insitu.execute(step, time, forest);
      for (const std::string& failure : report.failures)
        std::fprintf(stderr, "canopy: %s\n", failure.c_str());
      failures += static_cast<long>(report.failures.size());
    }
  }
  insitu.close();
  MPI_Finalize();
  return failures == 0 ? 0 : 1;
}
