// The truth an image is measured against (ExactImage.h: every pixel the
// area-weighted average of the mapped colours of the cells it covers), checked
// in closed form on a checkerboard forest; and level of detail that filters
// (ColorMap + ColorField: coarse quads drawn with their leaves' average colour)
// measured against it, rendered under Xvfb: closer to the truth than every leaf
// drawn (which point-samples: aliasing), and than coarse quads drawn with their
// mapped volume-averaged value.
#include "CheckerboardForest.h"
#include "ExactImage.h"
#include "OffscreenRenderer.h"
#include "SyntheticForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSlice.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>

#include <gtest/gtest.h>
#include <vtkCamera.h>
#include <vtkHyperTreeGrid.h>
#include <vtkPolyData.h>
#include <vtkScalarsToColors.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <iostream>

namespace canopy::testing
{
namespace
{

const std::array<double, 3> White{{255, 255, 255}};

void lookDown(vtkCamera* camera, double x, double y, double scale)
{
  camera->SetFocalPoint(x, y, 0.5);
  camera->SetPosition(x, y, 10);
  camera->SetViewUp(0, 1, 0);
  camera->ParallelProjectionOn();
  camera->SetParallelScale(scale);
}

std::array<double, 3> mapped(vtkScalarsToColors* map, double value)
{
  double rgb[3];
  map->GetColor(value, rgb);
  return {{255 * rgb[0], 255 * rgb[1], 255 * rgb[2]}};
}

/// The largest difference of any channel between `image` and `expected(i, j)`.
template <typename Expected>
double largestDeviation(const Image& image, Expected expected)
{
  double largest = 0;
  for (int j = 0; j < image.height; ++j)
    for (int i = 0; i < image.width; ++i)
    {
      const std::array<double, 3> want = expected(i, j);
      for (int c = 0; c < 3; ++c)
      {
        const double got = image.rgb[3 * (static_cast<std::size_t>(j) * image.width + i) + c];
        largest = std::max(largest, std::abs(got - want[c]));
      }
    }
  return largest;
}

template <typename Filter>
vtkSmartPointer<vtkPolyData> run(Filter* filter, vtkHyperTreeGrid* htg, vtkRenderer* renderer,
                                 bool levelOfDetail, vtkScalarsToColors* colors = nullptr,
                                 const char* field = nullptr)
{
  filter->SetInputData(htg);
  filter->SetRenderer(renderer);
  filter->SetLevelOfDetail(levelOfDetail);
  if (colors)
  {
    filter->SetColorMap(colors);
    filter->SetColorField(field);
  }
  filter->Update();
  return filter->GetPolyDataOutput();
}

TEST(ImageTruth, ACheckerboardBelowAPixelIsItsMeanColourAndEdgesAreCoverageWeighted)
{
  // 256 x 256 leaves on the unit square seen by 64 x 64 pixels: 4 x 4 leaves per
  // pixel, two of each colour in every row. The window is shifted a quarter
  // pixel left and down, so the first column and row are covered 3/4 (3 leaves
  // across, still half of each colour), and the corner pixel 3 x 3 leaves: 5 of
  // value 0 (even i + j), 4 of value 1, over 9/16 of it.
  CheckerboardForest board(2, 8);
  auto htg = buildHyperTreeGrid(board.forest);
  OffscreenRenderer r(64, 64);
  const double pixel = 1.0 / 64;
  lookDown(r.camera(), 0.5 - pixel / 4, 0.5 - pixel / 4, 0.5);
  vtkNew<vtkCanopyAdaptiveSurface> all; // every leaf, those beyond the window's edge too
  all->SetInputData(htg);
  all->ViewDependentOff();
  all->Update();
  vtkPolyData* leaves = all->GetPolyDataOutput();
  ASSERT_EQ(leaves->GetNumberOfCells(), 256 * 256);
  vtkScalarsToColors* map = r.colorMap(0, 1);
  const Image truth =
      exactImage(coloredRects(leaves, "value", map), parallelWindow(r.camera(), 64, 64), White);
  const auto zero = mapped(map, 0);
  const auto one = mapped(map, 1);
  auto expected = [&](int i, int j)
  {
    std::array<double, 3> rgb{};
    for (int c = 0; c < 3; ++c)
    {
      const double mean = (zero[c] + one[c]) / 2;
      if (i == 0 && j == 0)
        rgb[c] = (5 * zero[c] + 4 * one[c]) / 16 + 7.0 / 16 * White[c];
      else if (i == 0 || j == 0)
        rgb[c] = 0.75 * mean + 0.25 * White[c];
      else
        rgb[c] = mean;
    }
    return rgb;
  };
  // Rounding to bytes only.
  EXPECT_LE(largestDeviation(truth, expected), 0.5 + 1e-9);
}

TEST(ImageAccuracy, ACheckerboardBelowAPixelDrawnWithAverageColours)
{
  // Every pixel's truth is the mean of the two colours. Every leaf drawn, each
  // pixel shows the one leaf at its centre (one of the two colours); coarse
  // quads drawn by value show the colour of 0.5, which on a cool-to-warm map is
  // near white, not the purple mean; coarse quads drawn with their leaves'
  // average colour are the truth.
  CheckerboardForest board(2, 8);
  auto htg = buildHyperTreeGrid(board.forest);
  OffscreenRenderer r(64, 64);
  lookDown(r.camera(), 0.5, 0.5, 0.5);
  vtkScalarsToColors* map = r.colorMap(0, 1);
  vtkNew<vtkCanopyAdaptiveSurface> all;
  vtkNew<vtkCanopyAdaptiveSurface> byValue;
  vtkNew<vtkCanopyAdaptiveSurface> byColour;
  auto leaves = run(all.Get(), htg, r.renderer(), false);
  auto coarseValues = run(byValue.Get(), htg, r.renderer(), true);
  auto coarseColours = run(byColour.Get(), htg, r.renderer(), true, map, "value");
  ASSERT_LT(coarseColours->GetNumberOfCells(), leaves->GetNumberOfCells() / 4);
  const Image truth =
      exactImage(coloredRects(leaves, "value", map), parallelWindow(r.camera(), 64, 64), White);
  const ImageError full = compare(r.render(leaves, "value", 0, 1), truth, 2);
  const ImageError values = compare(r.render(coarseValues, "value", 0, 1), truth, 2);
  const ImageError colours = compare(r.renderColors(coarseColours, "Colors"), truth, 2);
  std::cout << "checkerboard against the truth: RMSE every leaf " << full.rmse
            << ", coarse by value " << values.rmse << ", coarse by average colour " << colours.rmse
            << "\n";
  EXPECT_GT(full.rmse, 40);
  EXPECT_GT(values.rmse, 40);
  EXPECT_LT(colours.rmse, 1.0);
  EXPECT_EQ(colours.pixelsOff, 0u);
}

TEST(ImageAccuracy, AFrontBelowAPixelIsCloserToTheTruthWithAverageColoursThanWithEveryLeaf)
{
  // The synthetic forest's pressure front refined far below a pixel (11 levels
  // on 4 x 4 roots), at Canopy's default threshold.
  tools::SyntheticForestOptions o;
  o.dimension = 2;
  o.rootsPerAxis = 4;
  o.maxLevels = 11;
  o.cutaway = false;
  tools::SyntheticForest forest(o);
  auto htg = buildHyperTreeGrid(forest.description());
  const int size = 256;
  OffscreenRenderer r(size, size);
  lookDown(r.camera(), 0, 0, 1);
  vtkScalarsToColors* map = r.colorMap(1, 7);
  vtkNew<vtkCanopyAdaptiveSurface> all;
  vtkNew<vtkCanopyAdaptiveSurface> byValue;
  vtkNew<vtkCanopyAdaptiveSurface> byColour;
  auto leaves = run(all.Get(), htg, r.renderer(), false);
  auto coarseValues = run(byValue.Get(), htg, r.renderer(), true);
  auto coarseColours = run(byColour.Get(), htg, r.renderer(), true, map, "pressure");
  ASSERT_LT(coarseColours->GetNumberOfCells(), leaves->GetNumberOfCells() / 4);
  const Image truth = exactImage(coloredRects(leaves, "pressure", map),
                                 parallelWindow(r.camera(), size, size), White);
  const Image fullImage = r.render(leaves, "pressure", 1, 7);
  const Image colourImage = r.renderColors(coarseColours, "Colors");
  const ImageError full = compare(fullImage, truth, 2);
  const ImageError values = compare(r.render(coarseValues, "pressure", 1, 7), truth, 2);
  const ImageError colours = compare(colourImage, truth, 2);
  std::cout << "front (" << leaves->GetNumberOfCells() << " visible leaves, "
            << coarseColours->GetNumberOfCells() << " quads) against the truth: RMSE every leaf "
            << full.rmse << " (" << 100 * full.shareOff << "% off by > 2/255), coarse by value "
            << values.rmse << " (" << 100 * values.shareOff << "%), coarse by average colour "
            << colours.rmse << " (" << 100 * colours.shareOff << "%)\n";
  writePng(truth, "accuracy_truth.png");
  writePng(fullImage, "accuracy_every_leaf.png");
  writePng(colourImage, "accuracy_average_colours.png");
  EXPECT_LT(colours.rmse, full.rmse);
  EXPECT_LT(colours.shareOff, full.shareOff);
  EXPECT_LT(colours.rmse, values.rmse);
}

TEST(ImageAccuracy, ASliceBelowAPixelDrawnWithAverageColours)
{
  // A 64^3 checkerboard cut at z = 0.3 (inside a leaf layer), seen face-on by
  // 32 x 32 pixels: 2 x 2 cut leaves per pixel, mean colour everywhere.
  CheckerboardForest board(3, 6);
  auto htg = buildHyperTreeGrid(board.forest);
  OffscreenRenderer r(32, 32);
  lookDown(r.camera(), 0.5, 0.5, 0.5);
  vtkScalarsToColors* map = r.colorMap(0, 1);
  vtkNew<vtkCanopyAdaptiveSlice> all;
  vtkNew<vtkCanopyAdaptiveSlice> byColour;
  all->AddPlane(2, 0.3);
  byColour->AddPlane(2, 0.3);
  auto cuts = run(all.Get(), htg, r.renderer(), false);
  auto coarse = run(byColour.Get(), htg, r.renderer(), true, map, "value");
  ASSERT_EQ(cuts->GetNumberOfCells(), 64 * 64);
  ASSERT_LT(coarse->GetNumberOfCells(), cuts->GetNumberOfCells() / 2);
  const Image truth =
      exactImage(coloredRects(cuts, "value", map), parallelWindow(r.camera(), 32, 32), White);
  const auto zero = mapped(map, 0);
  const auto one = mapped(map, 1);
  EXPECT_LE(largestDeviation(truth,
                             [&](int, int)
                             {
                               return std::array<double, 3>{{(zero[0] + one[0]) / 2,
                                                             (zero[1] + one[1]) / 2,
                                                             (zero[2] + one[2]) / 2}};
                             }),
            0.5 + 1e-9);
  const ImageError full = compare(r.render(cuts, "value", 0, 1), truth, 2);
  const ImageError colours = compare(r.renderColors(coarse, "Colors"), truth, 2);
  std::cout << "slice against the truth: RMSE every cut " << full.rmse
            << ", coarse by average colour " << colours.rmse << "\n";
  EXPECT_GT(full.rmse, 40);
  EXPECT_LT(colours.rmse, 1.0);
}

} // namespace
} // namespace canopy::testing
