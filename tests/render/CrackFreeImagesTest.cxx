// No pixel holes where coarse cells meet finer ones (T-junctions), rendered by
// real OpenGL under Xvfb: a slice, and a 3D surface with its back faces left out
// (so that nothing behind a crack hides it), drawn over a black background from
// oblique perspective and face-on parallel views, with level of detail on and
// off, on forests whose neighbouring trees differ by one and by three levels
// (dyadic and irregular root coordinates) and on a random forest. Every pixel
// whose centre lies inside the projection of the slice's rectangle (of the
// domain's box), at least one pixel from its border, must be drawn.
// CANOPY_RENDER_OUTPUT=<folder> also writes the pictures there.
#include "ImageHoles.h"
#include "LevelJumpForest.h"
#include "OffscreenRenderer.h"
#include "RandomForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSlice.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>

#include <gtest/gtest.h>
#include <vtkCamera.h>
#include <vtkHyperTreeGrid.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace canopy::testing
{
namespace
{

const std::array<unsigned char, 3> Black{{0, 0, 0}};
/// Large enough that level of detail stops above the leaves, in steps that vary
/// over a perspective view: its own T-junctions.
constexpr double LevelOfDetailPixels = 30;

struct Forest
{
  std::string name;
  std::shared_ptr<const void> owner; ///< what the grid borrows (coordinates, trees)
  vtkSmartPointer<vtkHyperTreeGrid> grid;
  std::array<double, 6> bounds;
  int levels;
};

/// The forests: level jumps of 1 and 3 between neighbouring trees, and a random
/// forest with jumps of every size inside its trees.
std::vector<Forest> forests()
{
  std::vector<Forest> all;
  auto jumps =
      [&](const std::string& name, std::array<int, 3> roots, int coarse, int fine, bool dyadic)
  {
    auto forest = std::make_shared<const LevelJumpForest>(roots, coarse, fine, dyadic);
    all.push_back({name, forest, buildHyperTreeGrid(forest->description()), forest->bounds(),
                   forest->description().maxLevels});
  };
  jumps("jump 1", {{6, 6, 2}}, 2, 3, true);
  jumps("jump 3", {{6, 6, 2}}, 1, 4, true);
  jumps("jump 3, irregular roots", {{5, 4, 2}}, 1, 4, false);
  RandomForestOptions o;
  o.rootCells = {{4, 4, 2}};
  o.maxLevels = 6;
  o.refineProbability = 0.45;
  o.seed = 11;
  auto random = std::make_shared<const RandomForest>(o);
  const auto& c = random->coordinates();
  all.push_back(
      {"random",
       random,
       buildHyperTreeGrid(random->description()),
       {{c[0].front(), c[0].back(), c[1].front(), c[1].back(), c[2].front(), c[2].back()}},
       o.maxLevels});
  return all;
}

struct View
{
  std::string name;
  bool parallel;
  std::array<double, 3> direction; ///< from the focal point to the camera
  double scale;                    ///< parallel scale (times the domain's size) or view angle
};

std::vector<View> views()
{
  return {{"oblique perspective", false, {{0.9, -1.1, 1.3}}, 30},
          {"grazing perspective", false, {{1.7, 0.4, 0.35}}, 40},
          {"face-on parallel", true, {{0, 0, 1}}, 0.55},
          {"oblique parallel", true, {{-0.5, 0.8, 1}}, 0.6}};
}

void aim(vtkCamera* camera, const View& v, const std::array<double, 3>& focal, double size)
{
  camera->SetFocalPoint(focal.data());
  camera->SetPosition(focal[0] + size * v.direction[0], focal[1] + size * v.direction[1],
                      focal[2] + size * v.direction[2]);
  const bool alongZ = v.direction[0] == 0 && v.direction[1] == 0;
  camera->SetViewUp(0, alongZ ? 1 : 0, alongZ ? 0 : 1);
  camera->SetParallelProjection(v.parallel);
  if (v.parallel)
  {
    camera->SetParallelScale(v.scale * size);
  }
  else
  {
    camera->SetViewAngle(v.scale);
  }
}

/// Checks one picture; writes it when CANOPY_RENDER_OUTPUT names a folder.
void expectNoHoles(OffscreenRenderer& r, const Image& image,
                   const std::vector<std::array<double, 3>>& region, const std::string& label)
{
  std::size_t inside = 0;
  const auto holes = holesInside(image, r.renderer(), region, 1.0, Black, &inside);
  EXPECT_GT(inside, 1000u) << label << ": the region covers too few pixels to say anything";
  std::ostringstream where;
  for (std::size_t h = 0; h < holes.size() && h < 8; ++h)
  {
    where << " (" << holes[h][0] << ", " << holes[h][1] << ")";
  }
  EXPECT_EQ(holes.size(), 0u) << label
                              << ": background pixels inside the footprint:" << where.str();
  if (const char* folder = std::getenv("CANOPY_RENDER_OUTPUT"))
  {
    std::string file = label;
    for (char& ch : file)
    {
      ch = std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    }
    writePng(image, std::string(folder) + "/" + file + ".png");
  }
}

TEST(CrackFreeImages, SlicesShowNoBackgroundInsideTheirFootprint)
{
  OffscreenRenderer r(640, 560);
  for (const Forest& f : forests())
  {
    const auto& b = f.bounds;
    // Off every cell face: a plane through the middle of the lower roots.
    const double z = b[4] + 0.37 * (b[5] - b[4]);
    const std::array<double, 3> centre{{(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, z}};
    const double size = std::max(b[1] - b[0], b[3] - b[2]);
    const std::vector<std::array<double, 3>> rectangle{
        {{b[0], b[2], z}}, {{b[1], b[2], z}}, {{b[1], b[3], z}}, {{b[0], b[3], z}}};
    for (const View& v : views())
    {
      aim(r.camera(), v, centre, 1.4 * size);
      for (bool lod : {false, true})
      {
        vtkNew<vtkCanopyAdaptiveSlice> slice;
        slice->SetInputData(f.grid);
        slice->AddZPlane(z);
        slice->SetRenderer(r.renderer());
        slice->SetLevelOfDetail(lod);
        slice->SetPixelThreshold(LevelOfDetailPixels);
        slice->Update();
        const std::string label =
            "slice, " + f.name + ", " + v.name + (lod ? ", level of detail" : ", every cut leaf");
        ASSERT_GT(slice->GetPolyDataOutput()->GetNumberOfCells(), 0) << label;
        const Image image = r.render(slice->GetPolyDataOutput(), "Level", -1, f.levels);
        expectNoHoles(r, image, rectangle, label);
      }
    }
  }
}

TEST(CrackFreeImages, SurfacesWithoutBackFacesShowNoBackgroundInsideTheirFootprint)
{
  OffscreenRenderer r(640, 560);
  for (const Forest& f : forests())
  {
    const auto& b = f.bounds;
    const std::array<double, 3> centre{{(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2}};
    const double size = std::max({b[1] - b[0], b[3] - b[2], b[5] - b[4]});
    std::vector<std::array<double, 3>> box;
    for (int k = 0; k < 8; ++k)
    {
      box.push_back({{b[k & 1], b[2 + ((k >> 1) & 1)], b[4 + ((k >> 2) & 1)]}});
    }
    for (const View& v : views())
    {
      aim(r.camera(), v, centre, 1.5 * size);
      for (bool lod : {false, true})
      {
        vtkNew<vtkCanopyAdaptiveSurface> surface;
        surface->SetInputData(f.grid);
        surface->SetRenderer(r.renderer());
        surface->SetLevelOfDetail(lod);
        surface->SetPixelThreshold(LevelOfDetailPixels);
        surface->SkipBackFacesOn(); // behind a crack: the background, not a back face
        surface->Update();
        const std::string label =
            "surface, " + f.name + ", " + v.name + (lod ? ", level of detail" : ", every leaf");
        ASSERT_GT(surface->GetPolyDataOutput()->GetNumberOfCells(), 0) << label;
        const Image image = r.render(surface->GetPolyDataOutput(), "Level", -1, f.levels);
        expectNoHoles(r, image, box, label);
      }
    }
  }
}

} // namespace
} // namespace canopy::testing
