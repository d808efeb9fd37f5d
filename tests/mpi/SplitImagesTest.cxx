// No pixel holes in pictures of grids split between ranks: each rank slices or
// draws its part (trees cut between ranks by p4est's partition, or whole trees
// per rank), rank 0 gathers every rank's pieces and renders them together by
// real OpenGL under Xvfb, as a compositor would show the ranks' pictures (a
// pixel no rank covers is background in both). Level jumps of one and three
// levels between trees, so coarse pieces of one rank meet finer ones of
// another; slices, and 3D surfaces without back faces; level of detail off and
// at 30 pixels. Every pixel inside the projected slice rectangle (the domain's
// box), at least a pixel from its border, must be drawn. Run with mpirun -np 1,
// 2 and 4 under tests/support/with_xvfb.sh; CANOPY_RENDER_OUTPUT=<folder> also
// writes the pictures.
#include "GatherPieces.h"
#include "ImageHoles.h"
#include "LevelJumpForest.h"
#include "OffscreenRenderer.h"
#include "RankForestPart.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSlice.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>

#include <gtest/gtest.h>
#include <vtkCamera.h>
#include <vtkHyperTreeGrid.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include <array>
#include <cctype>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace canopy::testing
{
namespace
{

constexpr int Width = 560;
constexpr int Height = 480;

vtkMultiProcessController* world()
{
  return vtkMultiProcessController::GetGlobalController();
}

/// This rank's part of `whole` (RankForestPart.h), cut trees stored breadth-first.
vtkSmartPointer<vtkHyperTreeGrid> partOf(const ForestDescription& whole, bool splitTrees,
                                         std::shared_ptr<void>& keep)
{
  return rankForestPart(whole, splitTrees, world()->GetLocalProcessId(),
                        world()->GetNumberOfProcesses(), keep, false);
}

/// Oblique perspective, and oblique parallel, views of the point `focal`, `size` away.
void aim(vtkCamera* camera, bool parallel, const std::array<double, 3>& focal, double size)
{
  camera->SetFocalPoint(focal.data());
  camera->SetPosition(focal[0] + 0.9 * size, focal[1] - 1.1 * size, focal[2] + 1.3 * size);
  camera->SetViewUp(0, 0, 1);
  camera->SetParallelProjection(parallel);
  camera->SetParallelScale(0.5 * size);
  camera->SetViewAngle(30);
}

/// Rank 0 renders every rank's pieces and checks that no background pixel lies
/// inside the hull of `region`'s projection.
void expectNoHoles(vtkPolyData* mine, vtkCamera* camera,
                   const std::vector<std::array<double, 3>>& region, int levels,
                   const std::string& label)
{
  vtkSmartPointer<vtkPolyData> all = gatherPieces(mine);
  if (world()->GetLocalProcessId() != 0)
  {
    return;
  }
  ASSERT_GT(all->GetNumberOfCells(), 0) << label;
  OffscreenRenderer r(Width, Height);
  r.camera()->DeepCopy(camera);
  const Image image = r.render(all, "Level", -1, levels);
  std::size_t inside = 0;
  const auto holes = holesInside(image, r.renderer(), region, 1.0, {{0, 0, 0}}, &inside);
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

TEST(SplitImages, SlicesAndSurfacesShowNoBackgroundInsideTheirFootprint)
{
  const std::string ranks = std::to_string(world()->GetNumberOfProcesses()) + " ranks";
  const LevelJumpForest jumpOne({{6, 5, 2}}, 2, 3, true);
  const LevelJumpForest jumpThree({{5, 4, 2}}, 1, 4, false);
  for (const LevelJumpForest* forest : {&jumpOne, &jumpThree})
  {
    const std::string name = forest == &jumpOne ? "jump 1" : "jump 3, irregular roots";
    const auto b = forest->bounds();
    const int levels = forest->description().maxLevels;
    for (bool splitTrees : {true, false})
    {
      std::shared_ptr<void> keep;
      auto grid = partOf(forest->description(), splitTrees, keep);
      for (bool parallel : {false, true})
      {
        for (double threshold : {0.0, 30.0})
        {
          const std::string label = name + (splitTrees ? ", trees split" : ", whole trees") +
                                    (parallel ? ", parallel" : ", perspective") +
                                    (threshold > 0 ? ", level of detail" : ", every leaf") + ", " +
                                    ranks;
          vtkNew<vtkCamera> camera;
          // The slice z = const through the lower roots, off every cell face.
          const double z = b[4] + 0.37 * (b[5] - b[4]);
          aim(camera, parallel, {{(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, z}},
              1.4 * std::max(b[1] - b[0], b[3] - b[2]));
          vtkNew<vtkCanopyAdaptiveSlice> slice;
          slice->SetInputData(grid);
          slice->AddZPlane(z);
          slice->SetCamera(camera);
          slice->SetViewportSize(Width, Height);
          slice->SetLevelOfDetail(threshold > 0);
          slice->SetPixelThreshold(threshold > 0 ? threshold : 1);
          slice->Update();
          expectNoHoles(
              slice->GetPolyDataOutput(), camera,
              {{{b[0], b[2], z}}, {{b[1], b[2], z}}, {{b[1], b[3], z}}, {{b[0], b[3], z}}}, levels,
              "slice, " + label);

          aim(camera, parallel, {{(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2}},
              1.6 * std::max({b[1] - b[0], b[3] - b[2], b[5] - b[4]}));
          vtkNew<vtkCanopyAdaptiveSurface> surface;
          surface->SetInputData(grid);
          surface->SetCamera(camera);
          surface->SetViewportSize(Width, Height);
          surface->SetLevelOfDetail(threshold > 0);
          surface->SetPixelThreshold(threshold > 0 ? threshold : 1);
          surface->SkipBackFacesOn(); // behind a crack: the background
          surface->Update();
          std::vector<std::array<double, 3>> box;
          for (int k = 0; k < 8; ++k)
          {
            box.push_back({{b[k & 1], b[2 + ((k >> 1) & 1)], b[4 + ((k >> 2) & 1)]}});
          }
          expectNoHoles(surface->GetPolyDataOutput(), camera, box, levels, "surface, " + label);
        }
      }
    }
  }
}

} // namespace
} // namespace canopy::testing
