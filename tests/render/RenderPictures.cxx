// Pictures for docs/filters.md: paper cases A and B, with and without mask,
// the full surface and the part kept for a view (shown from an overview camera
// so the culled region is visible). Usage: canopy_render_pictures OUTPUT_DIR
#include "DescriptorForest.h"
#include "LevelJumpForest.h"
#include "OffscreenRenderer.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>
#include <canopy/filters/vtkCanopyContour.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkGeometryFilter.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkIdTypeArray.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <set>
#include <string>
#include <utility>

#include "PaperCaseDefinitions.h"

namespace
{

using namespace canopy::testing;

vtkSmartPointer<vtkPolyData> surface(vtkHyperTreeGrid* htg, vtkCamera* view, int w, int h)
{
  vtkNew<vtkCanopyAdaptiveSurface> filter;
  filter->SetInputData(htg);
  if (view)
  {
    filter->SetCamera(view);
    filter->SetViewportSize(w, h);
  }
  else
  {
    filter->ViewDependentOff();
  }
  filter->Update();
  return filter->GetPolyDataOutput();
}

} // namespace

int main(int argc, char** argv)
{
  if (argc != 2)
  {
    std::cerr << "usage: canopy_render_pictures OUTPUT_DIR\n";
    return 2;
  }
  const std::filesystem::path out = argv[1];
  std::filesystem::create_directories(out);
  for (bool masked : {false, true})
  {
    const std::string suffix = masked ? "_masked" : "";
    // Case A: the paper's view (parallel, scale 1 around (0.75, 1.5), 400 x 400).
    DescriptorForest a(paperCaseA(masked));
    auto htgA = buildHyperTreeGrid(a.description());
    vtkNew<vtkCamera> paperView;
    paperView->SetFocalPoint(0.75, 1.5, 0);
    paperView->SetPosition(0.75, 1.5, 10);
    paperView->ParallelProjectionOn();
    paperView->SetParallelScale(1);
    OffscreenRenderer overview(480, 480);
    overview.camera()->SetFocalPoint(1.5, 1.5, 0);
    overview.camera()->SetPosition(1.5, 1.5, 10);
    overview.camera()->ParallelProjectionOn();
    overview.camera()->SetParallelScale(1.7);
    writePng(overview.render(surface(htgA, nullptr, 0, 0), "Depth", 0, 5, false, true),
             (out / ("caseA_full" + suffix + ".png")).string());
    auto kept = surface(htgA, paperView, 400, 400);
    writePng(overview.render(kept, "Depth", 0, 5, false, true),
             (out / ("caseA_culled" + suffix + ".png")).string());
    std::cout << "case A" << suffix << ": " << kept->GetNumberOfCells() << " quads kept\n";

    // Case B: the full surface from a perspective overview, and what a close
    // view keeps, seen from the same overview.
    DescriptorForest b(paperCaseB(masked));
    auto htgB = buildHyperTreeGrid(b.description());
    OffscreenRenderer view3d(560, 420);
    vtkCamera* c = view3d.camera();
    c->SetFocalPoint(2.25, 1.5, 0.7);
    c->SetPosition(2.25 + 5.5, 1.5 - 6.5, 0.7 + 4.5);
    c->SetViewUp(0, 0, 1);
    c->SetViewAngle(30);
    auto fullB = surface(htgB, nullptr, 0, 0);
    writePng(view3d.render(fullB, "Depth", 0, 4, true, true),
             (out / ("caseB_full" + suffix + ".png")).string());
    vtkNew<vtkCamera> close;
    close->SetFocalPoint(3.2, 1.0, 0.7);
    close->SetPosition(3.2 + 2.0, 1.0 - 2.4, 0.7 + 1.6);
    close->SetViewUp(0, 0, 1);
    close->SetViewAngle(20);
    auto keptB = surface(htgB, close, 560, 420);
    writePng(view3d.render(keptB, "Depth", 0, 4, true, true),
             (out / ("caseB_culled" + suffix + ".png")).string());
    std::cout << "case B" << suffix << ": " << fullB->GetNumberOfCells() << " faces, "
              << keptB->GetNumberOfCells() << " kept by the close view\n";
  }
  // Selections: case A by location (points on faces, corners and the upper
  // boundary included), shown on the full grid; case B by value range, shown alone.
  {
    DescriptorForest a(paperCaseA(true));
    auto htgA = buildHyperTreeGrid(a.description());
    vtkNew<vtkCanopyExtractSelection> select;
    select->SetInputData(htgA);
    const double points[][3] = {{0.1, 0.1, 0}, {0.75, 1.5, 0},    {1.5, 1.0, 0},  {2.25, 2.25, 0},
                                {3.0, 3.0, 0}, {0.375, 2.625, 0}, {1.125, 0.5, 0}};
    for (const auto& p : points)
    {
      select->AddLocation(p[0], p[1], p[2]);
    }
    select->Update();
    auto* picked = vtkUnstructuredGrid::SafeDownCast(select->GetOutput());
    std::set<vtkIdType> chosen;
    auto* ids = vtkIdTypeArray::SafeDownCast(picked->GetCellData()->GetArray("OriginalCellId"));
    for (vtkIdType i = 0; i < ids->GetNumberOfTuples(); ++i)
    {
      chosen.insert(ids->GetValue(i));
    }
    auto full = surface(htgA, nullptr, 0, 0);
    auto* fullIds = vtkIdTypeArray::SafeDownCast(full->GetCellData()->GetArray("OriginalCellId"));
    vtkNew<vtkDoubleArray> flag;
    flag->SetName("Selected");
    flag->SetNumberOfTuples(full->GetNumberOfCells());
    for (vtkIdType c = 0; c < full->GetNumberOfCells(); ++c)
    {
      flag->SetValue(c, chosen.count(fullIds->GetValue(c)) ? 1.0 : 0.0);
    }
    full->GetCellData()->AddArray(flag);
    OffscreenRenderer overview(480, 480);
    overview.camera()->SetFocalPoint(1.5, 1.5, 0);
    overview.camera()->SetPosition(1.5, 1.5, 10);
    overview.camera()->ParallelProjectionOn();
    overview.camera()->SetParallelScale(1.7);
    writePng(overview.render(full, "Selected", 0, 1, false, true),
             (out / "caseA_selection_locations.png").string());
    std::cout << "case A: " << chosen.size() << " cells selected by 7 points\n";

    DescriptorForest b(paperCaseB(true));
    auto htgB = buildHyperTreeGrid(b.description());
    vtkNew<vtkCanopyExtractSelection> range;
    range->SetInputData(htgB);
    range->SetSelectionMode(vtkCanopyExtractSelection::VALUE_RANGE);
    range->SetValueArrayName("Depth");
    range->SetValueRange(2, 4);
    vtkNew<vtkGeometryFilter> outline;
    outline->SetInputConnection(range->GetOutputPort());
    outline->Update();
    OffscreenRenderer view3d(560, 420);
    vtkCamera* c = view3d.camera();
    c->SetFocalPoint(2.25, 1.5, 0.7);
    c->SetPosition(2.25 + 5.5, 1.5 - 6.5, 0.7 + 4.5);
    c->SetViewUp(0, 0, 1);
    c->SetViewAngle(30);
    writePng(view3d.render(outline->GetOutput(), "Depth", 0, 4, true, true),
             (out / "caseB_selection_depth_2_to_4.png").string());
    std::cout << "case B: " << range->GetOutput()->GetNumberOfElements(vtkDataObject::CELL)
              << " leaves with Depth in [2, 4]\n";
  }
  // A sphere's isosurface across level jumps of one and of three: the trees of a
  // 2 x 2 x 2 root grid alternate between two depths (LevelJumpForest), the
  // sphere is centred on their common corner; the triangles' edges drawn,
  // each triangle coloured by its tree's depth.
  for (const auto& [coarse, fine] : {std::pair<int, int>{2, 3}, std::pair<int, int>{1, 4}})
  {
    LevelJumpForest jumps({{2, 2, 2}}, coarse, fine, true);
    auto htg = buildHyperTreeGrid(jumps.description());
    vtkNew<vtkDoubleArray> distance;
    distance->SetName("distance");
    distance->SetNumberOfTuples(htg->GetNumberOfCells());
    vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> cursor;
    for (vtkIdType t = 0; t < 8; ++t)
    {
      htg->InitializeNonOrientedGeometryCursor(cursor, t);
      auto walk = [&](auto& self) -> void
      {
        double b[6];
        cursor->GetBounds(b);
        const double x = 0.5 * (b[0] + b[1]) - 1;
        const double y = 0.5 * (b[2] + b[3]) - 1;
        const double z = 0.5 * (b[4] + b[5]) - 1;
        distance->SetValue(cursor->GetGlobalNodeIndex(), std::sqrt(x * x + y * y + z * z));
        if (cursor->IsLeaf())
        {
          return;
        }
        for (unsigned char c = 0; c < cursor->GetNumberOfChildren(); ++c)
        {
          cursor->ToChild(c);
          self(self);
          cursor->ToParent();
        }
      };
      walk(walk);
    }
    htg->GetCellData()->AddArray(distance);
    vtkNew<vtkCanopyContour> contour;
    contour->SetInputData(htg);
    contour->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "distance");
    contour->SetValue(0, 0.62);
    contour->Update();
    vtkPolyData* sphere = contour->GetOutput();
    vtkNew<vtkDoubleArray> depth;
    depth->SetName("Depth");
    depth->SetNumberOfTuples(sphere->GetNumberOfCells());
    for (vtkIdType c = 0; c < sphere->GetNumberOfCells(); ++c)
    {
      double bounds[6];
      sphere->GetCellBounds(c, bounds);
      const int i = 0.5 * (bounds[0] + bounds[1]) < 1 ? 0 : 1;
      const int j = 0.5 * (bounds[2] + bounds[3]) < 1 ? 0 : 1;
      const int k = 0.5 * (bounds[4] + bounds[5]) < 1 ? 0 : 1;
      depth->SetValue(c, (i + j + k) % 2 ? fine : coarse);
    }
    sphere->GetCellData()->AddArray(depth);
    OffscreenRenderer view3d(560, 420);
    vtkCamera* c = view3d.camera();
    c->SetFocalPoint(1.0, 0.56, 1.44);
    c->SetPosition(1.0 + 1.3, 0.56 - 1.6, 1.44 + 1.2);
    c->SetViewUp(0, 0, 1);
    c->SetViewAngle(30);
    const std::string jump = std::to_string(fine - coarse);
    writePng(view3d.render(sphere, "Depth", 0, 5, true, true),
             (out / ("contour_level_jump_" + jump + ".png")).string());
    std::cout << "contour across level jumps of " << jump << ": " << sphere->GetNumberOfCells()
              << " triangles\n";
  }
  return 0;
}
