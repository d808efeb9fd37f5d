// Level of detail that filters (LeafColorAverage.h): a node drawn for level of
// detail shows the area-weighted average of its visible leaves' mapped colours,
// not its mapped (volume-averaged) value. Closed forms: a "tent" colour map
// (black at 0, white at 0.5, black at 1) over leaves valued 0 and 1 averages to
// black, while the coarse value 0.5 maps to white; leaves at full resolution
// show their own mapped colour; a slice's coarse cut averages the cut leaves only.
#include "CheckerboardForest.h"
#include "ErrorMessages.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSlice.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkColorTransferFunction.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <array>
#include <cmath>
#include <vector>

namespace canopy::testing
{
namespace
{

vtkSmartPointer<vtkColorTransferFunction> tent()
{
  auto map = vtkSmartPointer<vtkColorTransferFunction>::New();
  map->AddRGBPoint(0.0, 0, 0, 0);
  map->AddRGBPoint(0.5, 1, 1, 1);
  map->AddRGBPoint(1.0, 0, 0, 0);
  return map;
}

std::array<int, 3> colorOf(vtkPolyData* out, vtkIdType cell)
{
  auto* colors = vtkUnsignedCharArray::SafeDownCast(out->GetCellData()->GetArray("Colors"));
  EXPECT_NE(colors, nullptr);
  std::array<int, 3> rgb{{-1, -1, -1}};
  for (int k = 0; colors && k < 3; ++k)
  {
    rgb[k] = colors->GetComponent(cell, k);
  }
  return rgb;
}

template <typename Filter>
void lookFromAbove(Filter* filter, double scale, int pixels, double threshold)
{
  filter->SetCameraPosition(0.5, 0.5, 10);
  filter->SetCameraFocalPoint(0.5, 0.5, 0.5);
  filter->SetParallelScale(scale);
  filter->SetViewportSize(pixels, pixels);
  filter->SetPixelThreshold(threshold);
}

TEST(LevelOfDetailColors, ACoarseQuadShowsItsLeavesAverageColourNotItsValuesColour)
{
  CheckerboardForest board(2, 4); // 16 x 16 leaves
  auto htg = buildHyperTreeGrid(board.forest);
  auto map = tent();
  vtkNew<vtkCanopyAdaptiveSurface> surface;
  surface->SetInputData(htg);
  surface->SetColorMap(map);
  surface->SetColorField("value");
  // 8 x 8 pixels over the unit square: the leaves are half a pixel, a level-3
  // node one pixel: level of detail stops there (4 leaves, 0, 1, 1, 0).
  lookFromAbove(surface.Get(), 0.5, 8, 1.0);
  ASSERT_TRUE(errorsOfUpdate(surface).empty());
  vtkPolyData* out = surface->GetPolyDataOutput();
  ASSERT_EQ(out->GetNumberOfCells(), 64);
  vtkDataArray* values = out->GetCellData()->GetArray("value");
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    EXPECT_EQ(values->GetTuple1(c), 0.5) << "the coarse value keeps its meaning";
    EXPECT_EQ(colorOf(out, c), (std::array<int, 3>{{0, 0, 0}})) << "cell " << c;
  }
  // Full resolution: each leaf its own colour (black, 0 and 1 both map to black),
  // and a field whose leaves are 0.25 and 0.75 maps to grey each.
  for (std::size_t i = 0; i < board.values.size(); ++i)
  {
    if (board.values[i] != 0.5)
    {
      board.values[i] = board.values[i] == 0 ? 0.25 : 0.75;
    }
  }
  htg->Modified();
  htg->GetCellData()->GetArray("value")->Modified();
  surface->ViewDependentOff();
  ASSERT_TRUE(errorsOfUpdate(surface).empty());
  out = surface->GetPolyDataOutput();
  ASSERT_EQ(out->GetNumberOfCells(), 256);
  double rgb[3];
  map->GetColor(0.25, rgb);
  const int grey = static_cast<int>(std::lround(255 * rgb[0]));
  EXPECT_GT(grey, 100);
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    EXPECT_EQ(colorOf(out, c), (std::array<int, 3>{{grey, grey, grey}})) << "leaf " << c;
  }
}

TEST(LevelOfDetailColors, ASliceCutAveragesTheCutLeavesOnly)
{
  // 3D, 16^3 leaves; the plane z = 0.3 cuts the layer k = 4 (a checkerboard of
  // 0 and 1), every other leaf is 0.5 (white). The coarse cuts of level-3 nodes
  // cover 2 x 2 cut leaves, 0, 1, 1, 0: black; their whole subtrees (2 x 2 x 2,
  // half of them white) would be grey.
  CheckerboardForest board(3, 4);
  // Leaves are stored breadth-first, not by (i, j, k): each one's k follows
  // from its place under its ancestors.
  {
    std::vector<long> zOf{0};
    std::size_t first = 0;
    for (int level = 0; level < 4; ++level)
    {
      std::vector<long> next;
      for (long z : zOf)
        for (int c = 0; c < 8; ++c)
          next.push_back(2 * z + ((c >> 2) & 1));
      first += zOf.size();
      zOf = next;
    }
    for (std::size_t n = 0; n < zOf.size(); ++n)
    {
      if (zOf[n] != 4)
      {
        board.values[first + n] = 0.5;
      }
    }
  }
  auto htg = buildHyperTreeGrid(board.forest);
  vtkNew<vtkCanopyAdaptiveSlice> slice;
  slice->SetInputData(htg);
  slice->AddPlane(2, 0.3);
  slice->SetColorMap(tent());
  slice->SetColorField("value");
  lookFromAbove(slice.Get(), 0.5, 8, 1.0);
  ASSERT_TRUE(errorsOfUpdate(slice).empty());
  vtkPolyData* out = slice->GetPolyDataOutput();
  ASSERT_EQ(out->GetNumberOfCells(), 64);
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    EXPECT_EQ(colorOf(out, c), (std::array<int, 3>{{0, 0, 0}})) << "cut " << c;
  }
}

TEST(LevelOfDetailColors, ALogarithmicMapIsSampledInLogSpace)
{
  // Leaves valued 0.01 and 100 on a black-to-white log map over [1e-3, 1e3]:
  // 1/6 and 5/6 of the way. Sampled evenly in the value instead, 0.01 would fall
  // between the samples 0.001 and 0.98 and come out nearly black.
  CheckerboardForest board(2, 1);
  for (std::size_t n = 1; n < board.values.size(); ++n)
  {
    board.values[n] = board.values[n] > 0.5 ? 100.0 : 0.01;
  }
  vtkNew<vtkLookupTable> map;
  map->SetScaleToLog10();
  map->SetRange(1e-3, 1e3);
  map->SetHueRange(0, 0);
  map->SetSaturationRange(0, 0);
  map->SetValueRange(0, 1);
  map->SetNumberOfTableValues(1024);
  map->Build();
  vtkNew<vtkCanopyAdaptiveSurface> surface;
  surface->SetInputData(buildHyperTreeGrid(board.forest));
  surface->SetColorMap(map);
  surface->SetColorField("value");
  surface->ViewDependentOff();
  ASSERT_TRUE(errorsOfUpdate(surface).empty());
  vtkPolyData* out = surface->GetPolyDataOutput();
  ASSERT_EQ(out->GetNumberOfCells(), 4);
  auto* values = out->GetCellData()->GetArray("value");
  for (vtkIdType c = 0; c < 4; ++c)
  {
    double rgb[3];
    map->GetColor(values->GetComponent(c, 0), rgb);
    EXPECT_NEAR(colorOf(out, c)[0], 255 * rgb[0], 1.0) << "value " << values->GetComponent(c, 0);
  }
  // The two colours: about 1/6 and 5/6 of the ramp.
  EXPECT_NEAR(colorOf(out, 0)[0] + colorOf(out, 1)[0], 255.0, 2.0);
}

TEST(LevelOfDetailColors, AColourFieldThatDoesNotExistIsAnError)
{
  CheckerboardForest board(2, 2);
  vtkNew<vtkCanopyAdaptiveSurface> surface;
  surface->SetInputData(buildHyperTreeGrid(board.forest));
  surface->SetColorMap(tent());
  surface->SetColorField("pressure");
  const auto errors = errorsOfUpdate(surface);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("pressure"), std::string::npos) << errors[0];
}

} // namespace
} // namespace canopy::testing
