// Pixel-filtered colours (PixelBoxFilter.h) of a 2D forest whose tree is split
// between real MPI ranks (p4est's partition): a pixel at the edge of a rank's
// part is overlapped by other ranks' quads, which the ranks exchange. Rank 0
// gathers every rank's quads and colours and checks them against the same
// filter run on the whole forest in one process: equal (within the rounding of
// a sum taken in another order). The same run without the exchange must
// differ on 2 or more ranks, or the comparison proves nothing.
#include "CheckerboardForest.h"
#include "RankPart.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkColorTransferFunction.h>
#include <vtkHyperTreeGrid.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace canopy::testing
{
namespace
{

vtkMultiProcessController* world()
{
  return vtkMultiProcessController::GetGlobalController();
}

/// Quad centre (rounded to a grid far finer than a leaf) -> colour.
using Colours = std::map<std::pair<long, long>, std::array<int, 3>>;

/// Surface colours of `htg` seen by 48 x 48 pixels over the unit square, a
/// third of a pixel off the leaves; `controller`: the exchange (none: each rank alone).
std::vector<double> colouredQuads(vtkHyperTreeGrid* htg, vtkMultiProcessController* controller,
                                  vtkIdType* filtered = nullptr)
{
  vtkNew<vtkColorTransferFunction> map;
  map->AddRGBPoint(0.0, 0.0, 0.0, 0.0);
  map->AddRGBPoint(1.0, 1.0, 1.0, 1.0);
  vtkNew<vtkCanopyAdaptiveSurface> surface;
  surface->SetInputData(htg);
  surface->SetController(controller);
  const double third = 1.0 / 48 / 3;
  surface->SetCameraPosition(0.5 + third, 0.5 + third, 10);
  surface->SetCameraFocalPoint(0.5 + third, 0.5 + third, 0);
  surface->SetParallelScale(0.5);
  surface->SetViewportSize(48, 48);
  surface->SetColorMap(map);
  surface->SetColorField("hash");
  surface->Update();
  if (filtered)
  {
    *filtered = surface->GetLastPixelFiltered();
  }
  vtkPolyData* out = surface->GetPolyDataOutput();
  auto* colors = vtkUnsignedCharArray::SafeDownCast(out->GetCellData()->GetArray("Colors"));
  std::vector<double> rows; // centre x, centre y, r, g, b
  for (vtkIdType c = 0; colors && c < out->GetNumberOfCells(); ++c)
  {
    double b[6];
    out->GetCellBounds(c, b);
    rows.insert(rows.end(), {0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), colors->GetComponent(c, 0),
                             colors->GetComponent(c, 1), colors->GetComponent(c, 2)});
  }
  return rows;
}

Colours keyed(const std::vector<double>& rows)
{
  Colours colours;
  for (std::size_t i = 0; i + 5 <= rows.size(); i += 5)
  {
    colours[{std::lround(rows[i] * 1e6), std::lround(rows[i + 1] * 1e6)}] = {
        {static_cast<int>(rows[i + 2]), static_cast<int>(rows[i + 3]),
         static_cast<int>(rows[i + 4])}};
  }
  return colours;
}

/// Every rank's rows on every rank.
std::vector<double> gathered(const std::vector<double>& mine)
{
  vtkMultiProcessController* c = world();
  const int ranks = c->GetNumberOfProcesses();
  const vtkIdType length = static_cast<vtkIdType>(mine.size());
  std::vector<vtkIdType> lengths(static_cast<std::size_t>(ranks), 0);
  c->AllGather(&length, lengths.data(), 1);
  std::vector<vtkIdType> offsets(static_cast<std::size_t>(ranks), 0);
  vtkIdType total = 0;
  for (int r = 0; r < ranks; ++r)
  {
    offsets[static_cast<std::size_t>(r)] = total;
    total += lengths[static_cast<std::size_t>(r)];
  }
  std::vector<double> all(static_cast<std::size_t>(std::max<vtkIdType>(total, 1)));
  double unused = 0;
  c->AllGatherV(mine.empty() ? &unused : mine.data(), all.data(), length, lengths.data(),
                offsets.data());
  all.resize(static_cast<std::size_t>(total));
  return all;
}

/// Quads whose colour differs by more than `tolerance` in a channel, or that
/// one side lacks.
int differences(const Colours& a, const Colours& b, int tolerance)
{
  int count = 0;
  for (const auto& [at, colour] : a)
  {
    const auto other = b.find(at);
    bool same = other != b.end();
    for (int k = 0; same && k < 3; ++k)
    {
      same = std::abs(colour[k] - other->second[k]) <= tolerance;
    }
    count += same ? 0 : 1;
  }
  return count + static_cast<int>(b.size() > a.size() ? b.size() - a.size() : 0);
}

TEST(SplitColours, PixelFilteredColoursDoNotDependOnTheRanks)
{
  const int rank = world()->GetLocalProcessId();
  const int ranks = world()->GetNumberOfProcesses();
  CheckerboardForest whole(2, 6); // 64 x 64 leaves: 0.75 pixel each
  RankPart part(whole.forest, rank, ranks, rank % 2 == 1);
  ASSERT_FALSE(part.description.trees.empty()) << "rank " << rank << " has no part";
  vtkIdType filtered = 0;
  const Colours split =
      keyed(gathered(colouredQuads(buildHyperTreeGrid(part.description), world(), &filtered)));
  const Colours alone =
      keyed(gathered(colouredQuads(buildHyperTreeGrid(part.description), nullptr)));
  // The reference: the whole forest in one process, its "hash" field as the
  // parts have it.
  RankPart everything(whole.forest, 0, 1, false);
  const Colours reference =
      keyed(colouredQuads(buildHyperTreeGrid(everything.description), nullptr));
  ASSERT_EQ(reference.size(), 64u * 64u);
  EXPECT_GT(filtered, 0);
  EXPECT_EQ(differences(split, reference, 1), 0) << ranks << " ranks";
  if (ranks > 1)
  {
    // Without the exchange the pixels at the parts' edges lose their other
    // ranks' share: this comparison can tell.
    EXPECT_GT(differences(alone, reference, 1), 0) << ranks << " ranks";
  }
}

} // namespace
} // namespace canopy::testing
