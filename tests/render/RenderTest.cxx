// Rendered under Xvfb (tests/support/with_xvfb.sh): with level of detail off the adaptive surface
// gives the same image as the full surface (culling removes only what is not seen); with level of
// detail on, the image error stays under a stated bound.
#include "DescriptorForest.h"
#include "OffscreenRenderer.h"
#include "PaperCaseDefinitions.h"
#include "SyntheticForest.h"

#include "canopy/HtgBuilder.h"
#include "vtkCanopyAdaptiveSurface.h"

#include <gtest/gtest.h>
#include <vtkCamera.h>
#include <vtkHyperTreeGrid.h>
#include <vtkPolyData.h>

#include <iostream>

namespace canopy::testing
{
namespace
{

vtkSmartPointer<vtkPolyData> surfaceFor(vtkHyperTreeGrid* htg, OffscreenRenderer& r, bool view,
                                        bool lod)
{
  vtkNew<vtkCanopyAdaptiveSurface> filter;
  filter->SetInputData(htg);
  filter->SetRenderer(r.renderer());
  filter->SetViewDependent(view);
  filter->SetLevelOfDetail(lod);
  filter->Update();
  return filter->GetPolyDataOutput();
}

TEST(Rendering, CullingAloneChangesNoPixel2D)
{
  for (bool withMask : {false, true})
  {
    DescriptorForest forest(paperCaseA(withMask));
    auto htg = buildHyperTreeGrid(forest.description());
    OffscreenRenderer r(400, 400);
    r.camera()->SetFocalPoint(0.75, 1.5, 0);
    r.camera()->SetPosition(0.75, 1.5, 10);
    r.camera()->SetViewUp(0, 1, 0);
    r.camera()->ParallelProjectionOn();
    r.camera()->SetParallelScale(1);
    auto culled = surfaceFor(htg, r, true, false);
    auto full = surfaceFor(htg, r, false, false);
    ASSERT_LT(culled->GetNumberOfCells(), full->GetNumberOfCells());
    const Image a = r.render(culled, "Depth", 0, 5);
    const Image b = r.render(full, "Depth", 0, 5);
    const ImageError e = compare(a, b);
    EXPECT_EQ(e.pixelsOff, 0u) << (withMask ? "with mask" : "without mask");
    // The picture is not empty: several colors are visible.
    std::size_t lit = 0;
    for (std::size_t i = 0; i < a.rgb.size(); i += 3)
    {
      lit += a.rgb[i] + a.rgb[i + 1] + a.rgb[i + 2] > 0;
    }
    EXPECT_GT(lit, a.rgb.size() / 3 / 3);
  }
}

TEST(Rendering, CullingAloneChangesNoPixel3D)
{
  tools::SyntheticForestOptions o;
  o.dimension = 3;
  o.rootsPerAxis = 4;
  o.maxLevels = 5;
  tools::SyntheticForest forest(o);
  auto htg = buildHyperTreeGrid(forest.description());
  OffscreenRenderer r(480, 360);
  r.camera()->SetFocalPoint(0.3, 0.2, 0.1);
  r.camera()->SetPosition(1.6, -1.2, 1.3);
  r.camera()->SetViewUp(0, 0, 1);
  r.camera()->SetViewAngle(30);
  auto culled = surfaceFor(htg, r, true, false);
  auto full = surfaceFor(htg, r, false, false);
  ASSERT_LT(culled->GetNumberOfCells(), full->GetNumberOfCells());
  const ImageError e = compare(r.render(culled, "density", 1, 4), r.render(full, "density", 1, 4));
  EXPECT_EQ(e.pixelsOff, 0u);
}

TEST(Rendering, LevelOfDetailErrorIsBounded)
{
  // A 2D front refined far below a pixel, colored by a leaves-only field, so
  // that coarse nodes show volume averages.
  tools::SyntheticForestOptions o;
  o.dimension = 2;
  o.rootsPerAxis = 4;
  o.maxLevels = 11;
  o.cutaway = false;
  tools::SyntheticForest forest(o);
  auto htg = buildHyperTreeGrid(forest.description());
  const int size = 256;
  const int supersampling = 4;
  OffscreenRenderer r(size, size);
  auto setView = [](vtkCamera* c)
  {
    c->SetFocalPoint(0, 0, 0);
    c->SetPosition(0, 0, 5);
    c->SetViewUp(0, 1, 0);
    c->ParallelProjectionOn();
    c->SetParallelScale(1.0);
  };
  setView(r.camera());
  auto detailed = surfaceFor(htg, r, true, false);
  auto adaptive = surfaceFor(htg, r, true, true);
  ASSERT_LT(adaptive->GetNumberOfCells(), detailed->GetNumberOfCells() / 4);
  const Image full = r.render(detailed, "pressure", 1, 7);
  const Image lod = r.render(adaptive, "pressure", 1, 7);
  // Reference: the full-resolution surface rendered 4x larger, averaged down.
  OffscreenRenderer big(size * supersampling, size * supersampling);
  setView(big.camera());
  const Image reference = downsample(big.render(detailed, "pressure", 1, 7), supersampling);
  const ImageError lodError = compare(lod, reference, 8);
  const ImageError fullError = compare(full, reference, 8);
  std::cout << "level of detail: " << adaptive->GetNumberOfCells() << " of "
            << detailed->GetNumberOfCells() << " cells; against the 4x supersampled reference: "
            << "adaptive RMSE " << lodError.rmse << " (PSNR " << lodError.psnr << " dB, "
            << 100 * lodError.shareOff << "% pixels off by > 8/255), full resolution RMSE "
            << fullError.rmse << " (PSNR " << fullError.psnr << " dB, " << 100 * fullError.shareOff
            << "%)\n";
  writePng(difference(lod, reference), "level_of_detail_difference.png");
  writePng(lod, "level_of_detail_adaptive.png");
  writePng(full, "level_of_detail_full.png");
  writePng(reference, "level_of_detail_reference.png");
  // Bounds stated in docs/filters.md: the adaptive image is no worse than the
  // full-resolution one (which aliases) by more than a small margin.
  EXPECT_LT(lodError.rmse, fullError.rmse * 1.25 + 1.0);
  EXPECT_LT(lodError.shareOff, 0.10);
}

} // namespace
} // namespace canopy::testing
