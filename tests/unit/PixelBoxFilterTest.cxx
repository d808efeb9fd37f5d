// Colours box-filtered on the pixel grid (PixelBoxFilter.h), through the
// filters' public properties: a quad that holds exactly one pixel centre shows
// that pixel's area-weighted average colour, computed here independently, pixel
// by pixel over the leaves' squares; quads seen otherwise than face-on, or in
// more than one plane, keep their own colours.
#include "CheckerboardForest.h"
#include "ErrorMessages.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSlice.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkColorTransferFunction.h>
#include <vtkHyperTreeGrid.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>

namespace canopy::testing
{
namespace
{

/// Black at 0, white at 1: a leaf of the checkerboard is 0 or 255 exactly.
vtkSmartPointer<vtkColorTransferFunction> grey()
{
  auto map = vtkSmartPointer<vtkColorTransferFunction>::New();
  map->AddRGBPoint(0.0, 0, 0, 0);
  map->AddRGBPoint(1.0, 1, 1, 1);
  return map;
}

int redOf(vtkPolyData* out, vtkIdType cell)
{
  auto* colors = vtkUnsignedCharArray::SafeDownCast(out->GetCellData()->GetArray("Colors"));
  return colors ? colors->GetComponent(cell, 0) : -1;
}

/// `pixels` x `pixels` over the unit square, looking down z.
template <typename Filter>
void lookFromAbove(Filter* filter, int pixels, double up[3] = nullptr)
{
  filter->SetCameraPosition(0.5, 0.5, 10);
  filter->SetCameraFocalPoint(0.5, 0.5, 0.5);
  if (up)
  {
    filter->SetCameraViewUp(up);
  }
  filter->SetParallelScale(0.5);
  filter->SetViewportSize(pixels, pixels);
  filter->LevelOfDetailOff();
  filter->SetColorMap(grey());
  filter->SetColorField("value");
}

TEST(PixelBoxFilter, AQuadHoldingOnePixelCentreShowsThatPixelsAverage)
{
  // 8 x 8 leaves seen by 6 x 6 pixels: a leaf is 0.75 pixel, not aligned with
  // them; each holds no pixel centre or one.
  CheckerboardForest board(2, 3);
  vtkNew<vtkCanopyAdaptiveSurface> surface;
  surface->SetInputData(buildHyperTreeGrid(board.forest));
  lookFromAbove(surface.Get(), 6);
  ASSERT_TRUE(errorsOfUpdate(surface).empty());
  vtkPolyData* out = surface->GetPolyDataOutput();
  ASSERT_EQ(out->GetNumberOfCells(), 64);
  // Every pixel centre lies in exactly one leaf: 36 leaves recoloured.
  EXPECT_EQ(surface->GetLastPixelFiltered(), 36);
  const double leaf = 1.0 / 8;
  const double pixel = 1.0 / 6;
  int checked = 0;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    double b[6];
    out->GetCellBounds(c, b);
    // The pixel whose centre the leaf holds, if any.
    const int i = static_cast<int>(std::ceil(b[0] / pixel - 0.5));
    const int j = static_cast<int>(std::ceil(b[2] / pixel - 0.5));
    const bool holds = (i + 0.5) * pixel >= b[0] && (i + 0.5) * pixel < b[1] &&
                       (j + 0.5) * pixel >= b[2] && (j + 0.5) * pixel < b[3];
    // The leaf's own value: white where (column + row) is odd.
    const int column = static_cast<int>(std::lround(b[0] / leaf));
    const int row = static_cast<int>(std::lround(b[2] / leaf));
    const double ownRed = (column + row) % 2 ? 255.0 : 0.0;
    if (!holds)
    {
      EXPECT_EQ(redOf(out, c), ownRed) << "leaf " << column << ", " << row << " holds no centre";
      continue;
    }
    // Brute force: the pixel's area-weighted average over the 64 leaf squares.
    double sum = 0;
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x)
      {
        const double w = std::max(0.0, std::min((i + 1) * pixel, (x + 1) * leaf) -
                                           std::max(i * pixel, x * leaf));
        const double h = std::max(0.0, std::min((j + 1) * pixel, (y + 1) * leaf) -
                                           std::max(j * pixel, y * leaf));
        sum += w * h * ((x + y) % 2 ? 255.0 : 0.0);
      }
    EXPECT_NEAR(redOf(out, c), sum / (pixel * pixel), 0.5 + 1e-9)
        << "leaf " << column << ", " << row << " in pixel " << i << ", " << j;
    ++checked;
  }
  EXPECT_EQ(checked, 36);
}

TEST(PixelBoxFilter, QuadsNotSeenFaceOnKeepTheirColours)
{
  CheckerboardForest board(2, 3);
  auto htg = buildHyperTreeGrid(board.forest);
  for (int variant = 0; variant < 2; ++variant)
  {
    vtkNew<vtkCanopyAdaptiveSurface> surface;
    surface->SetInputData(htg);
    double tilted[3] = {std::sin(0.3), std::cos(0.3), 0}; // the screen turned: not rectangles
    lookFromAbove(surface.Get(), 6, variant == 0 ? tilted : nullptr);
    if (variant == 1)
    {
      surface->FilterColorsOnPixelsOff();
    }
    ASSERT_TRUE(errorsOfUpdate(surface).empty());
    vtkPolyData* out = surface->GetPolyDataOutput();
    EXPECT_EQ(surface->GetLastPixelFiltered(), 0) << variant;
    for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
    {
      double b[6];
      out->GetCellBounds(c, b);
      const int column = static_cast<int>(std::lround(b[0] * 8));
      const int row = static_cast<int>(std::lround(b[2] * 8));
      EXPECT_EQ(redOf(out, c), (column + row) % 2 ? 255 : 0) << variant;
    }
  }
}

TEST(PixelBoxFilter, SlicesOneBehindTheOtherAreNotMixed)
{
  // Two z slices overlap on screen: not filtered. One z slice and one x slice
  // (seen edge-on): the z slice is.
  CheckerboardForest board(3, 3);
  auto htg = buildHyperTreeGrid(board.forest);
  vtkNew<vtkCanopyAdaptiveSlice> two;
  two->SetInputData(htg);
  two->AddPlane(2, 0.3);
  two->AddPlane(2, 0.6);
  lookFromAbove(two.Get(), 6);
  ASSERT_TRUE(errorsOfUpdate(two).empty());
  EXPECT_EQ(two->GetPolyDataOutput()->GetNumberOfCells(), 128);
  EXPECT_EQ(two->GetLastPixelFiltered(), 0);
  vtkNew<vtkCanopyAdaptiveSlice> crossed;
  crossed->SetInputData(htg);
  crossed->AddPlane(2, 0.3);
  crossed->AddPlane(0, 0.6);
  lookFromAbove(crossed.Get(), 6);
  ASSERT_TRUE(errorsOfUpdate(crossed).empty());
  EXPECT_EQ(crossed->GetLastPixelFiltered(), 36);
}

} // namespace
} // namespace canopy::testing
