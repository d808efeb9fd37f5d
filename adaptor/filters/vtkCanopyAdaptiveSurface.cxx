#include <canopy/filters/vtkCanopyAdaptiveSurface.h>

#include "AdaptiveSurfaceBuilder.h"
#include "EdgeVertexExchange.h"
#include "HyperTreeAccess.h"
#include "HyperTreeAccessCache.h"
#include "RemoteFaceExchange.h"
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

vtkStandardNewMacro(vtkCanopyAdaptiveSurface);

struct vtkCanopyAdaptiveSurface::vtkSurfaceInternals
{
  /// 3D: the builder's per-tree cell buffers, kept between executions.
  std::vector<canopy::TreeCells> CellBuffers;
};

vtkCanopyAdaptiveSurface::vtkCanopyAdaptiveSurface()
    : SurfaceInternals(std::make_unique<vtkSurfaceInternals>())
{
}

vtkCanopyAdaptiveSurface::~vtkCanopyAdaptiveSurface() = default;

bool vtkCanopyAdaptiveSurface::OneLayerFacing(vtkHyperTreeGrid* input, int) const
{
  return input->GetDimension() == 2;
}

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
  const bool viewUsable = this->Internals->CurrentView(camera);
  // Split 2D and 3D grids: every rank agrees whether to go on, whether faces
  // between ranks must be asked about (3D, masks) and whether the ranks put
  // the corners of their pieces on each other's edges (EdgeVertexExchange.h),
  // before anything collective.
  vtkMultiProcessController* controller = this->Controller;
  const bool collective =
      input->GetDimension() >= 2 && controller && controller->GetNumberOfProcesses() > 1;
  std::shared_ptr<const canopy::HyperTreeAccess> access;
  std::string problem;
  try
  {
    access = this->Internals->Topology->get(input, true);
  }
  catch (const std::exception& e)
  {
    this->Internals->Topology->clear();
    problem = e.what();
  }
  int local[3] = {!viewUsable || !access ? 1 : 0, access && access->hasMask() ? 1 : 0,
                  access && (access->hasAbsent() || access->hasTreesElsewhere()) ? 1 : 0};
  int agreed[3] = {local[0], local[1], local[2]};
  if (collective)
  {
    controller->AllReduce(local, agreed, 3, vtkCommunicator::MAX_OP);
  }
  if (agreed[0])
  {
    if (!problem.empty())
    {
      vtkErrorMacro("cannot build the surface: " << problem);
    }
    else if (viewUsable)
    {
      vtkErrorMacro("cannot build the surface: another process failed");
    }
    return 0;
  }

  // Release the previous output first: its arrays can then be reused.
  output->Initialize();
  const vtkInternals::CellArrays arrays = this->Internals->NewCellArrays();
  vtkIdType quads = 0; // cells: flat pieces, or segments of a 1D grid
  canopy::TreeProgress progress(this);
  try
  {
    canopy::SurfaceOptions options;
    const vtkInternals::ViewResources resources =
        this->Internals->ViewOptionsFor(camera, input, options);
    options.skipBackFaces = this->SkipBackFaces;
    options.remoteFaces = collective && input->GetDimension() == 3 && agreed[1] && agreed[2];
    options.sharedVertices = collective && agreed[2];
    options.memoize = this->Internals->Topology->lastWasKept();
    canopy::AdaptiveSurfaceBuilder builder(*access, options, &this->SurfaceInternals->CellBuffers,
                                           {&progress});
    builder.count();
    if (options.remoteFaces)
    {
      // Collective: an aborted rank still answers the others.
      canopy::exchangeRemoteFaces(builder, controller);
    }
    if (options.sharedVertices)
    {
      // The same; after the remote faces, whose pieces have edges too.
      canopy::exchangeSharedVertices(builder, controller);
    }
    if (progress.stopped())
    {
      return 1; // aborted: the output stays empty
    }
    quads = static_cast<vtkIdType>(builder.cells());
    builder.write(
        this->Internals->SizeCellArrays(arrays, quads, static_cast<vtkIdType>(builder.points())));
    if (progress.stopped())
    {
      return 1; // aborted: the arrays are partly written, the output stays empty
    }
  }
  catch (const std::exception& e)
  {
    this->Internals->Topology->clear();
    vtkErrorMacro("cannot build the surface: " << e.what());
    return 0;
  }
  this->Internals->AssembleOutput(input, output, arrays, quads, input->GetDimension() == 1);
  if (input->GetDimension() == 3)
  {
    this->Internals->AddAxisNormals(output);
  }
  return 1;
}

void vtkCanopyAdaptiveSurface::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SkipBackFaces: " << this->SkipBackFaces << "\n";
}
