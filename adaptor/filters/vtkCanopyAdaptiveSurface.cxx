#include "vtkCanopyAdaptiveSurface.h"

#include "AdaptiveSurfaceBuilder.h"
#include "HyperTreeAccess.h"
#include "HyperTreeAccessCache.h"
#include "ViewVolume.h"

#include <vtkDoubleArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkIdTypeArray.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

vtkStandardNewMacro(vtkCanopyAdaptiveSurface);

vtkCanopyAdaptiveSurface::vtkCanopyAdaptiveSurface() = default;

vtkCanopyAdaptiveSurface::~vtkCanopyAdaptiveSurface() = default;

int vtkCanopyAdaptiveSurface::ProcessTrees(vtkHyperTreeGrid* input, vtkDataObject* outputObject)
{
  vtkPolyData* output = vtkPolyData::SafeDownCast(outputObject);
  if (!output)
  {
    vtkErrorMacro("output is not a vtkPolyData");
    return 0;
  }
  if (input->GetDimension() < 1 || input->GetDimension() > 3)
  {
    vtkErrorMacro("only 1D, 2D and 3D hypertree grids are supported, got dimension "
                  << input->GetDimension());
    return 0;
  }
  canopy::CameraParameters camera;
  if (!this->CurrentView(camera))
  {
    return 0;
  }

  // Release the previous output first: its arrays can then be reused.
  output->Initialize();
  const CellArrays arrays = this->NewCellArrays();
  vtkIdType quads = 0; // cells: quads, or segments of a 1D grid
  vtkIdType perCell = 4;
  try
  {
    const std::shared_ptr<const canopy::HyperTreeAccess> access = this->Topology->get(input, true);
    std::unique_ptr<canopy::ViewVolume> view;
    canopy::SurfaceOptions options;
    if (this->ViewDependent)
    {
      view = std::make_unique<canopy::ViewVolume>(camera);
      options.view = view.get();
    }
    options.cullOutsideView = this->ViewCulling;
    options.levelOfDetail = this->LevelOfDetail;
    options.pixelThreshold = this->PixelThreshold;
    options.skipBackFaces = this->SkipBackFaces;
    canopy::AdaptiveSurfaceBuilder builder(*access, options);
    quads = static_cast<vtkIdType>(builder.count());
    perCell = static_cast<vtkIdType>(builder.pointsPerCell());
    // Allocated once, written in place by the trees in parallel.
    arrays.Points->SetNumberOfTuples(perCell * quads);
    arrays.Ids->SetNumberOfTuples(quads);
    arrays.Levels->SetNumberOfTuples(quads);
    builder.write(
        {arrays.Points->GetPointer(0), arrays.Ids->GetPointer(0), arrays.Levels->GetPointer(0)});
  }
  catch (const std::exception& e)
  {
    this->Topology->clear();
    vtkErrorMacro("cannot build the surface: " << e.what());
    return 0;
  }
  this->AssembleOutput(input, output, arrays, quads, perCell);
  return 1;
}

void vtkCanopyAdaptiveSurface::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SkipBackFaces: " << this->SkipBackFaces << "\n";
}
