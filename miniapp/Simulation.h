// The mini-app's simulation on one MPI rank: an advected (optionally diffused)
// scalar on the leaves of an adaptive forest, explicit and conservative.
//
// Layout (the simulation's own): every rank knows every tree's topology; it
// stores values only for the trees it owns, leaves-only, tree by tree in tree
// order and breadth-first within a tree: `scalar` (double), `velocity` (3
// doubles per leaf, interleaved), `level` and `rank` (doubles). Canopy reads
// these arrays in place every step (see describeForCanopy).
//
// With --blocks N the simulation also keeps, per own leaf, a block of N^d cells
// as a block-structured code would (allocated one by one, 2 ghost cells per side
// left NaN, variables [var][k][j][i]): the leaf's fields sampled at the cells'
// centres (sampleBlocks). Canopy then sees a block forest and reads the blocks.
#pragma once

#include "AmrForest.h"
#include "ExactSolution.h"
#include "HaloExchange.h"
#include "MiniAppOptions.h"
#include "MovingObjects.h"

#include <canopy/ForestDescription.h>

#include <mpi.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace miniamr
{

class Simulation
{
public:
  /// Collective. Builds the initial mesh around the objects and the initial blob.
  Simulation(const MiniAppOptions& options, MPI_Comm communicator);

  /// Collective. One time step: halo exchange, finite-volume update, then (every
  /// regridEvery steps) refinement/coarsening and, when imbalanced, repartition.
  void advance();

  /// The steps to run: --steps, or with --end-time as many as reach it.
  int plannedSteps() const { return Options.steps; }
  int step() const { return Step; }
  double time() const { return Time; }
  double timeStep() const { return Dt; }
  /// Collective: sum of value x volume over every leaf.
  double totalMass() const;
  /// Collective: (max leaves on a rank) / (mean leaves per rank).
  double imbalance() const;
  std::int64_t globalLeaves() const { return Forest.totalLeaves(); }
  /// This rank's leaves (of the trees it owns).
  std::int64_t localLeaves() const { return static_cast<std::int64_t>(Scalar.size()); }
  std::int64_t globalNodes() const { return Forest.totalNodes(); }
  int repartitions() const { return Repartitions; }

  /// This rank's trees and leaves-only fields, borrowed: valid until advance().
  /// With --blocks, a block forest over the blocks sampleBlocks last filled.
  canopy::ForestDescription describeForCanopy() const;

  /// --blocks N, collective (one halo exchange): fills every own leaf's block from
  /// the current state, cell (i, j, k) at centre x:
  ///  - scalar: the leaf's value u plus limited slopes, u + sum_a s_a (x_a - c_a),
  ///    c the leaf's centre: s_a the minmod of the one-sided differences to the
  ///    face neighbours along axis a (the leaves across a face as one: area-weighted
  ///    means of their values and centre distances), all scaled down together where
  ///    the block's corner cells would leave the range of u and its face neighbours'
  ///    values. The block's mean is u (conservative); no new extremum;
  ///  - velocity: the prescribed velocity at x (exact);
  ///  - level, rank: the leaf's level and owner.
  /// Call it before describeForCanopy on steps where Canopy runs.
  void sampleBlocks();
  /// The variables of a block, outermost: [var][k][j][i].
  enum BlockVariable
  {
    BlockScalar = 0,
    BlockVelocity = 1, ///< 3 variables: vx, vy, vz
    BlockLevel = 4,
    BlockRank = 5,
    BlockVariables = 6
  };
  static constexpr int BlockGhosts = 2;
  /// --blocks N: value of `variable` in interior cell (i, j, k) of own leaf `index`'s
  /// block (index in storage order, as dump and forEachOwnLeaf), and the block's
  /// whole array ((N + 4)^d values per variable: 2 ghosts per side, included).
  double blockValue(std::size_t index, int variable, int i, int j, int k) const;
  const double* blockArray(std::size_t index) const { return Blocks[index].get(); }
  std::size_t blockValuesPerVariable() const { return BlockExtentValues; }
  std::size_t ownBlocks() const { return BlockTables.empty() ? 0 : BlockTables[0].size(); }

  /// A hash of every array Canopy borrows (to prove Canopy never writes them).
  std::uint64_t borrowedArraysChecksum() const;

  /// Collective: rank 0 writes every leaf as "level x y z value" sorted by key.
  void dump(const std::string& path) const;

  /// Errors of the leaves' values against the exact solution's cell averages now.
  struct ExactErrors
  {
    double l1 = 0;  ///< sum of |error| x volume over every leaf
    double max = 0; ///< largest |error| of any leaf
  };
  /// Collective; only with --exact-solution (throws otherwise).
  ExactErrors errorsAgainstExact() const;

  const AmrForest& forest() const { return Forest; }
  const MovingObjects& objects() const { return Objects; }
  /// This rank's value of an own leaf (tree, leaf), or NaN if not owned.
  double valueOf(std::int32_t tree, std::int32_t leaf) const;
  /// The objects' clock: like miniAMR, objects move a fixed distance per step
  /// (their velocities are in domain lengths per 100 steps), not with the flow.
  double objectClock() const { return Step / 100.0; }

private:
  /// Calls f(node, index) for each leaf of this rank's trees, in storage order
  /// (tree order, breadth-first): `index` is the leaf's place in the own-leaf arrays.
  template <typename F>
  void forEachOwnLeaf(F&& f) const
  {
    for (auto tree : OwnTrees)
    {
      const auto offset = LeafOffset[static_cast<std::size_t>(tree)];
      for (const auto& node : Forest.trees()[static_cast<std::size_t>(tree)].nodes)
        if (node.firstChild < 0)
          f(node, static_cast<std::size_t>(offset + node.leaf));
    }
  }
  /// Every own leaf's initial value (initialCellValue).
  void sampleInitialValues();
  double valueAcross(const AmrForest::FaceNeighbour& neighbour) const;
  std::array<double, 3> velocityAt(const std::array<double, 3>& x) const;
  double initialValue(const std::array<double, 3>& x) const;
  /// A new leaf's initial value: the exact cell average with --exact-solution,
  /// else the blob at the cell's center.
  double initialCellValue(const NodeKey& key) const;
  std::array<double, 3> cellSizes(int level) const;
  std::vector<std::int8_t> ownWishes(bool objectsOnly) const;
  /// The limited slope of the scalar along each axis in a leaf (sampleBlocks).
  std::array<double, 3> limitedSlopes(const Tree::Node& node, double u) const;
  /// Where interior cell (i, j, k) is in one variable's array of a block, in values.
  std::size_t blockOffset(int i, int j, int k) const;
  /// One regrid pass; objectsOnly: refine only where objects' surfaces are, and
  /// return false (nothing done) when no leaf there is below the finest level.
  bool regrid(bool initial, bool objectsOnly);
  void repartitionIfImbalanced(bool force);
  void afterTopologyChange();
  double computeTimeStep() const;

  MiniAppOptions Options;
  MPI_Comm Communicator;
  int Rank = 0;
  int Size = 1;
  AmrForest Forest;
  MovingObjects Objects;
  std::optional<TranslatedGaussian> Exact; ///< with --exact-solution: fixed mesh, no regrid

  std::vector<int> Owner;               ///< per tree
  std::vector<std::int64_t> LeafOffset; ///< per tree: first value index if owned, else -1
  std::vector<std::int32_t> OwnTrees;   ///< in tree order
  std::vector<double> Scalar;           ///< own leaves
  std::vector<double> Velocity;         ///< own leaves, 3 per leaf
  std::vector<double> Level;            ///< own leaves (leaves-only fields are averaged: doubles)
  std::vector<double> RankField;        ///< own leaves
  HaloExchange Halo;
  std::vector<double> RootX, RootY, RootZ;
  /// --blocks: one allocation per own leaf (storage order), reused across steps.
  std::vector<std::unique_ptr<double[]>> Blocks;
  std::size_t BlockExtentValues = 0; ///< (N + 4)^d: one variable of one block
  /// Per field (scalar, velocity, level, rank): where its variable starts in each block.
  std::vector<std::vector<const double*>> BlockTables;
  int BlocksSampledAt = -1; ///< the step sampleBlocks last ran at
  int Step = 0;
  double Time = 0.0;
  double Dt = 0.0;
  int Repartitions = 0;
};

} // namespace miniamr
