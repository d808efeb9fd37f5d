#include <canopy/filters/vtkCanopyExtractSelection.h>

#include "CellSelection.h"
#include "HyperTreeAccess.h"
#include "HyperTreeAccessCache.h"
#include "MaskedGridOutput.h"
#include "SelectedCellsOutput.h"
#include "SelectionMask.h"
#include "SelectionMaskMemo.h"
#include "SelectionPasses.h"
#include "SelectionSpec.h"
#include "TreeProgress.h"

#include <vtkHyperTreeGrid.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkSelection.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <array>

vtkStandardNewMacro(vtkCanopyExtractSelection);

struct vtkCanopyExtractSelection::vtkInternals
{
  /// The input's topology read once while it is unchanged (a value range that
  /// changes every step re-reads nothing but the values).
  canopy::HyperTreeAccessCache Topology;
  /// The last mask, tree by tree (PreserveTopology): the next execution redoes
  /// only the trees whose inputs changed.
  canopy::SelectionMaskMemo MaskMemo;
};

vtkCanopyExtractSelection::vtkCanopyExtractSelection() : Internals(std::make_unique<vtkInternals>())
{
  this->SetNumberOfInputPorts(2);
}

vtkCanopyExtractSelection::~vtkCanopyExtractSelection() = default;

void vtkCanopyExtractSelection::AddLocation(double x, double y, double z)
{
  this->Locations.insert(this->Locations.end(), {x, y, z});
  this->Modified();
}

void vtkCanopyExtractSelection::ClearLocations()
{
  this->Locations.clear();
  this->Modified();
}

void vtkCanopyExtractSelection::AddId(vtkIdType id)
{
  this->Ids.push_back(id);
  this->Modified();
}

void vtkCanopyExtractSelection::ClearIds()
{
  this->Ids.clear();
  this->Modified();
}

void vtkCanopyExtractSelection::SetFrustumPlanes(const double planes[24])
{
  if (!std::equal(planes, planes + 24, this->FrustumPlanes))
  {
    std::copy(planes, planes + 24, this->FrustumPlanes);
    this->Modified();
  }
}

void vtkCanopyExtractSelection::AddFrustumCorner(double x, double y, double z)
{
  this->FrustumCorners.insert(this->FrustumCorners.end(), {x, y, z});
  this->Modified();
}

void vtkCanopyExtractSelection::ClearFrustumCorners()
{
  this->FrustumCorners.clear();
  this->Modified();
}

int vtkCanopyExtractSelection::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkHyperTreeGrid");
    return 1;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkSelection");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

int vtkCanopyExtractSelection::RequestDataObject(vtkInformation*, vtkInformationVector**,
                                                 vtkInformationVector* outputVector)
{
  vtkInformation* info = outputVector->GetInformationObject(0);
  vtkDataObject* current = info->Get(vtkDataObject::DATA_OBJECT());
  const char* wanted = this->PreserveTopology ? "vtkHyperTreeGrid" : "vtkUnstructuredGrid";
  if (!current || !current->IsA(wanted))
  {
    vtkSmartPointer<vtkDataObject> output;
    if (this->PreserveTopology)
    {
      output = vtkSmartPointer<vtkHyperTreeGrid>::New();
    }
    else
    {
      output = vtkSmartPointer<vtkUnstructuredGrid>::New();
    }
    info->Set(vtkDataObject::DATA_OBJECT(), output);
  }
  return 1;
}

void vtkCanopyExtractSelection::ResetLastReport()
{
  this->LastOutside = this->LastMasked = this->LastOutOfRange = this->LastDuplicates = 0;
  this->LastVisited = 0;
  this->LastKeptTrees = 0;
  this->LastRecomputedNodes = 0;
  for (int a = 0; a < 3; ++a)
  {
    this->LastSelectedBounds[2 * a] = 1e300;
    this->LastSelectedBounds[2 * a + 1] = -1e300;
  }
}

int vtkCanopyExtractSelection::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                           vtkInformationVector* outputVector)
{
  vtkHyperTreeGrid* input = vtkHyperTreeGrid::GetData(inputVector[0], 0);
  vtkSelection* selectionInput =
      this->GetNumberOfInputConnections(1) > 0 ? vtkSelection::GetData(inputVector[1], 0) : nullptr;
  vtkDataObject* outputObject = vtkDataObject::GetData(outputVector, 0);
  this->ResetLastReport();
  if (!input)
  {
    vtkErrorMacro("input 0 must be a vtkHyperTreeGrid");
    return 0;
  }
  // What to select: the vtkSelection if given, else the convenience properties.
  const canopy::SelectionProperties properties{
      this->SelectionMode,  this->Locations,  this->Ids, this->ValueArrayName,
      this->ValueComponent, this->ValueRange, this->Box, this->FrustumPlanes,
      this->FrustumCorners, this->Invert};
  canopy::SelectionSpec spec;
  const std::string problem = canopy::readSelectionSpec(properties, selectionInput, input, spec);
  if (!problem.empty())
  {
    vtkErrorMacro(<< problem);
    return 0;
  }

  canopy::TreeProgress progress(this);
  const canopy::ProgressShare share{&progress};
  // An aborted execution leaves an empty output.
  const auto abandon = [outputObject]
  {
    outputObject->Initialize();
    return 1;
  };
  try
  {
    // Neither index tables nor masked-descendant flags: selections read only
    // the nodes they walk.
    const std::shared_ptr<const canopy::HyperTreeAccess> access =
        this->Internals->Topology.get(input, false, false);
    const canopy::HyperTreeAccess& grid = *access;
    canopy::CellSelection selection(grid, this->AllowMasked);
    selection.setProgress(share.part(0, 0.5));
    if (this->PreserveTopology)
    {
      // Trees whose mask is kept from the last execution are not marked again.
      this->Internals->MaskMemo.begin(grid, spec.fingerprint(grid, this->AllowMasked),
                                      spec.readsByCellNumber());
    }
    else
    {
      this->Internals->MaskMemo.clear();
    }
    const canopy::SelectionRegion region = canopy::regionOf(selection, spec);
    canopy::SelectionReport report;
    std::vector<canopy::SelectedNode> nodes =
        canopy::selectNodes(selection, spec, region, this->PreserveTopology, report);
    this->LastOutside = static_cast<vtkIdType>(report.outside);
    this->LastMasked = static_cast<vtkIdType>(report.masked);
    this->LastOutOfRange = static_cast<vtkIdType>(report.outOfRange);
    this->LastDuplicates = static_cast<vtkIdType>(report.duplicates);
    this->LastVisited = static_cast<vtkIdType>(report.visited);
    if (progress.stopped())
    {
      this->Internals->MaskMemo.clear();
      return abandon();
    }
    if (this->PreserveTopology)
    {
      // The same grid with a mask: no node list for the complement, no copy.
      std::size_t visited = 0;
      const canopy::SelectionMaskResult shown =
          canopy::selectionMaskOf(grid, spec, region, nodes, this->AllowMasked,
                                  this->Internals->MaskMemo, share.part(0.5, 1), visited);
      this->LastVisited += static_cast<vtkIdType>(visited);
      if (progress.stopped())
      {
        return abandon();
      }
      this->LastKeptTrees = static_cast<vtkIdType>(this->Internals->MaskMemo.keptTrees());
      this->LastRecomputedNodes =
          static_cast<vtkIdType>(this->Internals->MaskMemo.recomputedNodes());
      std::copy(shown.bounds.begin(), shown.bounds.end(), this->LastSelectedBounds);
      canopy::shareWithMask(input, vtkHyperTreeGrid::SafeDownCast(outputObject), shown.mask,
                            shown.pure);
    }
    else
    {
      if (spec.invert)
      {
        selection.setProgress(share.part(0.5, 1));
        nodes = selection.complement(nodes);
        if (progress.stopped())
        {
          return abandon();
        }
      }
      const std::array<double, 6> bounds = canopy::boundsOf(selection, nodes);
      std::copy(bounds.begin(), bounds.end(), this->LastSelectedBounds);
      canopy::writeSelectedCells(grid, selection, nodes, input,
                                 vtkUnstructuredGrid::SafeDownCast(outputObject));
    }
  }
  catch (const std::exception& e)
  {
    this->Internals->Topology.clear();
    this->Internals->MaskMemo.clear();
    vtkErrorMacro("cannot extract the selection: " << e.what());
    return 0;
  }
  return 1;
}

void vtkCanopyExtractSelection::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SelectionMode: " << this->SelectionMode << "\n"
     << indent << "Locations: " << this->Locations.size() / 3 << "\n"
     << indent << "Ids: " << this->Ids.size() << "\n"
     << indent << "ValueArrayName: " << this->ValueArrayName << "\n"
     << indent << "ValueComponent: " << this->ValueComponent << "\n"
     << indent << "ValueRange: " << this->ValueRange[0] << " " << this->ValueRange[1] << "\n"
     << indent << "Box: " << this->Box[0] << " " << this->Box[1] << " " << this->Box[2] << " "
     << this->Box[3] << " " << this->Box[4] << " " << this->Box[5] << "\n"
     << indent << "FrustumPlanes:";
  for (double v : this->FrustumPlanes)
  {
    os << " " << v;
  }
  os << "\n"
     << indent << "FrustumCorners: " << this->FrustumCorners.size() / 3 << "\n"
     << indent << "Invert: " << this->Invert << "\n"
     << indent << "AllowMasked: " << this->AllowMasked << "\n"
     << indent << "PreserveTopology: " << this->PreserveTopology << "\n"
     << indent << "LastOutside: " << this->LastOutside << "\n"
     << indent << "LastMasked: " << this->LastMasked << "\n"
     << indent << "LastOutOfRange: " << this->LastOutOfRange << "\n"
     << indent << "LastDuplicates: " << this->LastDuplicates << "\n"
     << indent << "LastVisited: " << this->LastVisited << "\n"
     << indent << "LastKeptTrees: " << this->LastKeptTrees << "\n"
     << indent << "LastRecomputedNodes: " << this->LastRecomputedNodes << "\n"
     << indent << "LastSelectedBounds: " << this->LastSelectedBounds[0] << " "
     << this->LastSelectedBounds[1] << " " << this->LastSelectedBounds[2] << " "
     << this->LastSelectedBounds[3] << " " << this->LastSelectedBounds[4] << " "
     << this->LastSelectedBounds[5] << "\n";
}
