// The 3D surface of masked grids split between real MPI ranks (vtkMPIController
// as VTK's global controller, as Catalyst sets it): each rank draws its part,
// and the ranks ask each other about the faces between their parts
// (RemoteFaceExchange). Rank 0 gathers every rank's quads and checks them
// against the whole forest's voxels: exactly the faces between selected and
// unselected cells, each once, outward. Run with mpirun -np 1, 2 and 4.
#include "SelectedRegionCase.h"

#include <gtest/gtest.h>
#include <vtkMPIController.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>

#include <string>
#include <vector>

namespace canopy::testing
{
namespace
{

vtkMultiProcessController* world()
{
  return vtkMultiProcessController::GetGlobalController();
}

/// Every rank's quads on rank 0 (empty elsewhere).
std::vector<Quad> gatherQuads(const std::vector<Quad>& mine)
{
  std::vector<double> corners;
  for (const Quad& q : mine)
  {
    for (const Point& p : q.p)
    {
      corners.insert(corners.end(), p.begin(), p.end());
    }
  }
  vtkMultiProcessController* c = world();
  const int ranks = c->GetNumberOfProcesses();
  const vtkIdType length = static_cast<vtkIdType>(corners.size());
  std::vector<vtkIdType> lengths(static_cast<std::size_t>(ranks), 0);
  c->Gather(&length, lengths.data(), 1, 0);
  std::vector<vtkIdType> offsets(static_cast<std::size_t>(ranks), 0);
  vtkIdType total = 0;
  for (int r = 0; r < ranks; ++r)
  {
    offsets[static_cast<std::size_t>(r)] = total;
    total += lengths[static_cast<std::size_t>(r)];
  }
  std::vector<double> all(static_cast<std::size_t>(std::max<vtkIdType>(total, 1)));
  double unused = 0;
  c->GatherV(corners.empty() ? &unused : corners.data(), all.data(), length, lengths.data(),
             offsets.data(), 0);
  std::vector<Quad> quads;
  for (vtkIdType i = 0; c->GetLocalProcessId() == 0 && i + 12 <= total; i += 12)
  {
    std::array<Point, 4> p;
    for (int k = 0; k < 4; ++k)
    {
      for (int a = 0; a < 3; ++a)
      {
        p[k][a] = all[static_cast<std::size_t>(i + 3 * k + a)];
      }
    }
    quads.push_back(quadOf(p));
  }
  return quads;
}

std::string label(const std::string& field, std::uint64_t seed)
{
  return field + ", seed " + std::to_string(seed) + ", " +
         std::to_string(world()->GetNumberOfProcesses()) + " ranks";
}

TEST(SplitTreeSurfaces, SelectedRegionOfTreesSplitBetweenRanksIsExact)
{
  const int rank = world()->GetLocalProcessId();
  const int ranks = world()->GetNumberOfProcesses();
  for (const char* field : {"node", "hash"})
    for (std::uint64_t seed : {3u, 8u, 13u})
    {
      SelectedRegionCase region(seed, field);
      // Each rank's part as p4est would split it: trees cut between ranks.
      RankPart part(region.whole.description(), rank, ranks, rank % 2 == 1);
      const auto mine = selectedSurface(buildHyperTreeGrid(part.description), region.field,
                                        region.range, region.cutAway);
      const auto all = gatherQuads(mine);
      if (rank == 0)
      {
        expectExactBoundary(Voxels(region.oracle), all, label(field, seed));
      }
    }
}

TEST(SplitTreeSurfaces, SelectedRegionOfWholeTreesOnRanksIsExact)
{
  // Whole trees per rank (the mini-app's decomposition): a root cell without a
  // tree here has it on another rank.
  const int rank = world()->GetLocalProcessId();
  const int ranks = world()->GetNumberOfProcesses();
  for (const char* field : {"node", "hash"})
    for (std::uint64_t seed : {5u, 21u})
    {
      SelectedRegionCase region(seed, field);
      const ForestDescription& whole = region.whole.description();
      ForestDescription mine;
      mine.dimension = whole.dimension;
      mine.branchFactor = whole.branchFactor;
      mine.maxLevels = whole.maxLevels;
      mine.rootGrid = whole.rootGrid;
      mine.missingTreesAreElsewhere = true;
      std::vector<double> values;
      std::vector<double> hashes;
      for (std::size_t t = 0; t < whole.trees.size(); ++t)
      {
        if (static_cast<int>(t % static_cast<std::size_t>(ranks)) != rank)
        {
          continue;
        }
        mine.trees.push_back(
            {whole.trees[t].rootIndex, whole.trees[t].refinement, whole.trees[t].numberOfNodes});
        for (std::size_t n = 0; n < whole.trees[t].numberOfNodes; ++n)
        {
          values.push_back(wholeValue(t, n));
          hashes.push_back(wholeHash(t, n));
        }
      }
      mine.fields.push_back(FieldDescription::aos("node", values.data(), values.size()));
      mine.fields.push_back(FieldDescription::aos("hash", hashes.data(), hashes.size()));
      const auto quads = gatherQuads(
          selectedSurface(buildHyperTreeGrid(mine), region.field, region.range, region.cutAway));
      if (rank == 0)
      {
        expectExactBoundary(Voxels(region.oracle), quads, label(field, seed));
      }
    }
}

} // namespace
} // namespace canopy::testing
