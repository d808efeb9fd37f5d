// Steady-state times of the adaptive surface and slice filters on synthetic
// forests, with the output's size: cells, points, points per cell (a flat
// piece has 4, more where smaller pieces meet its edges). Each case executes
// once, then `repetitions` more times (re-executed as a camera move would, or
// on a new mask, as at each step of a pipeline that selects a region); the
// fastest is printed, the least disturbed by other jobs on the machine.
//
//   canopy_bench_filter_times [repetitions (21)] [only the cases whose name contains this]
//
// docs/benchmarks.md, "T-junction vertices", compares two builds of it.
#include "SyntheticForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSlice.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <vtkCamera.h>
#include <vtkHyperTreeGrid.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

namespace
{

struct Run
{
  int repetitions = 21;
  std::string only;

  /// `before`: what happens, untimed, before each execution (a new input).
  void time(vtkAlgorithm* filter, vtkPolyData* out, const std::string& name,
            const std::function<void()>& before = {}) const
  {
    if (!only.empty() && name.find(only) == std::string::npos)
    {
      return;
    }
    filter->Update();
    std::vector<double> times;
    for (int r = 0; r < repetitions; ++r)
    {
      filter->Modified();
      if (before)
      {
        before();
      }
      const auto start = std::chrono::steady_clock::now();
      filter->Update();
      times.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    const double fastest = *std::min_element(times.begin(), times.end());
    const double cells = static_cast<double>(std::max<vtkIdType>(1, out->GetNumberOfCells()));
    std::printf("%-42s cells %9lld points %10lld (%.3f per cell)  fastest %.4f s  %.1f ns/cell\n",
                name.c_str(), static_cast<long long>(out->GetNumberOfCells()),
                static_cast<long long>(out->GetNumberOfPoints()),
                static_cast<double>(out->GetNumberOfPoints()) / cells, fastest,
                1e9 * fastest / cells);
  }
};

} // namespace

int main(int argc, char** argv)
{
  using namespace canopy;
  Run run;
  run.repetitions = argc > 1 ? std::max(1, std::atoi(argv[1])) : 21;
  run.only = argc > 2 ? argv[2] : "";
  {
    // The surface benchmark's 2D front (16 x 16 roots, 10 levels), no mask.
    tools::SyntheticForestOptions o;
    o.dimension = 2;
    o.rootsPerAxis = 16;
    o.maxLevels = 10;
    o.cutaway = false;
    tools::SyntheticForest forest(o);
    auto htg = buildHyperTreeGrid(forest.description());
    std::printf("2D synthetic forest: %zu leaves\n", forest.numberOfLeaves());
    vtkNew<vtkCanopyAdaptiveSurface> full;
    full->SetInputData(htg);
    full->ViewDependentOff();
    run.time(full, full->GetPolyDataOutput(), "2D full surface");
    vtkNew<vtkCanopyAdaptiveSurface> adaptive;
    adaptive->SetInputData(htg);
    adaptive->SetCameraPosition(0, 0, 5);
    adaptive->SetCameraFocalPoint(0, 0, 0);
    adaptive->SetParallelScale(0.5);
    adaptive->SetViewportSize(1024, 1024);
    run.time(adaptive, adaptive->GetPolyDataOutput(), "2D adaptive 1024^2, whole domain");
    adaptive->SetCameraPosition(0.35, 0.2, 5);
    adaptive->SetCameraFocalPoint(0.35, 0.2, 0);
    adaptive->SetParallelScale(0.15);
    run.time(adaptive, adaptive->GetPolyDataOutput(), "2D adaptive 1024^2, zoomed on the front");
  }
  {
    // 6^3 roots, 7 levels, the octant towards +x +y +z masked.
    tools::SyntheticForestOptions o;
    o.dimension = 3;
    o.rootsPerAxis = 6;
    o.maxLevels = 7;
    o.cutaway = true;
    tools::SyntheticForest forest(o);
    auto htg = buildHyperTreeGrid(forest.description());
    std::printf("3D synthetic forest (octant cut away): %zu leaves\n", forest.numberOfLeaves());
    vtkNew<vtkCamera> camera;
    camera->SetFocalPoint(0, 0, 0);
    camera->SetPosition(1.6, -1.3, 1.1);
    camera->SetViewUp(0, 0, 1);
    camera->SetViewAngle(30);
    vtkNew<vtkCanopyAdaptiveSurface> surface;
    surface->SetInputData(htg);
    surface->SetCamera(camera);
    surface->SetViewportSize(1024, 768);
    run.time(surface, surface->GetPolyDataOutput(), "3D surface 1024x768, 1 px");
    surface->SetLevelOfDetail(false);
    run.time(surface, surface->GetPolyDataOutput(), "3D surface 1024x768, every leaf");
    // The region a pipeline selects (slice_image.py's: the front's shell, with
    // density >= 3), its mask made again before each execution as at each
    // step: the surface's topology memos start empty every time.
    vtkNew<vtkCanopyExtractSelection> shell;
    shell->SetInputData(htg);
    shell->SetSelectionMode(vtkCanopyExtractSelection::VALUE_RANGE);
    shell->SetValueArrayName("density");
    shell->SetValueRange(3, 1e30);
    shell->PreserveTopologyOn();
    vtkNew<vtkCanopyAdaptiveSurface> region;
    region->SetInputConnection(shell->GetOutputPort());
    region->SetCamera(camera);
    region->SetViewportSize(1024, 768);
    const auto newMask = [&]
    {
      shell->Modified();
      shell->Update();
    };
    run.time(region, region->GetPolyDataOutput(), "3D region surface, new mask, 1 px", newMask);
    region->SetLevelOfDetail(false);
    run.time(region, region->GetPolyDataOutput(), "3D region surface, new mask, every leaf",
             newMask);
    vtkNew<vtkCanopyAdaptiveSlice> slices;
    slices->SetInputData(htg);
    slices->AddXPlane(0.013);
    slices->AddYPlane(0.013);
    slices->AddZPlane(0.013);
    slices->SetCamera(camera);
    slices->SetViewportSize(1024, 768);
    run.time(slices, slices->GetPolyDataOutput(), "3 slices 1024x768, 1 px");
    slices->ViewDependentOff();
    run.time(slices, slices->GetPolyDataOutput(), "3 slices, every cut leaf");
  }
  return 0;
}
