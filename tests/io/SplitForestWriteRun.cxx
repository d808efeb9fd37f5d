// Canopy's VTKHDF writer from plain C++, without Catalyst: a simulation whose
// forest is shared between ranks builds its grid and appends steps to one file
// through canopy::io::VtkHdfWriter on MPI_COMM_WORLD. The forest's kind (--kind)
// picks its dimension, branch factor, masks, holes and how ranks share it: trees
// split the way p4est splits them (each rank describes its part, other ranks'
// parts absent), whole trees per rank, or one rank with nothing at all.
//
// Rank 0 also writes forest_<step>.json (tests/support/grid_extract_expectations.py):
// every rank's part (a tree split over k ranks is in k pieces), absent and masked
// cells as masked, and values at sampled cells of every part, vtkGhostType included
// (DUPLICATECELL, 1, where absent) when the ranks describe absent parts, for
// tests/support/vtkhdf_check.py.
//
// Usage: mpirun -np N canopy_split_forest_write --output DIR [--kind KIND]
#include "ForestJson.h"
#include "PartitionedForest.h"
#include "RandomForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/io/VtkHdfWriter.h>

#include <mpi.h>
#include <vtkHyperTreeGrid.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{

using canopy::testing::PartitionedTree;
using canopy::testing::RandomForest;
using canopy::testing::RandomForestOptions;

/// How the ranks share the forest.
enum class Sharing
{
  MortonLeaves,       ///< p4est's partition: trees split between ranks, absent parts described
  WholeTrees,         ///< each tree on one rank, contiguous blocks of trees, no absent parts
  MortonLeavesOneIdle ///< as MortonLeaves over all ranks but one, which has nothing (it changes
                      ///< with the step, so the empty piece is first, in between and last)
};

struct Kind
{
  RandomForestOptions forest;
  Sharing sharing = Sharing::MortonLeaves;
  int steps = 2;
  /// A new random forest at each step (seed + step): each step's offsets must be its own.
  bool newForestEachStep = true;
};

RandomForestOptions forestOptions(int dimension, int branchFactor, std::array<std::size_t, 3> roots,
                                  int maxLevels, double refineProbability, std::uint64_t seed)
{
  RandomForestOptions options;
  options.dimension = dimension;
  options.branchFactor = branchFactor;
  options.rootCells = roots;
  options.maxLevels = maxLevels;
  options.refineProbability = refineProbability;
  options.seed = seed;
  return options;
}

/// Every kind of forest Canopy writes, a few hundred to a few thousand cells each.
std::map<std::string, Kind> kinds()
{
  std::map<std::string, Kind> all;
  all["split-2d"] = {forestOptions(2, 2, {{4, 3, 1}}, 6, 0.55, 11), Sharing::MortonLeaves, 2,
                     false};
  all["binary-3d"] = {forestOptions(3, 2, {{3, 2, 2}}, 4, 0.45, 21), Sharing::WholeTrees};
  all["split-3d"] = {forestOptions(3, 2, {{3, 2, 1}}, 5, 0.45, 31)};
  Kind ternary2d{forestOptions(2, 3, {{3, 1, 2}}, 4, 0.4, 41)};
  ternary2d.forest.flatAxis = 1; // the xz plane
  all["ternary-2d"] = ternary2d;
  all["ternary-3d"] = {forestOptions(3, 3, {{2, 2, 2}}, 3, 0.35, 51)};
  Kind line{forestOptions(1, 2, {{1, 6, 1}}, 8, 0.75, 61)};
  line.forest.activeAxis = 1; // along y
  all["line-1d"] = line;
  Kind absent{forestOptions(2, 2, {{1, 4, 3}}, 6, 0.6, 71), Sharing::MortonLeavesOneIdle, 3};
  absent.forest.flatAxis = 0;              // the yz plane
  absent.forest.skipEveryOtherRoot = true; // holes in the root grid
  all["absent"] = absent;
  Kind masked{forestOptions(3, 2, {{2, 2, 2}}, 4, 0.5, 81)};
  masked.forest.maskProbability = 0.15;
  all["masked-3d"] = masked;
  return all;
}

/// What the simulation keeps for a node of the whole forest at a step: unique per node.
double wholeValue(std::size_t tree, std::size_t node, int step)
{
  return 100000.0 * static_cast<double>(tree) + static_cast<double>(node) + 0.25 + 0.5 * step;
}

std::size_t childrenOf(const canopy::ForestDescription& f)
{
  std::size_t children = 1;
  for (int d = 0; d < f.dimension; ++d)
    children *= static_cast<std::size_t>(f.branchFactor);
  return children;
}

std::vector<std::size_t> firstChildren(const PartitionedTree& tree, std::size_t children)
{
  std::vector<std::size_t> first(tree.refinement.size(), 0);
  for (std::size_t n = 0, next = 1; n < tree.refinement.size(); ++n)
  {
    if (tree.refinement[n])
    {
      first[n] = next;
      next += children;
    }
  }
  return first;
}

/// Rank `rank`'s trees, as the kind shares the forest.
std::vector<PartitionedTree> treesOfRank(const RandomForest& whole, Sharing sharing, int rank,
                                         int ranks, int step)
{
  const auto& forest = whole.description();
  if (sharing == Sharing::MortonLeaves || ranks == 1)
    return canopy::testing::partitionForRank(forest, rank, ranks);
  if (sharing == Sharing::MortonLeavesOneIdle)
  {
    const int idle = ((ranks - 1 - step) % ranks + ranks) % ranks;
    if (rank == idle)
      return {};
    return canopy::testing::partitionForRank(forest, rank < idle ? rank : rank - 1, ranks - 1);
  }
  std::vector<PartitionedTree> trees;
  const std::size_t count = forest.trees.size();
  for (std::size_t t = 0; t < count; ++t)
  {
    if (static_cast<int>(t * static_cast<std::size_t>(ranks) / count) != rank)
      continue;
    PartitionedTree tree;
    tree.rootIndex = forest.trees[t].rootIndex;
    tree.wholeTree = t;
    tree.refinement = whole.refinement()[t];
    tree.absent.assign(tree.refinement.size(), 0);
    for (std::size_t n = 0; n < tree.refinement.size(); ++n)
      tree.wholeNode.push_back(n);
    trees.push_back(std::move(tree));
  }
  return trees;
}

/// The simulation's mask of a rank's tree (absent nodes not masked: they are not its own).
std::vector<std::uint8_t> maskOf(const RandomForest& whole, const PartitionedTree& tree)
{
  const auto& masked = whole.masked()[tree.wholeTree];
  std::vector<std::uint8_t> mask(tree.refinement.size(), 0);
  for (std::size_t n = 0; !masked.empty() && n < mask.size(); ++n)
    mask[n] = !tree.absent[n] && masked[tree.wholeNode[n]];
  return mask;
}

/// One rank's part, stored depth-first (slot maps), present nodes only.
struct RankPart
{
  std::vector<PartitionedTree> trees;
  std::vector<std::vector<std::int64_t>> slots;
  std::vector<std::vector<std::uint8_t>> masks;
  std::vector<double> nodeValues;   // present nodes, slot order
  std::vector<double> vectorValues; // 3 per present node
  std::vector<double> leafValues;   // present leaves, slot order
  canopy::ForestDescription description;

  RankPart(const RandomForest& whole, const Kind& kind, int rank, int ranks, int step)
      : trees(treesOfRank(whole, kind.sharing, rank, ranks, step))
  {
    description.dimension = whole.description().dimension;
    description.branchFactor = whole.description().branchFactor;
    description.maxLevels = whole.description().maxLevels;
    description.rootGrid = whole.description().rootGrid;
    description.missingTreesAreElsewhere = !kind.forest.skipEveryOtherRoot;
    const std::size_t children = childrenOf(whole.description());
    std::int64_t next = 0;
    for (const auto& tree : trees)
    {
      std::vector<std::int64_t> slot(tree.refinement.size(), -1);
      const std::vector<std::size_t> first = firstChildren(tree, children);
      auto walk = [&](auto& self, std::size_t n) -> void
      {
        if (tree.absent[n])
          return;
        slot[n] = next++;
        const double value = wholeValue(tree.wholeTree, tree.wholeNode[n], step);
        nodeValues.push_back(value);
        vectorValues.insert(vectorValues.end(), {value, 2.0 * value, -value});
        if (!tree.refinement[n])
          leafValues.push_back(value);
        for (std::size_t c = 0; tree.refinement[n] && c < children; ++c)
          self(self, first[n] + c);
      };
      walk(walk, 0);
      slots.push_back(std::move(slot));
      masks.push_back(maskOf(whole, tree));
    }
    const bool describeAbsent = kind.sharing != Sharing::WholeTrees;
    const bool describeMask = kind.forest.maskProbability > 0;
    for (std::size_t t = 0; t < trees.size(); ++t)
    {
      description.trees.push_back({trees[t].rootIndex, trees[t].refinement.data(),
                                   trees[t].refinement.size(),
                                   describeMask ? masks[t].data() : nullptr, slots[t].data(),
                                   describeAbsent ? trees[t].absent.data() : nullptr});
    }
    using canopy::FieldDescription;
    description.fields.push_back(
        FieldDescription::aos("node", nodeValues.data(), nodeValues.size()));
    description.fields.push_back(
        FieldDescription::aos("vector", vectorValues.data(), nodeValues.size(), 3));
    description.fields.push_back(FieldDescription::aos("leaf", leafValues.data(), leafValues.size(),
                                                       1, canopy::Centering::LeavesOnly));
  }
};

/// Canopy's restriction for the leaves-only field (docs/api.md): the mean of the
/// present unmasked children, of every present child if all are masked.
double leafField(const PartitionedTree& tree, const std::vector<std::uint8_t>& mask,
                 const std::vector<std::size_t>& first, std::size_t children, std::size_t n,
                 int step)
{
  if (tree.absent[n])
    return std::nan("");
  if (!tree.refinement[n])
    return wholeValue(tree.wholeTree, tree.wholeNode[n], step);
  for (int pass = 0; pass < 2; ++pass)
  {
    double sum = 0.0;
    int used = 0;
    for (std::size_t c = 0; c < children; ++c)
    {
      const std::size_t child = first[n] + c;
      if (tree.absent[child] || (pass == 0 && mask[child]))
        continue;
      sum += leafField(tree, mask, first, children, child, step);
      ++used;
    }
    if (used > 0)
      return sum / used;
  }
  return std::nan("");
}

std::string number(double value)
{
  if (std::isnan(value))
    return "NaN";
  std::ostringstream text;
  text << std::setprecision(17) << value;
  return text.str();
}

std::string forestJson(const RandomForest& whole, const Kind& kind, int ranks, int step,
                       double time)
{
  std::ostringstream json;
  const std::size_t children = childrenOf(whole.description());
  const bool ghosts = kind.sharing != Sharing::WholeTrees;
  canopy::testing::writeForestJsonHeader(json, whole.description(), step, time, ranks);
  json << ", \"fields\": {\"node\": {\"components\": 1, \"leaves_only\": false}, "
          "\"vector\": {\"components\": 3, \"leaves_only\": false}, "
          "\"leaf\": {\"components\": 1, \"leaves_only\": true}}, \"trees\": [";
  std::ostringstream samples;
  bool firstTree = true;
  bool firstSample = true;
  for (int rank = 0; rank < ranks; ++rank)
  {
    for (const auto& tree : treesOfRank(whole, kind.sharing, rank, ranks, step))
    {
      const std::vector<std::uint8_t> mask = maskOf(whole, tree);
      std::string refinement, hidden;
      for (std::size_t n = 0; n < tree.refinement.size(); ++n)
      {
        refinement += tree.refinement[n] ? '1' : '0';
        hidden += tree.absent[n] || mask[n] ? '1' : '0';
      }
      json << (firstTree ? "\n  " : ",\n  ") << "{\"root\": " << tree.rootIndex
           << ", \"rank\": " << rank << ", \"refinement\": \"" << refinement << "\", \"mask\": \""
           << hidden << "\"}";
      firstTree = false;
      // Every 7th cell of each part, and its root, present or absent.
      const auto first = firstChildren(tree, children);
      for (std::size_t n = 0; n < tree.refinement.size(); n += n == 0 ? 1 : 7)
      {
        const bool absent = tree.absent[n] != 0;
        const double value =
            absent ? std::nan("") : wholeValue(tree.wholeTree, tree.wholeNode[n], step);
        samples << (firstSample ? "\n  " : ",\n  ") << "{\"rank\": " << rank
                << ", \"root\": " << tree.rootIndex << ", \"node\": " << n
                << ", \"values\": {\"node\": [" << number(value) << "], \"vector\": ["
                << number(value) << ", " << number(2.0 * value) << ", " << number(-value)
                << "], \"leaf\": [" << number(leafField(tree, mask, first, children, n, step))
                << "]";
        if (ghosts)
          samples << ", \"vtkGhostType\": [" << (absent ? 1 : 0) << "]";
        samples << "}}";
        firstSample = false;
      }
    }
  }
  json << "],\n \"samples\": [" << samples.str() << "]}\n";
  return json.str();
}

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  int status = 0;
  try
  {
    const auto all = kinds();
    std::map<std::string, std::string> arguments{{"--kind", "split-2d"}};
    for (int i = 1; i + 1 < argc; i += 2)
      arguments[argv[i]] = argv[i + 1];
    const std::string output = arguments["--output"], kindName = arguments["--kind"];
    if (argc % 2 == 0 || arguments.size() != 2 || output.empty() || !all.count(kindName))
    {
      std::string names;
      for (const auto& entry : all)
        names += " " + entry.first;
      throw std::invalid_argument(
          "usage: canopy_split_forest_write --output DIR [--kind KIND], KIND one of:" + names);
    }
    const Kind& kind = all.at(kindName);
    std::filesystem::create_directories(output);

    // The simulation's own writer object, kept for the run: each call appends a step.
    canopy::io::VtkHdfWriter writer(MPI_COMM_WORLD,
                                    (std::filesystem::path(output) / "grid.vtkhdf").string());
    for (int step = 0; step < kind.steps; ++step)
    {
      const double time = 0.5 * step;
      RandomForestOptions options = kind.forest;
      if (kind.newForestEachStep)
        options.seed += static_cast<std::uint64_t>(step);
      const RandomForest whole(options);
      const RankPart part(whole, kind, rank, ranks, step);
      if (rank == 0)
        std::ofstream(std::filesystem::path(output) / ("forest_" + std::to_string(step) + ".json"))
            << forestJson(whole, kind, ranks, step, time);
      const auto htg = canopy::buildHyperTreeGrid(part.description);
      writer.writeStep(htg, step, time);
      if (rank == 0)
        std::cout << "step " << step << " executed ran 1 failures 0 (" << kindName << ", "
                  << whole.numberOfNodes() << " cells)" << std::endl;
    }
  }
  catch (const std::exception& error)
  {
    std::cerr << "rank " << rank << ": " << error.what() << "\n";
    status = 1;
  }
  MPI_Finalize();
  return status;
}
