// The adaptive contour at 1024x1024: triangles against the pixels the surface
// covers, and run time against image error, under Xvfb (it renders).
//
// The forest: BlobForest.h with its band at level 7 (h = 1/2048, w = 0.75 h,
// 3.5 w each side), the background at level 2, about 8e6 leaves; the contour
// at f = 0.5, lit, white on black, flat colour, from a perspective camera
// (view angle 30 degrees) looking at the blob's centre obliquely, at the
// distances where the blob spans about 600, 300, 150 and 75 pixels.
//
// The truth: the full-resolution contour rendered at 4096x4096 and averaged
// down to 1024x1024 (4x4 supersampling). Per distance:
//   full         the full-resolution contour, no view (its time is one
//                execution; the same at every distance)
//   N px         level of detail with PixelThreshold N and view culling: time of
//                an execution after a camera move (the value ranges kept), the
//                median of --repetitions
// with triangles, triangles per covered pixel (a pixel the truth does not leave
// black), render time, and the error against the truth: RMSE (0..255) and the
// share of pixels off by more than 8/255 in a channel.
// Writes the truth, the 1 px image and their difference at 300 px into
// --output (default contour-adaptive).
//
//   canopy_bench_contour_adaptive [--output DIR] [--repetitions N] [--band-level L]
//                                 [--across PIXELS]... [--threshold PIXELS]...
// (--across and --threshold: only those rows, e.g. to profile one of them.)
#include "BlobForest.h"
#include "OffscreenRenderer.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyContour.h>

#include <vtkCamera.h>
#include <vtkHyperTreeGrid.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace
{

using canopy::testing::Image;
using canopy::testing::OffscreenRenderer;
using Clock = std::chrono::steady_clock;

constexpr int Size = 1024;
constexpr int Supersampling = 4;
constexpr double ViewAngle = 30;

double secondsSince(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// The camera at `distance` from the blob's centre, along a fixed oblique direction.
void place(vtkCamera* camera, double distance)
{
  const double direction[3] = {0.62, -0.48, 0.62};
  const double norm = std::sqrt(direction[0] * direction[0] + direction[1] * direction[1] +
                                direction[2] * direction[2]);
  camera->SetFocalPoint(0.5, 0.5, 0.5);
  camera->SetPosition(0.5 + distance * direction[0] / norm, 0.5 + distance * direction[1] / norm,
                      0.5 + distance * direction[2] / norm);
  camera->SetViewUp(0, 0, 1);
  camera->SetViewAngle(ViewAngle);
  camera->SetParallelProjection(false);
}

std::size_t coveredPixels(const Image& image)
{
  std::size_t covered = 0;
  for (std::size_t p = 0; p + 2 < image.rgb.size(); p += 3)
  {
    covered += (image.rgb[p] | image.rgb[p + 1] | image.rgb[p + 2]) != 0 ? 1 : 0;
  }
  return covered;
}

double median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

} // namespace

int main(int argc, char** argv)
{
  std::filesystem::path output = "contour-adaptive";
  int repetitions = 3;
  canopy::bench::BlobForestOptions options;
  options.bandLevel = 7;
  options.backgroundLevel = 2;
  options.widthInBandEdges = 0.75;
  options.bandHalfWidthInWidths = 3.5;
  std::vector<double> acrossList;
  std::vector<double> thresholds;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--across" && i + 1 < argc)
    {
      acrossList.push_back(std::atof(argv[++i]));
    }
    else if (arg == "--threshold" && i + 1 < argc)
    {
      thresholds.push_back(std::atof(argv[++i]));
    }
    else if (arg == "--output" && i + 1 < argc)
    {
      output = argv[++i];
    }
    else if (arg == "--repetitions" && i + 1 < argc)
    {
      repetitions = std::max(1, std::atoi(argv[++i]));
    }
    else if (arg == "--band-level" && i + 1 < argc)
    {
      options.bandLevel = std::atoi(argv[++i]);
    }
    else
    {
      std::fprintf(stderr, "unknown argument %s (see the file's header)\n", argv[i]);
      return 2;
    }
  }
  if (acrossList.empty())
  {
    acrossList = {600, 300, 150, 75};
  }
  if (thresholds.empty())
  {
    thresholds = {1, 2, 4, 8};
  }
  std::filesystem::create_directories(output);
  vtkSMPTools::Initialize(1);

  canopy::bench::BlobForest forest(options);
  auto htg = canopy::buildHyperTreeGrid(forest.description());
  auto configure = [&](vtkCanopyContour* contour)
  {
    contour->SetInputData(htg);
    contour->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "f");
    contour->SetValue(0, 0.5);
  };
  vtkNew<vtkCanopyContour> full;
  configure(full);
  auto start = Clock::now();
  full->Update();
  const double fullSeconds = secondsSince(start);
  vtkPolyData* fullSurface = full->GetOutput();

  OffscreenRenderer renderer(Size, Size);
  vtkNew<vtkCanopyContour> adaptive;
  configure(adaptive);
  adaptive->SetCamera(renderer.camera());
  adaptive->SetViewportSize(Size, Size);
  adaptive->ViewDependentOn();
  adaptive->ViewCullingOn();
  adaptive->LevelOfDetailOn();

  std::printf("%zu leaves (band level %d); the full contour: %lld triangles in %.2f s\n\n",
              forest.leaves(), options.bandLevel,
              static_cast<long long>(fullSurface->GetNumberOfCells()), fullSeconds);
  std::printf("| blob across (px) | surface | triangles | covered pixels | triangles per covered "
              "pixel | contour (s) | render (s) | RMSE | pixels off > 8/255 |\n"
              "|---|---|---|---|---|---|---|---|---|\n");
  // The blob (0.3 across) spans `pixels` at distance d: 0.3 / (2 d tan(15 deg) / 1024).
  const double perPixelAtUnitDistance = 2 * std::tan(ViewAngle / 2 * M_PI / 180) / Size;
  for (double across : acrossList)
  {
    const double distance =
        2 * canopy::bench::BlobForest::Radius / (across * perPixelAtUnitDistance);
    place(renderer.camera(), distance);
    renderer.resize(Size * Supersampling, Size * Supersampling);
    const Image truth = canopy::testing::downsample(
        renderer.render(fullSurface, "none", 0, 1, /*lighting=*/true), Supersampling);
    renderer.resize(Size, Size);
    const std::size_t covered = coveredPixels(truth);
    double renderSeconds = 0;
    const Image fullImage = renderer.render(fullSurface, "none", 0, 1, true, false, &renderSeconds);
    auto row = [&](const std::string& what, vtkIdType triangles, double contourSeconds,
                   const Image& image, double rendered)
    {
      const auto error = canopy::testing::compare(image, truth, 8);
      std::printf("| %.0f | %s | %lld | %zu | %.1f | %.3f | %.3f | %.2f | %.2f%% |\n", across,
                  what.c_str(), static_cast<long long>(triangles), covered,
                  static_cast<double>(triangles) /
                      static_cast<double>(std::max<std::size_t>(covered, 1)),
                  contourSeconds, rendered, error.rmse, 100 * error.shareOff);
      std::fflush(stdout);
    };
    row("full", fullSurface->GetNumberOfCells(), fullSeconds, fullImage, renderSeconds);
    for (double threshold : thresholds)
    {
      adaptive->SetPixelThreshold(threshold);
      adaptive->Update(); // the first at this view: the ranges are kept from the one before
      std::vector<double> times;
      for (int r = 0; r < repetitions; ++r)
      {
        adaptive->Modified();
        start = Clock::now();
        adaptive->Update();
        times.push_back(secondsSince(start));
      }
      if (!adaptive->GetLastRangesKept())
      {
        std::fprintf(stderr, "the ranges were not kept across a camera move\n");
        return 1;
      }
      const Image image =
          renderer.render(adaptive->GetOutput(), "none", 0, 1, true, false, &renderSeconds);
      row(std::to_string(static_cast<int>(threshold)) + " px",
          adaptive->GetOutput()->GetNumberOfCells(), median(times), image, renderSeconds);
      if (across == 300.0 && threshold == 1.0)
      {
        canopy::testing::writePng(truth, (output / "truth_300px.png").string());
        canopy::testing::writePng(image, (output / "adaptive_1px_300px.png").string());
        canopy::testing::writePng(canopy::testing::difference(image, truth),
                                  (output / "difference_1px_300px.png").string());
        canopy::testing::writePng(fullImage, (output / "full_300px.png").string());
      }
    }
  }
  return 0;
}
