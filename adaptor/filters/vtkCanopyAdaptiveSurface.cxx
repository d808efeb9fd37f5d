#include "vtkCanopyAdaptiveSurface.h"

#include "AdaptiveSurfaceBuilder.h"
#include "HyperTreeAccess.h"
#include "ViewVolume.h"

#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkObjectFactory.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <cstring>

vtkStandardNewMacro(vtkCanopyAdaptiveSurface);
vtkCxxSetObjectMacro(vtkCanopyAdaptiveSurface, Renderer, vtkRenderer);
vtkCxxSetObjectMacro(vtkCanopyAdaptiveSurface, Camera, vtkCamera);

namespace
{

/// Copies the tuples of `ids` from `source` into a new array of the same type.
vtkSmartPointer<vtkDataArray> gatherTuples(vtkDataArray* source, const std::vector<vtkIdType>& ids)
{
  vtkSmartPointer<vtkDataArray> out =
      vtkSmartPointer<vtkDataArray>::Take(vtkDataArray::CreateDataArray(source->GetDataType()));
  const int nc = source->GetNumberOfComponents();
  out->SetName(source->GetName());
  out->SetNumberOfComponents(nc);
  out->SetNumberOfTuples(static_cast<vtkIdType>(ids.size()));
  // Contiguous sources (the common case: wrapped simulation arrays) by memcpy.
  if (source->HasStandardMemoryLayout() && source->IsA("vtkAOSDataArrayTemplate") == 0)
  {
    // Fall through to the generic path for custom arrays.
  }
  const int size = source->GetDataTypeSize();
  auto* aos = vtkArrayDownCast<vtkDataArray>(source);
  const bool raw = aos && (source->IsA("vtkDoubleArray") || source->IsA("vtkFloatArray") ||
                           source->IsA("vtkTypeInt32Array") || source->IsA("vtkTypeInt64Array") ||
                           source->IsA("vtkIntArray") || source->IsA("vtkLongLongArray") ||
                           source->IsA("vtkLongArray") || source->IsA("vtkUnsignedCharArray") ||
                           source->IsA("vtkCharArray") || source->IsA("vtkShortArray") ||
                           source->IsA("vtkUnsignedIntArray") || source->IsA("vtkIdTypeArray"));
  if (raw)
  {
    const auto* from = static_cast<const unsigned char*>(source->GetVoidPointer(0));
    auto* to = static_cast<unsigned char*>(out->GetVoidPointer(0));
    const std::size_t tupleBytes = static_cast<std::size_t>(nc) * size;
    for (std::size_t i = 0; i < ids.size(); ++i)
    {
      std::memcpy(to + i * tupleBytes, from + static_cast<std::size_t>(ids[i]) * tupleBytes,
                  tupleBytes);
    }
    return out;
  }
  for (std::size_t i = 0; i < ids.size(); ++i)
  {
    for (int c = 0; c < nc; ++c)
    {
      out->SetComponent(static_cast<vtkIdType>(i), c, source->GetComponent(ids[i], c));
    }
  }
  return out;
}

} // namespace

vtkCanopyAdaptiveSurface::vtkCanopyAdaptiveSurface()
{
  this->AppropriateOutput = true;
}

vtkCanopyAdaptiveSurface::~vtkCanopyAdaptiveSurface()
{
  this->SetRenderer(nullptr);
  this->SetCamera(nullptr);
}

void vtkCanopyAdaptiveSurface::AddField(const char* name)
{
  if (name && std::find(this->Fields.begin(), this->Fields.end(), name) == this->Fields.end())
  {
    this->Fields.emplace_back(name);
    this->Modified();
  }
}

void vtkCanopyAdaptiveSurface::ClearFields()
{
  if (!this->Fields.empty())
  {
    this->Fields.clear();
    this->Modified();
  }
}

vtkPolyData* vtkCanopyAdaptiveSurface::GetPolyDataOutput()
{
  return vtkPolyData::SafeDownCast(this->GetOutput());
}

vtkMTimeType vtkCanopyAdaptiveSurface::GetMTime()
{
  vtkMTimeType time = this->Superclass::GetMTime();
  vtkCamera* camera = this->Renderer ? this->Renderer->GetActiveCamera() : this->Camera;
  if (this->Renderer)
  {
    const int* size = this->Renderer->GetSize();
    if (size[0] != this->LastRendererSize[0] || size[1] != this->LastRendererSize[1])
    {
      this->LastRendererSize[0] = size[0];
      this->LastRendererSize[1] = size[1];
      this->RendererSizeTime.Modified();
    }
    time = std::max(time, this->RendererSizeTime.GetMTime());
  }
  if (camera)
  {
    time = std::max(time, camera->GetMTime());
  }
  return time;
}

int vtkCanopyAdaptiveSurface::FillOutputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkPolyData");
  return 1;
}

int vtkCanopyAdaptiveSurface::ProcessTrees(vtkHyperTreeGrid* input, vtkDataObject* outputObject)
{
  vtkPolyData* output = vtkPolyData::SafeDownCast(outputObject);
  if (!output)
  {
    vtkErrorMacro("output is not a vtkPolyData");
    return 0;
  }
  if (!(this->PixelThreshold > 0) || !std::isfinite(this->PixelThreshold))
  {
    vtkErrorMacro("PixelThreshold must be a positive finite number of pixels, got "
                  << this->PixelThreshold);
    return 0;
  }
  if (input->GetDimension() != 2 && input->GetDimension() != 3)
  {
    vtkErrorMacro("only 2D and 3D hypertree grids are supported, got dimension "
                  << input->GetDimension());
    return 0;
  }

  canopy::CameraParameters camera;
  if (this->ViewDependent)
  {
    vtkCamera* source = this->Renderer ? this->Renderer->GetActiveCamera() : this->Camera;
    if (source)
    {
      source->GetPosition(camera.position.data());
      source->GetFocalPoint(camera.focalPoint.data());
      source->GetViewUp(camera.viewUp.data());
      camera.parallelProjection = source->GetParallelProjection() != 0;
      camera.parallelScale = source->GetParallelScale();
      camera.viewAngle = source->GetViewAngle();
      if (!camera.parallelProjection && source->GetUseHorizontalViewAngle())
      {
        vtkErrorMacro("cameras with a horizontal view angle are not supported");
        return 0;
      }
    }
    else
    {
      std::copy(this->CameraPosition, this->CameraPosition + 3, camera.position.begin());
      std::copy(this->CameraFocalPoint, this->CameraFocalPoint + 3, camera.focalPoint.begin());
      std::copy(this->CameraViewUp, this->CameraViewUp + 3, camera.viewUp.begin());
      camera.parallelProjection = this->ParallelProjection;
      camera.parallelScale = this->ParallelScale;
      camera.viewAngle = this->ViewAngle;
    }
    const int* size = this->Renderer ? this->Renderer->GetSize() : this->ViewportSize;
    camera.viewportWidth = size[0];
    camera.viewportHeight = size[1];
    const std::string problem = canopy::ViewVolume::validate(camera);
    if (!problem.empty())
    {
      vtkErrorMacro("invalid view: " << problem);
      return 0;
    }
  }

  canopy::SurfacePieces pieces;
  try
  {
    const canopy::HyperTreeAccess grid(input);
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
    pieces = canopy::buildAdaptiveSurface(grid, options);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro("cannot build the surface: " << e.what());
    return 0;
  }

  const auto quads = static_cast<vtkIdType>(pieces.numberOfQuads());
  vtkNew<vtkDoubleArray> coordinates;
  coordinates->SetNumberOfComponents(3);
  coordinates->SetNumberOfTuples(4 * quads);
  std::copy(pieces.points.begin(), pieces.points.end(), coordinates->GetPointer(0));
  vtkNew<vtkPoints> points;
  points->SetData(coordinates);

  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfTuples(quads + 1);
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfTuples(4 * quads);
  for (vtkIdType q = 0; q <= quads; ++q)
  {
    offsets->SetValue(q, 4 * q);
  }
  for (vtkIdType p = 0; p < 4 * quads; ++p)
  {
    connectivity->SetValue(p, p);
  }
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);

  output->Initialize();
  output->SetPoints(points);
  output->SetPolys(polys);

  vtkCellData* in = input->GetCellData();
  vtkCellData* out = output->GetCellData();
  for (int a = 0; a < in->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = in->GetArray(a);
    if (!array || !array->GetName())
    {
      continue;
    }
    if (!this->Fields.empty() &&
        std::find(this->Fields.begin(), this->Fields.end(), array->GetName()) == this->Fields.end())
    {
      continue;
    }
    out->AddArray(gatherTuples(array, pieces.cellIds));
  }
  vtkNew<vtkIdTypeArray> ids;
  ids->SetName("OriginalCellId");
  ids->SetNumberOfTuples(quads);
  std::copy(pieces.cellIds.begin(), pieces.cellIds.end(), ids->GetPointer(0));
  out->AddArray(ids);
  vtkNew<vtkUnsignedCharArray> levels;
  levels->SetName("Level");
  levels->SetNumberOfTuples(quads);
  std::copy(pieces.levels.begin(), pieces.levels.end(), levels->GetPointer(0));
  out->AddArray(levels);
  return 1;
}

void vtkCanopyAdaptiveSurface::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Renderer: " << this->Renderer << "\n"
     << indent << "Camera: " << this->Camera << "\n"
     << indent << "CameraPosition: " << this->CameraPosition[0] << " " << this->CameraPosition[1]
     << " " << this->CameraPosition[2] << "\n"
     << indent << "CameraFocalPoint: " << this->CameraFocalPoint[0] << " "
     << this->CameraFocalPoint[1] << " " << this->CameraFocalPoint[2] << "\n"
     << indent << "ParallelProjection: " << this->ParallelProjection << "\n"
     << indent << "ParallelScale: " << this->ParallelScale << "\n"
     << indent << "ViewAngle: " << this->ViewAngle << "\n"
     << indent << "ViewportSize: " << this->ViewportSize[0] << " x " << this->ViewportSize[1]
     << "\n"
     << indent << "ViewDependent: " << this->ViewDependent << "\n"
     << indent << "ViewCulling: " << this->ViewCulling << "\n"
     << indent << "LevelOfDetail: " << this->LevelOfDetail << "\n"
     << indent << "PixelThreshold: " << this->PixelThreshold << "\n"
     << indent << "SkipBackFaces: " << this->SkipBackFaces << "\n";
}
