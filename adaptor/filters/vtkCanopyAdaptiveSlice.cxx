#include <canopy/filters/vtkCanopyAdaptiveSlice.h>

#include "AdaptiveSliceBuilder.h"
#include "EdgeVertexExchange.h"
#include "HyperTreeAccess.h"
#include "HyperTreeAccessCache.h"
#include "TreeProgress.h"
#include "ViewDependentFilterInternals.h"
#include "ViewVolume.h"

#include <vtkDoubleArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkIdTypeArray.h>
#include <vtkMultiProcessController.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <stdexcept>
#include <string>

vtkStandardNewMacro(vtkCanopyAdaptiveSlice);

vtkCanopyAdaptiveSlice::vtkCanopyAdaptiveSlice() = default;

vtkCanopyAdaptiveSlice::~vtkCanopyAdaptiveSlice() = default;

void vtkCanopyAdaptiveSlice::AddPlane(int axis, double position)
{
  if (axis >= 0 && axis < 3)
  {
    this->Positions[static_cast<std::size_t>(axis)].push_back(position);
  }
  else
  {
    this->InvalidAxes.push_back(axis);
  }
  this->Modified();
}

void vtkCanopyAdaptiveSlice::ClearPlanes()
{
  for (auto& positions : this->Positions)
  {
    positions.clear();
  }
  this->InvalidAxes.clear();
  this->Modified();
}

void vtkCanopyAdaptiveSlice::ClearAxis(int axis)
{
  this->Positions[static_cast<std::size_t>(axis)].clear();
  this->Modified();
}

int vtkCanopyAdaptiveSlice::GetNumberOfPlanes() const
{
  std::size_t planes = this->InvalidAxes.size();
  for (const auto& positions : this->Positions)
  {
    planes += positions.size();
  }
  return static_cast<int>(planes);
}

int vtkCanopyAdaptiveSlice::ProcessTrees(vtkHyperTreeGrid* input, vtkDataObject* outputObject)
{
  this->LastVisited = 0;
  vtkPolyData* output = vtkPolyData::SafeDownCast(outputObject);
  if (!output)
  {
    vtkErrorMacro("output is not a vtkPolyData");
    return 0;
  }
  canopy::CameraParameters camera;
  const bool viewUsable = this->Internals->CurrentView(camera);
  std::vector<canopy::SlicePlane> planes;
  for (int axis = 0; axis < 3; ++axis)
  {
    for (double position : this->Positions[static_cast<std::size_t>(axis)])
    {
      planes.push_back({axis, position});
    }
  }
  for (int axis : this->InvalidAxes)
  {
    planes.push_back({axis, 0.0});
  }
  // No index tables and no masked-descendant flags: both cost a pass over
  // every node, and a slice reads only the nodes it cuts.
  std::shared_ptr<const canopy::HyperTreeAccess> access;
  std::string problem;
  try
  {
    access = this->Internals->Topology->get(input, false, false);
    problem = canopy::AdaptiveSliceBuilder::validate(*access, planes);
  }
  catch (const std::exception& e)
  {
    this->Internals->Topology->clear();
    problem = std::string("cannot build the slices: ") + e.what();
  }
  // A grid split between ranks: every rank agrees whether to go on and whether
  // the ranks exchange the corners of their cuts along each other's parts
  // (EdgeVertexExchange.h), before anything collective.
  vtkMultiProcessController* controller = this->Controller;
  const bool collective = controller && controller->GetNumberOfProcesses() > 1;
  int local[2] = {!viewUsable || !problem.empty() ? 1 : 0,
                  access && (access->hasAbsent() || access->hasTreesElsewhere()) ? 1 : 0};
  int agreed[2] = {local[0], local[1]};
  if (collective)
  {
    controller->AllReduce(local, agreed, 2, vtkCommunicator::MAX_OP);
  }
  if (agreed[0])
  {
    if (!problem.empty())
    {
      vtkErrorMacro(<< (access ? "cannot slice: " : "") << problem);
    }
    else if (viewUsable)
    {
      vtkErrorMacro("cannot build the slices: another process failed");
    }
    return 0;
  }

  output->Initialize();
  const vtkInternals::CellArrays arrays = this->Internals->NewCellArrays();
  vtkIdType quads = 0;
  try
  {
    canopy::SliceOptions options;
    const vtkInternals::ViewResources resources =
        this->Internals->ViewOptionsFor(camera, input, options);
    canopy::TreeProgress progress(this);
    canopy::AdaptiveSliceBuilder builder(*access, std::move(planes), options, {&progress});
    quads = static_cast<vtkIdType>(builder.count());
    this->LastVisited = static_cast<vtkIdType>(builder.visited());
    if (collective && agreed[1])
    {
      // Collective: an aborted rank still takes part.
      canopy::exchangeSharedVertices(builder, controller);
    }
    if (progress.stopped())
    {
      return 1; // aborted: the output stays empty
    }
    builder.write(
        this->Internals->SizeCellArrays(arrays, quads, static_cast<vtkIdType>(builder.points())));
  }
  catch (const std::exception& e)
  {
    this->Internals->Topology->clear();
    vtkErrorMacro("cannot build the slices: " << e.what());
    return 0;
  }
  this->Internals->AssembleOutput(input, output, arrays, quads, false);
  return 1;
}

bool vtkCanopyAdaptiveSlice::OneLayerFacing(vtkHyperTreeGrid*, int axis) const
{
  std::vector<double> at = this->Positions[static_cast<std::size_t>(axis)];
  std::sort(at.begin(), at.end());
  return !at.empty() && at.front() == at.back();
}

void vtkCanopyAdaptiveSlice::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const char* names[3] = {"XPlanes", "YPlanes", "ZPlanes"};
  for (std::size_t axis = 0; axis < 3; ++axis)
  {
    os << indent << names[axis] << ":";
    for (double position : this->Positions[axis])
    {
      os << " " << position;
    }
    os << "\n";
  }
  os << indent << "InvalidAxes:";
  for (int axis : this->InvalidAxes)
  {
    os << " " << axis;
  }
  os << "\n" << indent << "LastVisited: " << this->LastVisited << "\n";
}
