// Rendered under Xvfb (tests/support/with_xvfb.sh): with level of detail off the adaptive surface
// gives the same image as the full surface (culling removes only what is not seen). Level of
// detail's accuracy: ImageAccuracyTest.cxx.
#include "DescriptorForest.h"
#include "OffscreenRenderer.h"
#include "PaperCaseDefinitions.h"
#include "SyntheticForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>

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

} // namespace
} // namespace canopy::testing
