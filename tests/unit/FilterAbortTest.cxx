// Aborting the filters, as ParaView's progress handler or a script does: an
// observer of the filter's ProgressEvent sets AbortExecute at the first
// intermediate progress. Each filter must report intermediate progress (not
// only VTK's own 0 and 1), stop walking trees once aborted (what it examined
// and what it output far below a full execution's), report no error, and leave
// an empty output; the next execution is whole again. With the Sequential and
// the STDThread backends (the abort is seen between batches of trees, and per
// tree on the pipeline's thread: TreeProgress.h).
#include "ErrorMessages.h"
#include "RandomForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSlice.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>
#include <canopy/filters/vtkCanopyContour.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <gtest/gtest.h>
#include <vtkBitArray.h>
#include <vtkCallbackCommand.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkUnstructuredGrid.h>

#include <functional>
#include <memory>
#include <string>

namespace canopy::testing
{
namespace
{

/// A forest of many small trees: 40 x 40 roots in 2D, 12 x 12 x 12 in 3D. The
/// grid borrows the forest's arrays: both are kept.
struct ManyTrees
{
  std::unique_ptr<RandomForest> forest;
  vtkSmartPointer<vtkHyperTreeGrid> htg;

  explicit ManyTrees(int dimension)
  {
    RandomForestOptions o;
    o.dimension = dimension;
    o.rootCells = dimension == 2 ? std::array<std::size_t, 3>{{40, 40, 1}}
                                 : std::array<std::size_t, 3>{{12, 12, 12}};
    o.maxLevels = dimension == 2 ? 5 : 4;
    o.refineProbability = 0.5;
    o.maskProbability = 0.05;
    o.seed = 22;
    forest = std::make_unique<RandomForest>(o);
    htg = buildHyperTreeGrid(forest->description());
  }
};

/// What an execution showed of its progress.
struct Progress
{
  int events = 0;
  int intermediate = 0; ///< events strictly between 0 and 1
  bool abortAtFirstIntermediate = false;
};

void onProgress(vtkObject* caller, unsigned long, void* data, void* callData)
{
  auto* progress = static_cast<Progress*>(data);
  const double fraction = *static_cast<double*>(callData);
  ++progress->events;
  if (fraction > 0 && fraction < 1)
  {
    ++progress->intermediate;
    if (progress->abortAtFirstIntermediate)
    {
      static_cast<vtkAlgorithm*>(caller)->AbortExecuteOn();
    }
  }
}

/// What an execution showed: its progress events and the errors it reported.
struct Watched
{
  Progress progress;
  std::vector<std::string> errors;
};

/// One execution of `filter` (re-executed: Modified), aborted at its first
/// intermediate progress or not; `beforeEach` runs first when given.
Watched run(vtkAlgorithm* filter, bool abort, const std::function<void()>& beforeEach)
{
  if (beforeEach)
  {
    beforeEach();
  }
  Watched watched;
  watched.progress.abortAtFirstIntermediate = abort;
  vtkNew<vtkCallbackCommand> observer;
  observer->SetClientData(&watched.progress);
  observer->SetCallback(onProgress);
  const unsigned long tag = filter->AddObserver(vtkCommand::ProgressEvent, observer);
  filter->Modified();
  watched.errors = errorsOfUpdate(filter);
  filter->RemoveObserver(tag);
  return watched;
}

/// The full execution, an aborted one and a full one again, with both SMP
/// backends: the aborted one must have reported progress, stopped early and
/// left an empty output, without an error. `size()`: what the filter output;
/// `work()`: what it examined (nodes), when it says; `beforeEach()`: what makes
/// each execution a whole one for a filter that keeps work from before.
void expectAbortStopsEarly(const std::string& name, vtkAlgorithm* filter,
                           const std::function<vtkIdType()>& size,
                           const std::function<vtkIdType()>& work = {},
                           const std::function<void()>& beforeEach = {})
{
  for (const char* backend : {"Sequential", "STDThread"})
  {
    vtkSMPTools::SetBackend(backend);
    SCOPED_TRACE(name + " with the " + backend + " backend");
    const Watched full = run(filter, false, beforeEach);
    ASSERT_TRUE(full.errors.empty()) << full.errors.front();
    const vtkIdType fullSize = size();
    const vtkIdType fullWork = work ? work() : 0;
    ASSERT_GT(fullSize, 1000) << "too small to tell an early stop";
    EXPECT_GT(full.progress.intermediate, 1) << "the filter reports its progress";

    const Watched aborted = run(filter, true, beforeEach);
    EXPECT_TRUE(aborted.errors.empty()) << aborted.errors.front();
    EXPECT_GT(aborted.progress.events, 1);
    EXPECT_GE(aborted.progress.intermediate, 1);
    EXPECT_LT(aborted.progress.intermediate, full.progress.intermediate)
        << "no progress reported after the abort";
    EXPECT_EQ(size(), 0) << "an aborted execution leaves an empty output (full: " << fullSize
                         << ")";
    if (work)
    {
      EXPECT_LT(work(), fullWork / 2) << "nodes examined after the abort";
    }

    // Nothing the aborted execution left (kept buffers, memos) changes the next,
    // once the caller has reset the flag (VTK leaves that to it).
    filter->AbortExecuteOff();
    const Watched again = run(filter, false, beforeEach);
    EXPECT_TRUE(again.errors.empty());
    EXPECT_EQ(size(), fullSize);
  }
  vtkSMPTools::SetBackend("Sequential");
}

TEST(FilterAbort, AdaptiveSurfaceStopsPerTree)
{
  for (int dimension : {2, 3})
  {
    const ManyTrees grid(dimension);
    vtkNew<vtkCanopyAdaptiveSurface> filter;
    filter->SetInputData(grid.htg);
    // The view sees the whole grid: nothing is culled.
    filter->SetCameraPosition(20, 20, 100);
    filter->SetCameraFocalPoint(20, 20, 0);
    filter->SetParallelScale(1e4);
    filter->LevelOfDetailOff();
    expectAbortStopsEarly(std::to_string(dimension) + "D surface", filter,
                          [&] { return filter->GetPolyDataOutput()->GetNumberOfCells(); });
  }
}

TEST(FilterAbort, AdaptiveSliceStopsPerTree)
{
  const ManyTrees grid(3);
  double b[6];
  grid.htg->GetBounds(b);
  vtkNew<vtkCanopyAdaptiveSlice> filter;
  filter->SetInputData(grid.htg);
  filter->ViewDependentOff();
  for (int axis = 0; axis < 3; ++axis)
  {
    filter->AddPlane(axis, 0.5 * (b[2 * axis] + b[2 * axis + 1]));
  }
  expectAbortStopsEarly(
      "slice", filter, [&] { return filter->GetPolyDataOutput()->GetNumberOfCells(); },
      [&] { return filter->GetLastVisited(); });
}

TEST(FilterAbort, ExtractSelectionStopsPerTree)
{
  const ManyTrees grid(3);
  double b[6];
  grid.htg->GetBounds(b);
  for (bool preserveTopology : {false, true})
  {
    vtkNew<vtkCanopyExtractSelection> filter;
    filter->SetInputData(grid.htg);
    filter->SetSelectionMode(vtkCanopyExtractSelection::BOX);
    filter->SetBox(b);
    filter->SetPreserveTopology(preserveTopology);
    expectAbortStopsEarly(
        preserveTopology ? "masked selection" : "extracted selection", filter,
        [&]
        {
          vtkDataObject* out = filter->GetOutputDataObject(0);
          if (auto* grid = vtkHyperTreeGrid::SafeDownCast(out))
          {
            if (!grid->HasMask())
            {
              return grid->GetNumberOfCells();
            }
            // The cells the mask leaves visible.
            vtkBitArray* mask = grid->GetMask();
            vtkIdType visible = 0;
            for (vtkIdType c = 0; c < mask->GetNumberOfTuples(); ++c)
            {
              visible += mask->GetValue(c) == 0;
            }
            return visible;
          }
          return vtkUnstructuredGrid::SafeDownCast(out)->GetNumberOfCells();
        },
        [&] { return filter->GetLastVisited(); },
        [&]
        {
          // Every tree changed (its modified time): the masked selection keeps
          // no tree's mask from the execution before (SelectionMaskMemo).
          vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
          grid.htg->InitializeTreeIterator(it);
          vtkIdType index = 0;
          while (vtkHyperTree* tree = it.GetNextTree(index))
          {
            tree->Modified();
          }
        });
  }
}

TEST(FilterAbort, ContourStopsPerChunk)
{
  for (int dimension : {2, 3})
  {
    const ManyTrees grid(dimension);
    // A field that crosses its contour value in most dual cells.
    vtkNew<vtkDoubleArray> field;
    field->SetName("f");
    field->SetNumberOfTuples(grid.htg->GetNumberOfCells());
    for (vtkIdType c = 0; c < field->GetNumberOfTuples(); ++c)
    {
      field->SetValue(c, static_cast<double>((c * 2654435761u) % 1000) / 1000.0);
    }
    grid.htg->GetCellData()->AddArray(field);
    vtkNew<vtkCanopyContour> filter;
    filter->SetInputData(grid.htg);
    filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "f");
    filter->SetValue(0, 0.5);
    expectAbortStopsEarly(
        std::to_string(dimension) + "D contour", filter,
        [&] { return filter->GetOutput()->GetNumberOfCells(); },
        [&] { return filter->GetLastVisited() + filter->GetLastDualCells(); });
  }
}

} // namespace
} // namespace canopy::testing
