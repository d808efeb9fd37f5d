// Canopy's VTKHDF writer from plain C++, without Catalyst: a simulation whose
// trees are split between ranks the way p4est splits them (each rank describes
// its part, other ranks' parts absent) builds its grid and appends two steps to
// one file through canopy::io::VtkHdfWriter on MPI_COMM_WORLD.
//
// Rank 0 also writes forest_<step>.json (tests/support/grid_extract_expectations.py):
// every rank's part (a tree split over k ranks is in k pieces), absent cells as
// masked, and values at sampled cells of every part, vtkGhostType included
// (DUPLICATECELL, 1, where absent), for tests/support/vtkhdf_check.py.
//
// Usage: mpirun -np N canopy_split_forest_write --output DIR
#include "ForestJson.h"
#include "PartitionedForest.h"
#include "RandomForest.h"

#include <VtkHdfWriter.h>
#include <canopy/HtgBuilder.h>

#include <mpi.h>
#include <vtkHyperTreeGrid.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace
{

using canopy::testing::PartitionedTree;

/// What the simulation keeps for a node of the whole forest at a step: unique per node.
double wholeValue(std::size_t tree, std::size_t node, int step)
{
  return 1000.0 * static_cast<double>(tree) + static_cast<double>(node) + 0.25 + 0.5 * step;
}

/// One rank's part, stored depth-first (slot maps), present nodes only.
struct RankPart
{
  std::vector<PartitionedTree> trees;
  std::vector<std::vector<std::int64_t>> slots;
  std::vector<double> nodeValues;   // present nodes, slot order
  std::vector<double> vectorValues; // 3 per present node
  std::vector<double> leafValues;   // present leaves, slot order
  canopy::ForestDescription description;

  RankPart(const canopy::ForestDescription& whole, int rank, int ranks, int step)
      : trees(canopy::testing::partitionForRank(whole, rank, ranks))
  {
    description.dimension = whole.dimension;
    description.branchFactor = whole.branchFactor;
    description.maxLevels = whole.maxLevels;
    description.rootGrid = whole.rootGrid;
    description.missingTreesAreElsewhere = true;
    const std::size_t children = childrenOf(whole);
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
    }
    for (std::size_t t = 0; t < trees.size(); ++t)
    {
      description.trees.push_back({trees[t].rootIndex, trees[t].refinement.data(),
                                   trees[t].refinement.size(), nullptr, slots[t].data(),
                                   trees[t].absent.data()});
    }
    using canopy::FieldDescription;
    description.fields.push_back(
        FieldDescription::aos("node", nodeValues.data(), nodeValues.size()));
    description.fields.push_back(
        FieldDescription::aos("vector", vectorValues.data(), nodeValues.size(), 3));
    description.fields.push_back(FieldDescription::aos("leaf", leafValues.data(), leafValues.size(),
                                                       1, canopy::Centering::LeavesOnly));
  }

  static std::size_t childrenOf(const canopy::ForestDescription& f)
  {
    std::size_t children = 1;
    for (int d = 0; d < f.dimension; ++d)
      children *= static_cast<std::size_t>(f.branchFactor);
    return children;
  }

  static std::vector<std::size_t> firstChildren(const PartitionedTree& tree, std::size_t children)
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
};

/// Canopy's restriction for the leaves-only field: the mean of the present children.
double leafField(const PartitionedTree& tree, const std::vector<std::size_t>& first,
                 std::size_t children, std::size_t n, int step)
{
  if (tree.absent[n])
    return std::nan("");
  if (!tree.refinement[n])
    return wholeValue(tree.wholeTree, tree.wholeNode[n], step);
  double sum = 0.0;
  int used = 0;
  for (std::size_t c = 0; c < children; ++c)
  {
    if (!tree.absent[first[n] + c])
    {
      sum += leafField(tree, first, children, first[n] + c, step);
      ++used;
    }
  }
  return sum / used;
}

std::string number(double value)
{
  if (std::isnan(value))
    return "NaN";
  std::ostringstream text;
  text << std::setprecision(17) << value;
  return text.str();
}

std::string forestJson(const canopy::ForestDescription& whole, int ranks, int step, double time)
{
  std::ostringstream json;
  const std::size_t children = RankPart::childrenOf(whole);
  canopy::testing::writeForestJsonHeader(json, whole, step, time, ranks);
  json << ", \"fields\": {\"node\": {\"components\": 1, \"leaves_only\": false}, "
          "\"vector\": {\"components\": 3, \"leaves_only\": false}, "
          "\"leaf\": {\"components\": 1, \"leaves_only\": true}}, \"trees\": [";
  std::ostringstream samples;
  bool firstTree = true;
  bool firstSample = true;
  for (int rank = 0; rank < ranks; ++rank)
  {
    for (const auto& tree : canopy::testing::partitionForRank(whole, rank, ranks))
    {
      std::string refinement, mask;
      for (std::size_t n = 0; n < tree.refinement.size(); ++n)
      {
        refinement += tree.refinement[n] ? '1' : '0';
        mask += tree.absent[n] ? '1' : '0';
      }
      json << (firstTree ? "\n  " : ",\n  ") << "{\"root\": " << tree.rootIndex
           << ", \"rank\": " << rank << ", \"refinement\": \"" << refinement << "\", \"mask\": \""
           << mask << "\"}";
      firstTree = false;
      // Every 7th cell of each part, and its root, present or absent.
      const auto first = RankPart::firstChildren(tree, children);
      for (std::size_t n = 0; n < tree.refinement.size(); n += n == 0 ? 1 : 7)
      {
        const bool absent = tree.absent[n] != 0;
        const double value =
            absent ? std::nan("") : wholeValue(tree.wholeTree, tree.wholeNode[n], step);
        samples << (firstSample ? "\n  " : ",\n  ") << "{\"rank\": " << rank
                << ", \"root\": " << tree.rootIndex << ", \"node\": " << n
                << ", \"values\": {\"node\": [" << number(value) << "], \"vector\": ["
                << number(value) << ", " << number(2.0 * value) << ", " << number(-value)
                << "], \"leaf\": [" << number(leafField(tree, first, children, n, step))
                << "], \"vtkGhostType\": [" << (absent ? 1 : 0) << "]}}";
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
    if (argc != 3 || std::string(argv[1]) != "--output")
      throw std::invalid_argument("usage: canopy_split_forest_write --output DIR");
    const std::filesystem::path output = argv[2];
    std::filesystem::create_directories(output);
    canopy::testing::RandomForestOptions options;
    options.dimension = 2;
    options.rootCells = {{4, 3, 1}};
    options.maxLevels = 6;
    options.refineProbability = 0.55;
    options.seed = 11;
    const canopy::testing::RandomForest whole(options);

    // The simulation's own writer object, kept for the run: each call appends a step.
    canopy::io::VtkHdfWriter writer(MPI_COMM_WORLD, (output / "grid.vtkhdf").string());
    for (int step = 0; step < 2; ++step)
    {
      const double time = 0.5 * step;
      const RankPart part(whole.description(), rank, ranks, step);
      if (rank == 0)
        std::ofstream(output / ("forest_" + std::to_string(step) + ".json"))
            << forestJson(whole.description(), ranks, step, time);
      const auto htg = canopy::buildHyperTreeGrid(part.description);
      writer.writeStep(htg, step, time);
      if (rank == 0)
        std::cout << "step " << step << " executed ran 1 failures 0" << std::endl;
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
