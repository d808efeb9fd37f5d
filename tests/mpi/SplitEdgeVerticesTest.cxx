// T-junctions across ranks (EdgeVertexExchange.h): where a rank's flat piece
// meets finer pieces of another rank along an edge, their corners must be on
// its edge, although this rank knows nothing of the grid there. Every rank
// slices or draws its part of a forest split between the ranks (p4est's
// partition, trees cut between ranks; and whole trees per rank); rank 0 gathers
// all the pieces and checks each against all the others' corners: exactly
// them for slices and 2D surfaces (every neighbour drawn: culling off), at
// least them for 3D faces. Run with mpirun -np 1, 2 and 4.
#include "FlatPolygons.h"
#include "GatherPieces.h"
#include "LevelJumpForest.h"
#include "RandomForest.h"
#include "RankForestPart.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSlice.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>

#include <gtest/gtest.h>
#include <vtkHyperTreeGrid.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include <array>
#include <memory>
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

/// This rank's part of `whole` (RankForestPart.h).
vtkSmartPointer<vtkHyperTreeGrid> partOf(const ForestDescription& whole, bool splitTrees,
                                         std::shared_ptr<void>& keep)
{
  return rankForestPart(whole, splitTrees, world()->GetLocalProcessId(),
                        world()->GetNumberOfProcesses(), keep);
}

/// The whole forest's bounds (every rank's: a rank's part may not reach them).
void domainBounds(const ForestDescription& whole, double b[6])
{
  const double* coords[3] = {whole.rootGrid.x, whole.rootGrid.y, whole.rootGrid.z};
  const std::size_t sizes[3] = {whole.rootGrid.pointsX, whole.rootGrid.pointsY,
                                whole.rootGrid.pointsZ};
  for (int a = 0; a < 3; ++a)
  {
    b[2 * a] = coords[a][0];
    b[2 * a + 1] = coords[a][sizes[a] - 1];
  }
}

/// A view of the whole domain from above and aside, culling off (every piece
/// drawn, so that every corner a piece needs is in the output); level of
/// detail at `threshold` pixels, or none (0: no view).
void viewWholeDomain(vtkCanopyViewDependentFilter* filter, const double b[6], double threshold)
{
  if (threshold == 0)
  {
    filter->ViewDependentOff();
    return;
  }
  filter->SetCameraFocalPoint((b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2);
  filter->SetCameraPosition(b[1] + 1.5 * (b[1] - b[0]), b[2] - (b[3] - b[2]), b[5] + 3);
  filter->SetCameraViewUp(0, 0, 1);
  filter->ParallelProjectionOff();
  filter->SetViewAngle(30);
  filter->SetViewportSize(240, 180);
  filter->SetViewCulling(false);
  filter->SetPixelThreshold(threshold);
}

std::string label(const std::string& what, bool splitTrees, double threshold)
{
  return what + (splitTrees ? ", trees split" : ", whole trees") + ", threshold " +
         std::to_string(threshold) + ", " + std::to_string(world()->GetNumberOfProcesses()) +
         " ranks";
}

/// Rank 0 checks every rank's pieces against one another; returns the
/// vertices on their edges (0 elsewhere).
std::size_t expectCornersOnEdges(vtkPolyData* mine, bool exact, const std::string& what)
{
  vtkSmartPointer<vtkPolyData> all = gatherPieces(mine);
  if (world()->GetLocalProcessId() != 0)
  {
    return 0;
  }
  EXPECT_GT(all->GetNumberOfCells(), 0) << what;
  return expectEdgeVerticesAreNeighboursCorners(all, what, exact);
}

TEST(SplitEdgeVertices, SlicesCarryTheCornersOfEveryRanksCuts)
{
  const LevelJumpForest jumps({{4, 4, 2}}, 1, 4, false);
  RandomForestOptions o;
  o.rootCells = {{3, 3, 2}};
  o.maxLevels = 6;
  o.refineProbability = 0.5;
  o.seed = 23;
  const RandomForest random(o);
  std::size_t vertices = 0;
  for (const ForestDescription* whole : {&jumps.description(), &random.description()})
  {
    for (bool splitTrees : {true, false})
    {
      std::shared_ptr<void> keep;
      auto grid = partOf(*whole, splitTrees, keep);
      double b[6];
      domainBounds(*whole, b);
      for (double threshold : {0.0, 3.0})
      {
        vtkNew<vtkCanopyAdaptiveSlice> slice;
        slice->SetInputData(grid);
        slice->AddZPlane(b[4] + 0.37 * (b[5] - b[4]));
        slice->AddXPlane(b[0] + 0.61 * (b[1] - b[0]));
        viewWholeDomain(slice, b, threshold);
        slice->Update();
        vertices += expectCornersOnEdges(slice->GetPolyDataOutput(), true,
                                         label("slices", splitTrees, threshold));
      }
    }
  }
  if (world()->GetLocalProcessId() == 0)
  {
    EXPECT_GT(vertices, 100u);
  }
}

TEST(SplitEdgeVertices, SurfacesCarryTheCornersOfEveryRanksPieces)
{
  RandomForestOptions flat;
  flat.dimension = 2;
  flat.rootCells = {{5, 4, 1}};
  flat.maxLevels = 7;
  flat.refineProbability = 0.5;
  flat.seed = 29;
  const RandomForest plane(flat);
  const LevelJumpForest jumps({{4, 3, 2}}, 1, 3, true);
  std::size_t vertices = 0;
  for (const ForestDescription* whole : {&plane.description(), &jumps.description()})
  {
    const bool solid = whole->dimension == 3;
    for (bool splitTrees : {true, false})
    {
      std::shared_ptr<void> keep;
      auto grid = partOf(*whole, splitTrees, keep);
      double b[6];
      domainBounds(*whole, b);
      for (double threshold : {0.0, 3.0})
      {
        vtkNew<vtkCanopyAdaptiveSurface> surface;
        surface->SetInputData(grid);
        viewWholeDomain(surface, b, threshold);
        surface->Update();
        vertices +=
            expectCornersOnEdges(surface->GetPolyDataOutput(), !solid,
                                 label(solid ? "3D surface" : "2D surface", splitTrees, threshold));
      }
    }
  }
  if (world()->GetLocalProcessId() == 0)
  {
    EXPECT_GT(vertices, 100u);
  }
}

} // namespace
} // namespace canopy::testing
