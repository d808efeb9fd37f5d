#include <canopy/filters/vtkCanopyViewDependentFilter.h>

#include "ViewDependentFilterInternals.h"

#include "AdaptiveSurfaceBuilder.h"
#include "GatherFromAll.h"
#include "GatherTuples.h"
#include "HyperTreeAccessCache.h"
#include "LeafColorAverage.h"
#include "PixelBoxFilter.h"
#include "Vec3.h"
#include "ViewVolume.h"

#include <vtkAOSDataArrayTemplate.h>
#include <vtkBuffer.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkMultiProcessController.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>
#include <vtkSMPTools.h>
#include <vtkScalarsToColors.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

void vtkCanopyViewDependentFilter::SetRenderer(vtkRenderer* renderer)
{
  if (this->Renderer != renderer)
  {
    this->Renderer = renderer;
    this->Modified();
  }
}

vtkRenderer* vtkCanopyViewDependentFilter::GetRenderer()
{
  return this->Renderer;
}

vtkCxxSetObjectMacro(vtkCanopyViewDependentFilter, Camera, vtkCamera);
vtkCxxSetObjectMacro(vtkCanopyViewDependentFilter, ColorMap, vtkScalarsToColors);

vtkCanopyViewDependentFilter::vtkInternals::ViewResources::ViewResources() = default;
vtkCanopyViewDependentFilter::vtkInternals::ViewResources::~ViewResources() = default;
vtkCanopyViewDependentFilter::vtkInternals::ViewResources::ViewResources(ViewResources&&) noexcept =
    default;
vtkCanopyViewDependentFilter::vtkInternals::ViewResources&
vtkCanopyViewDependentFilter::vtkInternals::ViewResources::operator=(ViewResources&&) noexcept =
    default;

vtkCanopyViewDependentFilter::vtkInternals::vtkInternals(vtkCanopyViewDependentFilter& filter)
    : Topology(std::make_unique<canopy::HyperTreeAccessCache>()), Filter(filter)
{
}

vtkCanopyViewDependentFilter::vtkInternals::~vtkInternals() = default;

vtkCanopyViewDependentFilter::vtkCanopyViewDependentFilter()
    : Internals(std::make_unique<vtkInternals>(*this))
{
  this->AppropriateOutput = true;
  this->SetController(vtkMultiProcessController::GetGlobalController());
}

vtkCanopyViewDependentFilter::~vtkCanopyViewDependentFilter()
{
  this->SetCamera(nullptr);
  this->SetColorMap(nullptr);
  this->SetController(nullptr);
}

void vtkCanopyViewDependentFilter::AddField(const char* name)
{
  if (name && std::find(this->Fields.begin(), this->Fields.end(), name) == this->Fields.end())
  {
    this->Fields.emplace_back(name);
    this->Modified();
  }
}

void vtkCanopyViewDependentFilter::ClearFields()
{
  if (!this->Fields.empty())
  {
    this->Fields.clear();
    this->Modified();
  }
}

vtkPolyData* vtkCanopyViewDependentFilter::GetPolyDataOutput()
{
  return vtkPolyData::SafeDownCast(this->GetOutput());
}

vtkMTimeType vtkCanopyViewDependentFilter::GetMTime()
{
  vtkMTimeType time = this->Superclass::GetMTime();
  vtkCamera* camera = this->Camera;
  if (this->Renderer)
  {
    time = std::max(time, this->Renderer->GetMTime());
    const int* size = this->Renderer->GetSize();
    if (size[0] != this->Internals->LastRendererSize[0] ||
        size[1] != this->Internals->LastRendererSize[1])
    {
      this->Internals->LastRendererSize[0] = size[0];
      this->Internals->LastRendererSize[1] = size[1];
      this->Internals->RendererSizeTime.Modified();
    }
    time = std::max(time, this->Internals->RendererSizeTime.GetMTime());
    // Do not create a camera just to ask for its time.
    camera = this->Renderer->IsActiveCameraCreated() ? this->Renderer->GetActiveCamera() : nullptr;
  }
  if (camera != this->Internals->LastCamera)
  {
    this->Internals->LastCamera = camera;
    this->Internals->CameraSwapTime.Modified();
  }
  time = std::max(time, this->Internals->CameraSwapTime.GetMTime());
  if (camera)
  {
    time = std::max(time, camera->GetMTime());
  }
  if (this->ColorMap)
  {
    time = std::max(time, this->ColorMap->GetMTime());
  }
  return time;
}

vtkCxxSetObjectMacro(vtkCanopyViewDependentFilter, Controller, vtkMultiProcessController);

int vtkCanopyViewDependentFilter::RequestData(vtkInformation* request,
                                              vtkInformationVector** inputVector,
                                              vtkInformationVector* outputVector)
{
  this->Internals->ExecutedView.reset();
  this->LastPixelFiltered = 0;
  const int done = this->Superclass::RequestData(request, inputVector, outputVector);
  vtkHyperTreeGrid* input = vtkHyperTreeGrid::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  // Everything deciding whether to filter is the same on every rank (the
  // properties, the view, the input's shape), so all or none exchange.
  if (!this->FilterColorsOnPixels || !this->ColorMap || this->ColorField.empty() ||
      !this->ViewDependent || !this->Internals->ExecutedView || !input || !output)
  {
    return done;
  }
  const canopy::ViewVolume view(*this->Internals->ExecutedView);
  const int axis = canopy::PixelBoxFilter::faceOnAxis(view);
  if (axis < 0 || !this->OneLayerFacing(input, axis))
  {
    return done;
  }
  // This rank's quads (none when its part failed: it still takes part).
  auto* colors = vtkUnsignedCharArray::SafeDownCast(output->GetCellData()->GetArray("Colors"));
  vtkDoubleArray* points =
      output->GetPoints() ? vtkDoubleArray::SafeDownCast(output->GetPoints()->GetData()) : nullptr;
  vtkCellArray* polys = output->GetPolys();
  const bool quads = colors && points && polys && polys->IsStorage64Bit() &&
                     polys->GetNumberOfCells() == output->GetNumberOfCells();
  const vtkIdType count = quads ? output->GetNumberOfCells() : 0;
  canopy::PixelBoxFilter filter(
      view, quads ? points->GetPointer(0) : nullptr,
      quads ? reinterpret_cast<const vtkIdType*>(polys->GetOffsetsArray64()->GetPointer(0))
            : nullptr,
      count, quads ? colors->GetPointer(0) : nullptr);
  vtkMultiProcessController* controller = this->Controller;
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    std::vector<vtkIdType> counts;
    filter.addShares(canopy::gatherFromAll(controller, filter.shares(), counts));
  }
  if (quads)
  {
    this->LastPixelFiltered = filter.finish(colors->GetPointer(0)).recoloured;
    colors->Modified();
  }
  return done;
}

int vtkCanopyViewDependentFilter::FillOutputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkPolyData");
  return 1;
}

bool vtkCanopyViewDependentFilter::vtkInternals::CurrentView(canopy::CameraParameters& camera)
{
  if (!(this->Filter.PixelThreshold > 0) || !std::isfinite(this->Filter.PixelThreshold))
  {
    vtkErrorWithObjectMacro(&this->Filter,
                            "PixelThreshold must be a positive finite number of pixels, got "
                                << this->Filter.PixelThreshold);
    return false;
  }
  if (!this->Filter.ViewDependent)
  {
    return true;
  }
  vtkCamera* source =
      this->Filter.Renderer ? this->Filter.Renderer->GetActiveCamera() : this->Filter.Camera;
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
      vtkErrorWithObjectMacro(&this->Filter,
                              "cameras with a horizontal view angle are not supported");
      return false;
    }
  }
  else
  {
    std::copy(this->Filter.CameraPosition, this->Filter.CameraPosition + 3,
              camera.position.begin());
    std::copy(this->Filter.CameraFocalPoint, this->Filter.CameraFocalPoint + 3,
              camera.focalPoint.begin());
    std::copy(this->Filter.CameraViewUp, this->Filter.CameraViewUp + 3, camera.viewUp.begin());
    camera.parallelProjection = this->Filter.ParallelProjection;
    camera.parallelScale = this->Filter.ParallelScale;
    camera.viewAngle = this->Filter.ViewAngle;
  }
  const int* size =
      this->Filter.Renderer ? this->Filter.Renderer->GetSize() : this->Filter.ViewportSize;
  camera.viewportWidth = size[0];
  camera.viewportHeight = size[1];
  const std::string problem = canopy::ViewVolume::validate(camera);
  if (!problem.empty())
  {
    vtkErrorWithObjectMacro(&this->Filter, "invalid view: " << problem);
    return false;
  }
  this->ExecutedView = std::make_unique<canopy::CameraParameters>(camera);
  return true;
}

vtkCanopyViewDependentFilter::vtkInternals::ViewResources
vtkCanopyViewDependentFilter::vtkInternals::ViewOptionsFor(const canopy::CameraParameters& camera,
                                                           vtkHyperTreeGrid* input,
                                                           canopy::ViewOptions& options) const
{
  ViewResources resources;
  if (this->Filter.ViewDependent)
  {
    resources.View = std::make_unique<canopy::ViewVolume>(camera);
  }
  if (this->Filter.ColorMap && !this->Filter.ColorField.empty())
  {
    vtkDataArray* values = input->GetCellData()->GetArray(this->Filter.ColorField.c_str());
    if (!values)
    {
      throw std::invalid_argument("ColorField: no cell field named '" + this->Filter.ColorField +
                                  "'");
    }
    if (this->Filter.ColorComponent >= values->GetNumberOfComponents() ||
        this->Filter.ColorComponent < -1)
    {
      throw std::invalid_argument("ColorComponent " + std::to_string(this->Filter.ColorComponent) +
                                  ": field '" + this->Filter.ColorField + "' has " +
                                  std::to_string(values->GetNumberOfComponents()) +
                                  " component(s)");
    }
    // A one-component field is mapped by its value, not its magnitude.
    const int component = values->GetNumberOfComponents() == 1 ? 0 : this->Filter.ColorComponent;
    if (!this->SampledColorMap || !this->SampledColorMap->sampledFrom(this->Filter.ColorMap))
    {
      this->SampledColorMap = std::make_shared<canopy::ColorTable>(this->Filter.ColorMap);
    }
    this->SampledColorMap->setField(values, component);
    resources.Colors = this->SampledColorMap;
  }
  options.view = resources.View.get();
  options.cullOutsideView = this->Filter.ViewCulling;
  options.levelOfDetail = this->Filter.LevelOfDetail;
  options.pixelThreshold = this->Filter.PixelThreshold;
  options.colors = resources.Colors.get();
  return resources;
}

namespace
{

/// Reads an AoS array's protected storage buffer (a pointer to member formed in
/// a derived class is a pointer to the base's member: well defined).
template <typename T>
struct BufferOf : vtkAOSDataArrayTemplate<T>
{
  static vtkBuffer<T>* get(vtkAOSDataArrayTemplate<T>* array)
  {
    vtkBuffer<T>* vtkAOSDataArrayTemplate<T>::*member = &BufferOf::Buffer;
    return array->*member;
  }
};

/// True when the array's memory is also held elsewhere (ShallowCopy shares the
/// buffer, not the array object): then it must not be overwritten.
bool storageShared(vtkDataArray* array)
{
  switch (array->GetDataType())
  {
    vtkTemplateMacro({
      auto* aos = vtkAOSDataArrayTemplate<VTK_TT>::FastDownCast(array);
      return !aos || BufferOf<VTK_TT>::get(aos)->GetReferenceCount() > 1;
    });
  }
  return true;
}

} // namespace

template <typename ArrayType>
vtkSmartPointer<ArrayType>
vtkCanopyViewDependentFilter::vtkInternals::ReusableArray(const std::string& key, int dataType)
{
  // Fresh memory is expensive (first-touch page faults cost more than writing
  // the output); an array only this filter still holds is reused instead.
  auto& slot = this->Reusable[key];
  if (slot && slot->GetReferenceCount() == 1 && slot->GetDataType() == dataType &&
      !storageShared(slot))
  {
    if (auto* typed = ArrayType::SafeDownCast(slot))
    {
      typed->Modified(); // its values change: drop cached ranges
      return typed;
    }
  }
  slot = vtkSmartPointer<vtkDataArray>::Take(vtkDataArray::CreateDataArray(dataType));
  return ArrayType::SafeDownCast(slot);
}

vtkSmartPointer<vtkIdTypeArray>
vtkCanopyViewDependentFilter::vtkInternals::ArithmeticIds(const std::string& key, vtkIdType count,
                                                          vtkIdType step)
{
  KeptSequence& kept = this->Sequences[key];
  // The values are right if ReusableArray hands back the array this wrote last,
  // unmodified since. (A replaced array is created before the old one is
  // released, so the two never share an address.)
  vtkDataArray* previous = this->Reusable[key];
  const bool unmodified = previous && previous->GetMTime() == kept.Time && kept.Step == step;
  auto array = this->ReusableArray<vtkIdTypeArray>(key, VTK_ID_TYPE);
  // Within its allocation, resizing keeps the values; beyond it, VTK allocates
  // afresh (vtkGenericDataArray::Allocate) and every value is written again.
  if (!unmodified || array.Get() != previous || count > array->GetSize())
  {
    kept.Valid = 0;
  }
  kept.Step = step;
  array->SetNumberOfTuples(count);
  vtkIdType* value = array->GetPointer(0);
  vtkSMPTools::For(std::min(kept.Valid, count), count,
                   [&](vtkIdType begin, vtkIdType end)
                   {
                     for (vtkIdType i = begin; i < end; ++i)
                     {
                       value[i] = step * i;
                     }
                   });
  kept.Valid = count;
  array->Modified();
  kept.Time = array->GetMTime();
  return array;
}

vtkCanopyViewDependentFilter::vtkInternals::CellArrays
vtkCanopyViewDependentFilter::vtkInternals::NewCellArrays()
{
  CellArrays arrays;
  arrays.Points = this->ReusableArray<vtkDoubleArray>("points", VTK_DOUBLE);
  arrays.Points->SetNumberOfComponents(3);
  arrays.Offsets = this->ReusableArray<vtkIdTypeArray>("cellOffsets", VTK_ID_TYPE);
  arrays.Ids = this->ReusableArray<vtkIdTypeArray>("OriginalCellId", VTK_ID_TYPE);
  arrays.Ids->SetName("OriginalCellId");
  arrays.Levels = this->ReusableArray<vtkUnsignedCharArray>("Level", VTK_UNSIGNED_CHAR);
  arrays.Levels->SetName("Level");
  if (this->Filter.ColorMap && !this->Filter.ColorField.empty())
  {
    arrays.Colors = this->ReusableArray<vtkUnsignedCharArray>("Colors", VTK_UNSIGNED_CHAR);
    arrays.Colors->SetName("Colors");
    arrays.Colors->SetNumberOfComponents(3);
  }
  return arrays;
}

canopy::SurfaceArrays
vtkCanopyViewDependentFilter::vtkInternals::SizeCellArrays(const CellArrays& arrays,
                                                           vtkIdType cells, vtkIdType points)
{
  // Allocated once, written in place by the trees in parallel.
  arrays.Points->SetNumberOfTuples(points);
  arrays.Offsets->SetNumberOfTuples(cells + 1);
  arrays.Ids->SetNumberOfTuples(cells);
  arrays.Levels->SetNumberOfTuples(cells);
  if (arrays.Colors)
  {
    arrays.Colors->SetNumberOfTuples(cells);
  }
  return {arrays.Points->GetPointer(0), arrays.Offsets->GetPointer(0), arrays.Ids->GetPointer(0),
          arrays.Levels->GetPointer(0), arrays.Colors ? arrays.Colors->GetPointer(0) : nullptr};
}

void vtkCanopyViewDependentFilter::vtkInternals::AssembleOutput(vtkHyperTreeGrid* input,
                                                                vtkPolyData* output,
                                                                const CellArrays& arrays,
                                                                vtkIdType cells, bool segments)
{
  vtkNew<vtkPoints> points;
  points->SetData(arrays.Points);

  // Every cell's points are its own, written in cell order.
  auto connectivity = this->ArithmeticIds("connectivity", arrays.Points->GetNumberOfTuples(), 1);
  arrays.Offsets->Modified();
  vtkNew<vtkCellArray> cellArray;
  cellArray->SetData(arrays.Offsets, connectivity);

  output->SetPoints(points);
  if (segments)
  {
    output->SetLines(cellArray); // two-point lines: VTK_LINE cells
  }
  else
  {
    output->SetPolys(cellArray);
  }

  vtkCellData* in = input->GetCellData();
  vtkCellData* out = output->GetCellData();
  for (int a = 0; a < in->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = in->GetArray(a);
    if (!array || !array->GetName())
    {
      continue;
    }
    if (!this->Filter.Fields.empty() &&
        std::find(this->Filter.Fields.begin(), this->Filter.Fields.end(), array->GetName()) ==
            this->Filter.Fields.end())
    {
      continue;
    }
    vtkSmartPointer<vtkDataArray> target = this->ReusableArray<vtkDataArray>(
        std::string("field:") + array->GetName(), array->GetDataType());
    out->AddArray(canopy::gatherTuples(array, arrays.Ids->GetPointer(0), cells, target));
  }
  out->AddArray(arrays.Ids);
  out->AddArray(arrays.Levels);
  if (arrays.Colors)
  {
    out->AddArray(arrays.Colors);
  }
}

void vtkCanopyViewDependentFilter::vtkInternals::AddAxisNormals(vtkPolyData* output)
{
  auto normals = this->ReusableArray<vtkFloatArray>("Normals", VTK_FLOAT);
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  const vtkIdType cells = output->GetNumberOfCells();
  normals->SetNumberOfTuples(cells);
  // The builders write each polygon's points consecutively, corners in order
  // with any extra vertices on the edges between them: the first point is a
  // corner, the second lies along its first edge and the last along its last.
  const double* p = vtkDoubleArray::SafeDownCast(output->GetPoints()->GetData())->GetPointer(0);
  static_assert(sizeof(vtkIdType) == sizeof(vtkTypeInt64), "64-bit ids");
  const auto* offsets =
      reinterpret_cast<const vtkIdType*>(output->GetPolys()->GetOffsetsArray64()->GetPointer(0));
  float* n = normals->GetPointer(0);
  vtkSMPTools::For(0, cells,
                   [&](vtkIdType begin, vtkIdType end)
                   {
                     for (vtkIdType q = begin; q < end; ++q)
                     {
                       auto point = [p](vtkIdType k) {
                         return canopy::Vec3{{p[3 * k], p[3 * k + 1], p[3 * k + 2]}};
                       };
                       const canopy::Vec3 first = point(offsets[q]);
                       const canopy::Vec3 normal =
                           canopy::cross(canopy::sub(point(offsets[q] + 1), first),
                                         canopy::sub(point(offsets[q + 1] - 1), first));
                       for (int a = 0; a < 3; ++a)
                       {
                         const double x = normal[a];
                         n[3 * q + a] = x > 0 ? 1.0f : x < 0 ? -1.0f : 0.0f;
                       }
                     }
                   });
  output->GetCellData()->SetNormals(normals);
}

bool vtkCanopyViewDependentFilter::GetLastTopologyKept() const
{
  return this->Internals->Topology->lastWasKept();
}

void vtkCanopyViewDependentFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Renderer: " << this->Renderer.GetPointer() << "\n"
     << indent << "Camera: " << this->Camera << "\n"
     << indent << "CameraPosition: " << this->CameraPosition[0] << " " << this->CameraPosition[1]
     << " " << this->CameraPosition[2] << "\n"
     << indent << "CameraFocalPoint: " << this->CameraFocalPoint[0] << " "
     << this->CameraFocalPoint[1] << " " << this->CameraFocalPoint[2] << "\n"
     << indent << "CameraViewUp: " << this->CameraViewUp[0] << " " << this->CameraViewUp[1] << " "
     << this->CameraViewUp[2] << "\n"
     << indent << "ParallelProjection: " << this->ParallelProjection << "\n"
     << indent << "ParallelScale: " << this->ParallelScale << "\n"
     << indent << "ViewAngle: " << this->ViewAngle << "\n"
     << indent << "ViewportSize: " << this->ViewportSize[0] << " x " << this->ViewportSize[1]
     << "\n"
     << indent << "ViewDependent: " << this->ViewDependent << "\n"
     << indent << "ViewCulling: " << this->ViewCulling << "\n"
     << indent << "LevelOfDetail: " << this->LevelOfDetail << "\n"
     << indent << "PixelThreshold: " << this->PixelThreshold << "\n"
     << indent << "ColorMap: " << this->ColorMap << "\n"
     << indent << "ColorField: " << this->ColorField << "\n"
     << indent << "ColorComponent: " << this->ColorComponent << "\n"
     << indent << "FilterColorsOnPixels: " << this->FilterColorsOnPixels << "\n"
     << indent << "LastPixelFiltered: " << this->LastPixelFiltered << "\n"
     << indent << "LastTopologyKept: " << this->GetLastTopologyKept() << "\n"
     << indent << "Controller: " << this->Controller << "\n"
     << indent << "Fields:";
  for (const std::string& field : this->Fields)
  {
    os << " " << field;
  }
  os << (this->Fields.empty() ? " (all)\n" : "\n");
}
