// What the contour's exchange between ranks costs (ContourGhosts.h): a random
// forest split between the ranks as p4est splits it (trees cut between ranks),
// each rank contouring its part; per execution, the slowest rank's time for the
// whole filter and for the exchange in it (finding the border leaves, the
// AllGatherV, indexing what came), and the bytes each rank received.
//
//   mpirun -np N canopy_bench_contour_ranks [--roots R] [--levels L] [--repetitions K]
//
// Defaults: 6^3 roots, 6 levels (refinement probability 0.5), 5 repetitions.
#include "NodeCentreField.h"
#include "RandomForest.h"
#include "RankPart.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyContour.h>

#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkMPIController.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>

int main(int argc, char** argv)
{
  vtkNew<vtkMPIController> controller;
  controller->Initialize(&argc, &argv);
  vtkMultiProcessController::SetGlobalController(controller);
  const int rank = controller->GetLocalProcessId();
  const int ranks = controller->GetNumberOfProcesses();
  std::size_t roots = 6;
  int levels = 6;
  int repetitions = 5;
  for (int i = 1; i + 1 < argc; i += 2)
  {
    if (!std::strcmp(argv[i], "--roots"))
    {
      roots = static_cast<std::size_t>(std::atoi(argv[i + 1]));
    }
    else if (!std::strcmp(argv[i], "--levels"))
    {
      levels = std::atoi(argv[i + 1]);
    }
    else if (!std::strcmp(argv[i], "--repetitions"))
    {
      repetitions = std::atoi(argv[i + 1]);
    }
    else
    {
      std::fprintf(stderr, "unknown option %s\n", argv[i]);
      return 2;
    }
  }
  canopy::testing::RandomForestOptions o;
  o.dimension = 3;
  o.rootCells = {{roots, roots, roots}};
  o.maxLevels = levels;
  o.refineProbability = 0.5;
  o.seed = 5;
  canopy::testing::RandomForest whole(o);
  canopy::testing::RankPart part(whole.description(), rank, ranks, false);
  vtkSmartPointer<vtkHyperTreeGrid> grid = canopy::buildHyperTreeGrid(part.description);
  double bounds[6];
  grid->GetBounds(bounds);
  // The whole domain's centre (a rank's part may not reach it).
  double centre[3] = {0, 0, 0};
  controller->AllReduce(bounds, centre, 1, vtkCommunicator::MIN_OP);
  double high = 0;
  controller->AllReduce(bounds + 1, &high, 1, vtkCommunicator::MAX_OP);
  centre[0] = centre[1] = centre[2] = 0.5 * (centre[0] + high);
  canopy::testing::addNodeCentreField(
      grid, "distance",
      [&](const double* x)
      {
        const double d[3] = {x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]};
        return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      });
  // The whole forest's leaves (a rank's part also has other ranks' parts as
  // absent leaves).
  vtkIdType leaves = 0;
  if (rank == 0)
  {
    vtkSmartPointer<vtkHyperTreeGrid> all = canopy::buildHyperTreeGrid(whole.description());
    vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
    all->InitializeTreeIterator(it);
    vtkIdType index = 0;
    while (vtkHyperTree* tree = it.GetNextTree(index))
    {
      leaves += tree->GetNumberOfLeaves();
    }
  }
  vtkNew<vtkCanopyContour> contour;
  contour->SetInputData(grid);
  contour->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "distance");
  contour->SetValue(0, 0.3 * (high - centre[0]) + 0.2 * centre[0]);
  double best[2] = {std::numeric_limits<double>::infinity(),
                    std::numeric_limits<double>::infinity()};
  double bytes = 0;
  vtkIdType triangles = 0;
  for (int r = 0; r < std::max(repetitions, 1); ++r)
  {
    grid->GetCellData()->GetArray("distance")->Modified(); // a new step's values
    contour->Modified();
    controller->Barrier();
    const auto start = std::chrono::steady_clock::now();
    contour->Update();
    const double mine[2] = {
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
        contour->GetLastGhostSeconds()};
    double slowest[2] = {0, 0};
    controller->AllReduce(mine, slowest, 2, vtkCommunicator::MAX_OP);
    best[0] = std::min(best[0], slowest[0]);
    best[1] = std::min(best[1], slowest[1]);
    const double received = static_cast<double>(contour->GetLastGhostBytesReceived());
    controller->AllReduce(&received, &bytes, 1, vtkCommunicator::MAX_OP);
    const vtkIdType cells = contour->GetOutput()->GetNumberOfCells();
    controller->AllReduce(&cells, &triangles, 1, vtkCommunicator::SUM_OP);
  }
  if (rank == 0)
  {
    std::printf("| %d | %lld | %lld | %.3f | %.3f (%.0f%%) | %.2f |\n", ranks,
                static_cast<long long>(leaves), static_cast<long long>(triangles), best[0], best[1],
                100 * best[1] / best[0], bytes / 1e6);
  }
  vtkMultiProcessController::SetGlobalController(nullptr);
  controller->Finalize();
  return 0;
}
