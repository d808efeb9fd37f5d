#include "vtkCanopyExtractSelection.h"

#include "ByteHash.h"
#include "CellSelection.h"
#include "Frustum.h"
#include "GatherTuples.h"
#include "HyperTreeAccess.h"
#include "HyperTreeAccessCache.h"
#include "PointMerger.h"
#include "PureMask.h"
#include "SelectionMask.h"
#include "SelectionMaskMemo.h"
#include "TreeProgress.h"

#include <vtkBitArray.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPoints.h>
#include <vtkSelection.h>
#include <vtkSelectionNode.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <unordered_set>

vtkStandardNewMacro(vtkCanopyExtractSelection);

vtkCanopyExtractSelection::vtkCanopyExtractSelection()
    : Topology(std::make_unique<canopy::HyperTreeAccessCache>()),
      MaskMemo(std::make_unique<canopy::SelectionMaskMemo>())
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

namespace
{

/// The input's structure, trees, cell and field data, with another mask. Not
/// ShallowCopy: in VTK 9.2 it also asks the input for its "pure mask", a cursor
/// walk over every node whenever the input has a mask (a chained selection's
/// does), which cost more than the selection itself.
void shareWithMask(vtkHyperTreeGrid* input, vtkHyperTreeGrid* output, vtkBitArray* mask,
                   vtkBitArray* pure)
{
  output->Initialize();
  output->CopyEmptyStructure(input);
  vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
  input->InitializeTreeIterator(it);
  vtkIdType index = 0;
  while (vtkHyperTree* tree = it.GetNextTree(index))
  {
    output->SetTree(index, tree); // the same tree, shared
  }
  output->GetCellData()->ShallowCopy(input->GetCellData());
  output->GetFieldData()->ShallowCopy(input->GetFieldData());
  output->SetMask(mask);
  if (!output->GetHasInterface())
  {
    canopy::setPureMask(output, pure); // what ShallowCopy and ParaView would ask VTK to compute
  }
}

/// Lines (1D), quads (2D) or hexahedra (3D) with merged points, the input's
/// fields, ids and levels.
void toUnstructured(const canopy::HyperTreeAccess& grid, const canopy::CellSelection& selection,
                    const std::vector<canopy::SelectedNode>& nodes, vtkHyperTreeGrid* input,
                    vtkUnstructuredGrid* output)
{
  // Points merged by exact value, ids in order of first use; arrays sized for
  // the worst case once (growing them costs a copy per doubling).
  const int dimension = grid.dimension();
  const vtkIdType perCell = dimension == 1 ? 2 : dimension == 2 ? 4 : 8;
  const auto count = static_cast<vtkIdType>(nodes.size());
  vtkNew<vtkDoubleArray> coordinates;
  coordinates->SetNumberOfComponents(3);
  coordinates->SetNumberOfTuples(perCell * count);
  canopy::PointMerger merger(coordinates->GetPointer(0), static_cast<std::size_t>(perCell * count));
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfTuples(count + 1);
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfTuples(perCell * count);
  vtkIdType* offset = offsets->GetPointer(0);
  vtkIdType* ids = connectivity->GetPointer(0);
  for (vtkIdType i = 0; i < count; ++i)
  {
    const canopy::SelectedNode& n = nodes[static_cast<std::size_t>(i)];
    offset[i] = perCell * i;
    canopy::Vec3 lo;
    canopy::Vec3 hi;
    selection.bounds(n, lo, hi);
    if (dimension == 1)
    {
      for (const canopy::Vec3& c : canopy::segmentEnds(lo, hi, grid.activeAxes()[0]))
      {
        *ids++ = merger.id(c);
      }
    }
    else if (dimension == 3)
    {
      // VTK_HEXAHEDRON: the bottom face (z = lo), then the top one, both
      // counter-clockwise seen from +z.
      for (int k = 0; k < 2; ++k)
      {
        canopy::Vec3 layer = lo;
        layer[2] = k ? hi[2] : lo[2];
        for (const canopy::Vec3& c : canopy::rectangleCorners(layer, hi, 0, 1))
        {
          *ids++ = merger.id(c);
        }
      }
    }
    else
    {
      for (const canopy::Vec3& c :
           canopy::rectangleCorners(lo, hi, grid.activeAxes()[0], grid.activeAxes()[1]))
      {
        *ids++ = merger.id(c);
      }
    }
  }
  offset[count] = perCell * count;
  coordinates->SetNumberOfTuples(merger.count()); // shrinks in place
  vtkNew<vtkPoints> points;
  points->SetData(coordinates);
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);
  output->SetPoints(points);
  output->SetCells(dimension == 1 ? VTK_LINE : dimension == 2 ? VTK_QUAD : VTK_HEXAHEDRON, cells);
  std::vector<vtkIdType> globals(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i)
  {
    globals[i] = nodes[i].global;
  }
  vtkCellData* in = input->GetCellData();
  for (int a = 0; a < in->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* source = in->GetArray(a);
    if (source && source->GetName())
    {
      output->GetCellData()->AddArray(canopy::gatherTuples(source, globals.data(), count));
    }
  }
  vtkNew<vtkIdTypeArray> original;
  original->SetName("OriginalCellId");
  original->SetNumberOfTuples(count);
  vtkNew<vtkUnsignedCharArray> level;
  level->SetName("Level");
  level->SetNumberOfTuples(count);
  for (vtkIdType i = 0; i < count; ++i)
  {
    original->SetValue(i, globals[static_cast<std::size_t>(i)]);
    level->SetValue(i, static_cast<unsigned char>(nodes[static_cast<std::size_t>(i)].level));
  }
  output->GetCellData()->AddArray(original);
  output->GetCellData()->AddArray(level);
}

/// What a masked selection depends on beside the trees (SelectionMaskMemo):
/// the grid's kind, the mode and its parameters, and for a value range the
/// values' array and its modified time (VTK gives each change a later time).
std::uint64_t selectionFingerprint(const canopy::HyperTreeAccess& grid, int mode, bool invert,
                                   bool allowMasked, const std::vector<canopy::Vec3>& points,
                                   const std::vector<vtkIdType>& ids, vtkDataArray* values,
                                   int component, const double range[2],
                                   const std::array<double, 6>& box, const canopy::Frustum& frustum)
{
  using canopy::hashBytes;
  using canopy::hashCombine;
  std::uint64_t h = hashCombine(0xCA40B1ull, static_cast<std::uint64_t>(mode));
  h = hashCombine(h, (invert ? 1u : 0u) | (allowMasked ? 2u : 0u));
  h = hashCombine(h, static_cast<std::uint64_t>(grid.dimension() * 64 + grid.childrenPerNode()));
  switch (mode)
  {
  case vtkCanopyExtractSelection::LOCATIONS:
    return hashBytes(points.data(), points.size() * sizeof(canopy::Vec3), h);
  case vtkCanopyExtractSelection::IDS:
    return hashBytes(ids.data(), ids.size() * sizeof(vtkIdType), h);
  case vtkCanopyExtractSelection::VALUE_RANGE:
    h = hashCombine(h, reinterpret_cast<std::uintptr_t>(values));
    h = hashCombine(h, values ? values->GetMTime() : 0);
    h = hashCombine(h, static_cast<std::uint64_t>(component + 1));
    return hashBytes(range, 2 * sizeof(double), h);
  case vtkCanopyExtractSelection::BOX:
    return hashBytes(box.data(), sizeof(box), h);
  default:
    return hashBytes(frustum.planes.data(), sizeof(frustum.planes), h);
  }
}

} // namespace

int vtkCanopyExtractSelection::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                           vtkInformationVector* outputVector)
{
  vtkHyperTreeGrid* input = vtkHyperTreeGrid::GetData(inputVector[0], 0);
  vtkSelection* selectionInput =
      this->GetNumberOfInputConnections(1) > 0 ? vtkSelection::GetData(inputVector[1], 0) : nullptr;
  vtkDataObject* outputObject = vtkDataObject::GetData(outputVector, 0);
  this->LastOutside = this->LastMasked = this->LastOutOfRange = this->LastDuplicates = 0;
  this->LastVisited = 0;
  this->LastKeptTrees = 0;
  this->LastRecomputedNodes = 0;
  for (int a = 0; a < 3; ++a)
  {
    this->LastSelectedBounds[2 * a] = 1e300;
    this->LastSelectedBounds[2 * a + 1] = -1e300;
  }
  if (!input)
  {
    vtkErrorMacro("input 0 must be a vtkHyperTreeGrid");
    return 0;
  }

  // What to select: the vtkSelection if given, else the convenience properties.
  int mode = this->SelectionMode;
  std::vector<canopy::Vec3> points;
  std::vector<vtkIdType> ids;
  std::string field = this->ValueArrayName;
  int component = this->ValueComponent;
  double range[2] = {this->ValueRange[0], this->ValueRange[1]};
  canopy::Frustum frustum;
  std::string frustumProblem;
  if (selectionInput)
  {
    vtkSelectionNode* node =
        selectionInput->GetNumberOfNodes() > 0 ? selectionInput->GetNode(0) : nullptr;
    vtkDataArray* list = node ? vtkArrayDownCast<vtkDataArray>(node->GetSelectionList()) : nullptr;
    if (!node)
    {
      mode = IDS; // an empty selection selects nothing
    }
    else if (!list)
    {
      vtkErrorMacro("the selection node has no numeric selection list");
      return 0;
    }
    else if (node->GetContentType() == vtkSelectionNode::LOCATIONS)
    {
      mode = LOCATIONS;
      if (list->GetNumberOfComponents() != 3)
      {
        vtkErrorMacro("a LOCATIONS selection needs 3-component points, got "
                      << list->GetNumberOfComponents());
        return 0;
      }
      for (vtkIdType i = 0; i < list->GetNumberOfTuples(); ++i)
      {
        points.push_back(
            {{list->GetComponent(i, 0), list->GetComponent(i, 1), list->GetComponent(i, 2)}});
      }
    }
    else if (node->GetContentType() == vtkSelectionNode::GLOBALIDS ||
             node->GetContentType() == vtkSelectionNode::INDICES)
    {
      mode = IDS;
      for (vtkIdType i = 0; i < list->GetNumberOfTuples(); ++i)
      {
        ids.push_back(static_cast<vtkIdType>(list->GetComponent(i, 0)));
      }
    }
    else if (node->GetContentType() == vtkSelectionNode::THRESHOLDS)
    {
      mode = VALUE_RANGE;
      if (list->GetNumberOfValues() < 2 || !list->GetName())
      {
        vtkErrorMacro("a THRESHOLDS selection needs a named list with a [low, high] pair");
        return 0;
      }
      field = list->GetName();
      range[0] = list->GetComponent(0, 0);
      range[1] =
          list->GetNumberOfComponents() > 1 ? list->GetComponent(0, 1) : list->GetComponent(1, 0);
      component = node->GetProperties()->Has(vtkSelectionNode::COMPONENT_NUMBER())
                      ? node->GetProperties()->Get(vtkSelectionNode::COMPONENT_NUMBER())
                      : 0;
    }
    else if (node->GetContentType() == vtkSelectionNode::FRUSTUM)
    {
      mode = FRUSTUM;
      // As vtkFrustumSelector reads it: 32 values, x y z w per corner, w ignored.
      if (list->GetNumberOfValues() != 32)
      {
        vtkErrorMacro("a FRUSTUM selection needs 8 corners (x, y, z, w: 32 values), got "
                      << list->GetNumberOfValues() << " values");
        return 0;
      }
      std::array<canopy::Vec3, 8> corners;
      for (vtkIdType c = 0; c < 8; ++c)
      {
        for (int a = 0; a < 3; ++a)
        {
          const vtkIdType v = 4 * c + a;
          corners[static_cast<std::size_t>(c)][static_cast<std::size_t>(a)] =
              list->GetComponent(v / list->GetNumberOfComponents(),
                                 static_cast<int>(v % list->GetNumberOfComponents()));
        }
      }
      frustumProblem = canopy::Frustum::fromCorners(corners, frustum);
    }
    else
    {
      vtkErrorMacro(
          "selection content type "
          << vtkSelectionNode::GetContentTypeAsString(node->GetContentType())
          << " is not supported (LOCATIONS, GLOBALIDS, INDICES, THRESHOLDS, FRUSTUM are)");
      return 0;
    }
  }
  else if (mode == LOCATIONS)
  {
    for (std::size_t i = 0; i + 2 < this->Locations.size(); i += 3)
    {
      points.push_back({{this->Locations[i], this->Locations[i + 1], this->Locations[i + 2]}});
    }
  }
  else if (mode == IDS)
  {
    ids = this->Ids;
  }
  else if (mode == FRUSTUM && this->FrustumCorners.empty())
  {
    for (std::size_t p = 0; p < 6; ++p)
    {
      std::copy(this->FrustumPlanes + 4 * p, this->FrustumPlanes + 4 * p + 4,
                frustum.planes[p].begin());
    }
    frustumProblem = frustum.problem();
  }
  else if (mode == FRUSTUM && this->FrustumCorners.size() == 24)
  {
    std::array<canopy::Vec3, 8> corners;
    for (std::size_t c = 0; c < 8; ++c)
    {
      std::copy(this->FrustumCorners.begin() + static_cast<std::ptrdiff_t>(3 * c),
                this->FrustumCorners.begin() + static_cast<std::ptrdiff_t>(3 * c + 3),
                corners[c].begin());
    }
    frustumProblem = canopy::Frustum::fromCorners(corners, frustum);
  }
  else if (mode == FRUSTUM)
  {
    frustumProblem = "a frustum needs 8 corners or none (then its 6 planes), got " +
                     std::to_string(this->FrustumCorners.size() / 3) + " corners";
  }
  if (!frustumProblem.empty())
  {
    vtkErrorMacro("invalid frustum: " << frustumProblem);
    return 0;
  }
  const std::array<double, 6> box{
      {this->Box[0], this->Box[1], this->Box[2], this->Box[3], this->Box[4], this->Box[5]}};
  for (int a = 0; mode == BOX && a < 3; ++a)
  {
    if (!(box[2 * a] <= box[2 * a + 1]))
    {
      vtkErrorMacro("box [" << box[2 * a] << ", " << box[2 * a + 1] << "] along axis "
                            << "xyz"[a] << " needs min <= max (and no NaN)");
      return 0;
    }
  }

  for (std::size_t i = 0; i < points.size(); ++i)
  {
    if (!std::isfinite(points[i][0]) || !std::isfinite(points[i][1]) ||
        !std::isfinite(points[i][2]))
    {
      vtkErrorMacro("location " << i << " is not finite: (" << points[i][0] << ", " << points[i][1]
                                << ", " << points[i][2] << ")");
      return 0;
    }
  }
  vtkDataArray* values = nullptr;
  if (mode == VALUE_RANGE)
  {
    values = input->GetCellData()->GetArray(field.c_str());
    if (!values)
    {
      vtkErrorMacro("no cell field named '" << field << "' in the input");
      return 0;
    }
    if (component >= values->GetNumberOfComponents() || component < -1)
    {
      vtkErrorMacro("field '" << field << "' has " << values->GetNumberOfComponents()
                              << " components; component " << component << " does not exist");
      return 0;
    }
  }

  // A selection node's INVERSE key inverts once more (as in VTK).
  bool invert = this->Invert;
  if (selectionInput && selectionInput->GetNumberOfNodes() > 0)
  {
    vtkInformation* properties = selectionInput->GetNode(0)->GetProperties();
    if (properties->Has(vtkSelectionNode::INVERSE()) &&
        properties->Get(vtkSelectionNode::INVERSE()) != 0)
    {
      invert = !invert;
    }
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
        this->Topology->get(input, false, false);
    const canopy::HyperTreeAccess& grid = *access;
    canopy::CellSelection selection(grid, this->AllowMasked);
    selection.setProgress(share.part(0, 0.5));
    if (this->PreserveTopology)
    {
      // Trees whose mask is kept from the last execution are not marked again.
      this->MaskMemo->begin(grid,
                            selectionFingerprint(grid, mode, invert, this->AllowMasked, points, ids,
                                                 values, component, range, box, frustum),
                            mode == IDS || mode == VALUE_RANGE);
    }
    else
    {
      this->MaskMemo->clear();
    }
    const bool byRegion = mode == BOX || mode == FRUSTUM;
    canopy::SelectionRegion region;
    if (byRegion)
    {
      region = mode == BOX ? selection.boxRegion(box) : selection.frustumRegion(frustum);
    }
    canopy::SelectionReport report;
    std::vector<canopy::SelectedNode> nodes;
    if (mode == LOCATIONS)
    {
      nodes = selection.byLocation(points, report);
    }
    else if (mode == IDS)
    {
      nodes = selection.byId(ids, report);
    }
    else if (mode == VALUE_RANGE && !this->PreserveTopology)
    {
      nodes = selection.byValue(values, component, range[0], range[1]);
    }
    else if (byRegion && !this->PreserveTopology)
    {
      nodes = selection.byRegion(region, report);
    }
    this->LastOutside = static_cast<vtkIdType>(report.outside);
    this->LastMasked = static_cast<vtkIdType>(report.masked);
    this->LastOutOfRange = static_cast<vtkIdType>(report.outOfRange);
    this->LastDuplicates = static_cast<vtkIdType>(report.duplicates);
    this->LastVisited = static_cast<vtkIdType>(report.visited);
    if (progress.stopped())
    {
      this->MaskMemo->clear();
      return abandon();
    }
    if (this->PreserveTopology)
    {
      // The same grid with a mask: no node list for the complement, no copy.
      // A value range, a box or a frustum is tested in the mask's own pass: no
      // node list.
      std::size_t visited = 0;
      const canopy::ProgressShare maskShare = share.part(0.5, 1);
      const canopy::SelectionMaskResult shown =
          mode == VALUE_RANGE
              ? canopy::selectionMaskOfLeaves(
                    grid,
                    canopy::CellSelection::valueInRange(values, component, range[0], range[1]),
                    invert, this->AllowMasked, *this->MaskMemo, maskShare)
          : byRegion ? canopy::selectionMaskOfRegion(grid, region, invert, this->AllowMasked,
                                                     *this->MaskMemo, visited, maskShare)
                     : canopy::selectionMask(grid, nodes, invert, this->AllowMasked,
                                             *this->MaskMemo, maskShare);
      this->LastVisited += static_cast<vtkIdType>(visited);
      if (progress.stopped())
      {
        return abandon();
      }
      this->LastKeptTrees = static_cast<vtkIdType>(this->MaskMemo->keptTrees());
      this->LastRecomputedNodes = static_cast<vtkIdType>(this->MaskMemo->recomputedNodes());
      std::copy(shown.bounds.begin(), shown.bounds.end(), this->LastSelectedBounds);
      shareWithMask(input, vtkHyperTreeGrid::SafeDownCast(outputObject), shown.mask, shown.pure);
    }
    else
    {
      if (invert)
      {
        selection.setProgress(share.part(0.5, 1));
        nodes = selection.complement(nodes);
        if (progress.stopped())
        {
          return abandon();
        }
      }
      for (const canopy::SelectedNode& n : nodes)
      {
        canopy::Vec3 lo;
        canopy::Vec3 hi;
        selection.bounds(n, lo, hi);
        for (int a = 0; a < 3; ++a)
        {
          this->LastSelectedBounds[2 * a] = std::min(this->LastSelectedBounds[2 * a], lo[a]);
          this->LastSelectedBounds[2 * a + 1] =
              std::max(this->LastSelectedBounds[2 * a + 1], hi[a]);
        }
      }
      auto* output = vtkUnstructuredGrid::SafeDownCast(outputObject);
      output->Initialize();
      toUnstructured(grid, selection, nodes, input, output);
    }
  }
  catch (const std::exception& e)
  {
    this->Topology->clear();
    this->MaskMemo->clear();
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
