#include <canopy/filters/vtkCanopyContour.h>

#include "ContourBuilder.h"
#include "ContourField.h"
#include "ContourGhosts.h"
#include "GatherFromAll.h"
#include "HyperTreeAccessCache.h"
#include "NodeRanges.h"
#include "TreeProgress.h"
#include "ViewDependentFilterInternals.h"
#include "ViewVolume.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkContourValues.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkMultiProcessController.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

vtkStandardNewMacro(vtkCanopyContour);

/// Ranges are kept while the access (the topology) is the kept one and the
/// field is the same array, unmodified, read at the same component. A
/// simulation's fields are wrapped anew at every build (GridBuilder), so a new
/// step computes them again; new contour values do not.
struct vtkCanopyContour::KeptRanges
{
  std::shared_ptr<const canopy::HyperTreeAccess> access;
  const vtkDataArray* array = nullptr;
  vtkMTimeType arrayTime = 0;
  int component = -1;
  int maximumLevel = -1;
  std::shared_ptr<const canopy::NodeRanges> ranges;
};

vtkCanopyContour::vtkCanopyContour()
    : ContourValues(vtkSmartPointer<vtkContourValues>::New()), Kept(std::make_unique<KeptRanges>())
{
  // The full contour unless a view is asked for.
  this->ViewDependent = false;
  this->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS,
                               vtkDataSetAttributes::SCALARS);
}

vtkCanopyContour::~vtkCanopyContour() = default;

void vtkCanopyContour::SetValue(int i, double value)
{
  this->ContourValues->SetValue(i, value);
}

double vtkCanopyContour::GetValue(int i)
{
  return this->ContourValues->GetValue(i);
}

double* vtkCanopyContour::GetValues()
{
  return this->ContourValues->GetValues();
}

void vtkCanopyContour::SetNumberOfContours(int number)
{
  this->ContourValues->SetNumberOfContours(number);
}

int vtkCanopyContour::GetNumberOfContours()
{
  return this->ContourValues->GetNumberOfContours();
}

void vtkCanopyContour::GenerateValues(int number, double range[2])
{
  this->ContourValues->GenerateValues(number, range);
}

void vtkCanopyContour::GenerateValues(int number, double first, double last)
{
  this->ContourValues->GenerateValues(number, first, last);
}

void vtkCanopyContour::AddInterpolatedField(const char* name)
{
  if (name && std::find(this->InterpolatedFields.begin(), this->InterpolatedFields.end(), name) ==
                  this->InterpolatedFields.end())
  {
    this->InterpolatedFields.emplace_back(name);
    this->Modified();
  }
}

void vtkCanopyContour::ClearInterpolatedFields()
{
  if (!this->InterpolatedFields.empty())
  {
    this->InterpolatedFields.clear();
    this->Modified();
  }
}

vtkMTimeType vtkCanopyContour::GetMTime()
{
  return std::max(this->Superclass::GetMTime(), this->ContourValues->GetMTime());
}

namespace
{

/// The contoured cell array: by name, or the active scalars.
vtkDataArray* contouredArray(vtkHyperTreeGrid* input, vtkInformation* selection)
{
  vtkCellData* cells = input->GetCellData();
  if (selection && selection->Has(vtkDataObject::FIELD_NAME()))
  {
    return cells->GetArray(selection->Get(vtkDataObject::FIELD_NAME()));
  }
  return cells->GetScalars();
}

/// Per point, the area-weighted mean of its triangles' normals (each the unit
/// vector against the gradient in its tetrahedron). A point whose triangles
/// all have no area (the contour through a dual vertex, or a flat
/// tetrahedron's, whose gradient means nothing) takes a neighbour's.
vtkSmartPointer<vtkDoubleArray> pointNormals(const canopy::ContourResult& result)
{
  auto normals = vtkSmartPointer<vtkDoubleArray>::New();
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(static_cast<vtkIdType>(result.points.size()));
  std::vector<std::array<double, 3>> sums(result.points.size(), {{0, 0, 0}});
  for (std::size_t c = 0; c + 2 < result.cells.size(); c += 3)
  {
    const auto& a = result.points[static_cast<std::size_t>(result.cells[c])];
    const auto& b = result.points[static_cast<std::size_t>(result.cells[c + 1])];
    const auto& d = result.points[static_cast<std::size_t>(result.cells[c + 2])];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double v[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    const double w[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                         u[0] * v[1] - u[1] * v[0]};
    const double area = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    const auto& n = result.cellNormals[c / 3];
    for (std::size_t k = 0; k < 3; ++k)
    {
      auto& sum = sums[static_cast<std::size_t>(result.cells[c + k])];
      for (std::size_t i = 0; i < 3; ++i)
      {
        sum[i] += area * n[i];
      }
    }
  }
  auto unset = [&](std::size_t p) { return sums[p][0] == 0 && sums[p][1] == 0 && sums[p][2] == 0; };
  // Neighbours' normals across triangles, a few rounds (a run of points without
  // area is short).
  for (int round = 0; round < 4; ++round)
  {
    bool changed = false;
    for (std::size_t c = 0; c + 2 < result.cells.size(); c += 3)
    {
      for (std::size_t k = 0; k < 3; ++k)
      {
        const std::size_t p = static_cast<std::size_t>(result.cells[c + k]);
        const std::size_t q = static_cast<std::size_t>(result.cells[c + (k + 1) % 3]);
        if (unset(p) && !unset(q))
        {
          sums[p] = sums[q];
          changed = true;
        }
      }
    }
    if (!changed)
    {
      break;
    }
  }
  for (std::size_t p = 0; p < result.points.size(); ++p)
  {
    const auto& sum = sums[p];
    const double length = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    const double scale = length > 0 ? 1 / length : 0;
    normals->SetTypedTuple(
        static_cast<vtkIdType>(p),
        std::array<double, 3>{{sum[0] * scale, sum[1] * scale, sum[2] * scale}}.data());
  }
  return normals;
}

/// Removes the triangles another rank draws, and the points only they use,
/// from `result` and from `normals` (per point, or null).
void dropForeignTriangles(canopy::ContourResult& result, vtkDoubleArray* normals)
{
  if (std::none_of(result.foreign.begin(), result.foreign.end(),
                   [](unsigned char f) { return f != 0; }))
  {
    return;
  }
  std::vector<vtkIdType> newId(result.points.size(), -1);
  std::vector<vtkIdType> cells;
  std::vector<std::array<double, 3>> cellNormals;
  for (std::size_t t = 0; t < result.foreign.size(); ++t)
  {
    if (result.foreign[t])
    {
      continue;
    }
    for (std::size_t k = 0; k < 3; ++k)
    {
      const vtkIdType p = result.cells[3 * t + k];
      vtkIdType& id = newId[static_cast<std::size_t>(p)];
      if (id < 0)
      {
        id = 0; // numbered below, in the old order
      }
      cells.push_back(p);
    }
    cellNormals.push_back(result.cellNormals[t]);
  }
  vtkIdType next = 0;
  for (std::size_t p = 0; p < newId.size(); ++p)
  {
    if (newId[p] < 0)
    {
      continue;
    }
    newId[p] = next;
    const std::size_t to = static_cast<std::size_t>(next++);
    result.points[to] = result.points[p];
    result.contours[to] = result.contours[p];
    result.leaves[to] = result.leaves[p];
    result.weights[to] = result.weights[p];
    if (normals)
    {
      double n[3];
      normals->GetTypedTuple(static_cast<vtkIdType>(p), n);
      normals->SetTypedTuple(static_cast<vtkIdType>(to), n);
    }
  }
  const std::size_t kept = static_cast<std::size_t>(next);
  result.points.resize(kept);
  result.contours.resize(kept);
  result.leaves.resize(kept);
  result.weights.resize(kept);
  if (normals)
  {
    normals->SetNumberOfTuples(next);
  }
  for (vtkIdType& p : cells)
  {
    p = newId[static_cast<std::size_t>(p)];
  }
  result.cells.swap(cells);
  result.cellNormals.swap(cellNormals);
  result.foreign.assign(result.cellNormals.size(), 0);
}

} // namespace

int vtkCanopyContour::ProcessTrees(vtkHyperTreeGrid* input, vtkDataObject* outputObject)
{
  this->LastVisited = 0;
  this->LastPruned = 0;
  this->LastCulled = 0;
  this->LastRangesKept = false;
  this->LastDualCells = 0;
  this->LastGhostsReceived = 0;
  this->LastGhostBytesReceived = 0;
  this->LastGhostSeconds = 0;
  vtkPolyData* output = vtkPolyData::SafeDownCast(outputObject);
  if (!input || !output)
  {
    vtkErrorMacro("the input must be a vtkHyperTreeGrid");
    return 0;
  }
  output->Initialize();
  // On several processes the exchange of border leaves is collective: every
  // rank takes part, whatever its own checks found (an empty share), and
  // fails after it, so that no rank waits for one that gave up.
  vtkMultiProcessController* controller = this->Controller;
  const bool exchange = controller && controller->GetNumberOfProcesses() > 1;
  std::string problem;
  canopy::CameraParameters camera;
  const bool viewUsable = this->Internals->CurrentView(camera); // says why when not
  vtkDataArray* array = contouredArray(input, this->GetInputArrayInformation(0));
  std::vector<vtkDataArray*> interpolated;
  if (!array)
  {
    problem = "no cell field to contour: select one with SetInputArrayToProcess";
  }
  else if (this->ArrayComponent < 0 || this->ArrayComponent >= array->GetNumberOfComponents())
  {
    problem = "component " + std::to_string(this->ArrayComponent) + " of " +
              (array->GetName() ? array->GetName() : "the field") + ", which has " +
              std::to_string(array->GetNumberOfComponents());
  }
  for (const std::string& name : this->InterpolatedFields)
  {
    vtkDataArray* other = input->GetCellData()->GetArray(name.c_str());
    if (!other && problem.empty())
    {
      problem = "no cell field " + name + " to interpolate";
    }
    interpolated.push_back(other);
  }
  const std::vector<double> values(this->ContourValues->GetValues(),
                                   this->ContourValues->GetValues() +
                                       this->ContourValues->GetNumberOfContours());

  canopy::ContourResult result;
  std::shared_ptr<const canopy::HyperTreeAccess> access;
  try
  {
    // Explicit global indices read once into tables (kept with the access
    // while the topology holds): the traversal asks for one per node, and the
    // pruning pass for every node. No masked-descendant flags.
    access = this->Internals->Topology->get(input, true, false);
    auto tooShort = [&](vtkDataArray* a)
    { return a && a->GetNumberOfTuples() < access->numberOfCells(); };
    if (problem.empty() &&
        (tooShort(array) || std::any_of(interpolated.begin(), interpolated.end(), tooShort)))
    {
      problem = "a field has fewer values than the grid has cells";
    }
  }
  catch (const std::exception& e)
  {
    this->Internals->Topology->clear();
    problem = std::string("cannot contour: ") + e.what();
  }
  const int maximumLevel = std::max(this->MaximumLevel, -1);
  canopy::ViewOptions options;
  vtkInternals::ViewResources resources;
  try
  {
    if (problem.empty() && viewUsable)
    {
      resources = this->Internals->ViewOptionsFor(camera, input, options);
    }
  }
  catch (const std::exception& e)
  {
    problem = std::string("cannot contour: ") + e.what();
  }
  const bool contouring = problem.empty() && viewUsable && !values.empty();
  canopy::ContourField field =
      contouring ? canopy::ContourField(array, this->ArrayComponent) : canopy::ContourField();
  std::unique_ptr<canopy::ContourGhosts> ghosts;
  const auto exchangeStart = std::chrono::steady_clock::now();
  if (exchange)
  {
    std::vector<double> mine;
    std::vector<int> components;
    try
    {
      if (contouring)
      {
        mine = canopy::ContourGhosts::collect(*access, field, interpolated, maximumLevel, options);
        for (vtkDataArray* other : interpolated)
        {
          components.push_back(other->GetNumberOfComponents());
        }
      }
    }
    catch (const std::exception& e)
    {
      mine.clear();
      problem = std::string("cannot collect the border leaves: ") + e.what();
    }
    std::vector<vtkIdType> counts;
    const std::vector<double> all = canopy::gatherFromAll(controller, mine, counts);
    try
    {
      if (contouring && problem.empty())
      {
        std::vector<std::vector<double>> records(counts.size());
        std::size_t at = 0;
        for (std::size_t r = 0; r < counts.size(); ++r)
        {
          records[r].assign(all.begin() + static_cast<std::ptrdiff_t>(at),
                            all.begin() + static_cast<std::ptrdiff_t>(at + counts[r]));
          at += static_cast<std::size_t>(counts[r]);
        }
        ghosts = std::make_unique<canopy::ContourGhosts>(
            *access, records, controller->GetLocalProcessId(), components);
        field.setGhosts(access->numberOfCells(), ghosts->values().data());
        this->LastGhostsReceived = static_cast<vtkIdType>(ghosts->size());
        this->LastGhostBytesReceived = static_cast<vtkIdType>(ghosts->bytesReceived());
      }
    }
    catch (const std::exception& e)
    {
      problem = std::string("cannot use the other ranks' border leaves: ") + e.what();
    }
  }
  this->LastGhostSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - exchangeStart).count();
  if (!problem.empty())
  {
    vtkErrorMacro(<< problem);
    return 0;
  }
  if (!viewUsable)
  {
    return 0; // said why
  }
  if (values.empty())
  {
    return 1;
  }

  try
  {
    canopy::ContourBuilder builder(*access, field, values, maximumLevel, options);
    builder.setGhosts(ghosts.get());
    canopy::TreeProgress progress(this);
    const canopy::ProgressShare share{&progress};
    std::shared_ptr<const canopy::NodeRanges> ranges;
    if (this->Pruning)
    {
      KeptRanges& kept = *this->Kept;
      // The ranges are the forest's without the view (ContourBuilder::ranges):
      // kept across camera moves. With other ranks' leaves, the boundary
      // gradients along the rank borders depend on theirs: not kept.
      this->LastRangesKept = !ghosts && kept.ranges && kept.access == access &&
                             kept.array == array && kept.arrayTime == array->GetMTime() &&
                             kept.component == this->ArrayComponent &&
                             kept.maximumLevel == maximumLevel;
      if (!this->LastRangesKept)
      {
        kept = KeptRanges{};
        ranges = builder.ranges(share.part(0, 0.3));
        if (!share.stopped() && !ghosts)
        {
          kept = {access, array, array->GetMTime(), this->ArrayComponent, maximumLevel, ranges};
        }
      }
      ranges = kept.ranges ? kept.ranges : ranges;
    }
    const bool done = builder.run(this->Pruning ? share.part(0.3, 1) : share, ranges.get());
    this->LastVisited = static_cast<vtkIdType>(builder.visited());
    this->LastPruned = static_cast<vtkIdType>(builder.pruned());
    this->LastCulled = static_cast<vtkIdType>(builder.culled());
    this->LastDualCells = static_cast<vtkIdType>(builder.dualCells());
    if (!done)
    {
      return 1; // aborted: the output stays empty
    }
    result = builder.merge();
  }
  catch (const std::exception& e)
  {
    this->Internals->Topology->clear();
    *this->Kept = KeptRanges{};
    vtkErrorMacro("cannot contour: " << e.what());
    return 0;
  }

  // Normals over every triangle made here, then the other ranks' triangles
  // (made for the normals of the points on the border) left out.
  vtkSmartPointer<vtkDoubleArray> normals;
  if (this->ComputeNormals && result.verticesPerCell == 3)
  {
    normals = pointNormals(result);
  }
  dropForeignTriangles(result, normals);

  const vtkIdType points = static_cast<vtkIdType>(result.points.size());
  vtkNew<vtkDoubleArray> coordinates;
  coordinates->SetNumberOfComponents(3);
  coordinates->SetNumberOfTuples(points);
  double* xyz = coordinates->GetPointer(0);
  for (const auto& x : result.points)
  {
    xyz = std::copy(x.begin(), x.end(), xyz);
  }
  vtkNew<vtkPoints> outputPoints;
  outputPoints->SetData(coordinates);
  output->SetPoints(outputPoints);

  const vtkIdType per = result.verticesPerCell;
  const vtkIdType cells = static_cast<vtkIdType>(result.cells.size()) / per;
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfTuples(cells + 1);
  for (vtkIdType c = 0; c <= cells; ++c)
  {
    offsets->SetValue(c, c * per);
  }
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfTuples(static_cast<vtkIdType>(result.cells.size()));
  std::copy(result.cells.begin(), result.cells.end(), connectivity->GetPointer(0));
  vtkNew<vtkCellArray> cellArray;
  cellArray->SetData(offsets, connectivity);
  if (per == 2)
  {
    output->SetLines(cellArray);
  }
  else
  {
    output->SetPolys(cellArray);
  }

  vtkPointData* pointData = output->GetPointData();
  if (this->ComputeScalars)
  {
    vtkNew<vtkDoubleArray> scalars;
    scalars->SetName(array->GetName() ? array->GetName() : "ContourValue");
    scalars->SetNumberOfTuples(points);
    for (vtkIdType p = 0; p < points; ++p)
    {
      scalars->SetValue(p, values[result.contours[static_cast<std::size_t>(p)]]);
    }
    pointData->SetScalars(scalars);
  }
  if (this->ComputeNormals && per == 3)
  {
    pointData->SetNormals(normals);
  }
  for (vtkDataArray* const& other : interpolated)
  {
    vtkNew<vtkDoubleArray> out;
    out->SetName(other->GetName());
    const int components = other->GetNumberOfComponents();
    out->SetNumberOfComponents(components);
    out->SetNumberOfTuples(points);
    // A leaf's value, or a centroid's: its leaves' weighted sum.
    const std::size_t which = static_cast<std::size_t>(&other - interpolated.data());
    const vtkIdType local = access->numberOfCells();
    auto leafValue = [&](vtkIdType leaf, int c)
    {
      return leaf < local ? other->GetComponent(leaf, c)
                          : ghosts->interpolated(which, leaf - local, c);
    };
    auto valueAt = [&](vtkIdType leaf, int c)
    {
      if (leaf >= 0)
      {
        return leafValue(leaf, c);
      }
      const auto& centroid = result.centroids[static_cast<std::size_t>(-leaf - 1)];
      double sum = 0;
      for (std::size_t j = 0; j < static_cast<std::size_t>(centroid.count); ++j)
      {
        sum += centroid.weights[j] * leafValue(centroid.leaves[j], c);
      }
      return sum;
    };
    for (vtkIdType p = 0; p < points; ++p)
    {
      const std::size_t up = static_cast<std::size_t>(p);
      const double t = result.weights[up];
      for (int c = 0; c < components; ++c)
      {
        out->SetTypedComponent(p, c,
                               (1 - t) * valueAt(result.leaves[up][0], c) +
                                   t * valueAt(result.leaves[up][1], c));
      }
    }
    pointData->AddArray(out);
  }
  return 1;
}

void vtkCanopyContour::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  this->ContourValues->PrintSelf(os, indent.GetNextIndent());
  os << indent << "ArrayComponent: " << this->ArrayComponent << "\n";
  os << indent << "MaximumLevel: " << this->MaximumLevel << "\n";
  os << indent << "ComputeScalars: " << this->ComputeScalars << "\n";
  os << indent << "ComputeNormals: " << this->ComputeNormals << "\n";
  os << indent << "Pruning: " << this->Pruning << "\n";
  os << indent << "InterpolatedFields:";
  for (const std::string& name : this->InterpolatedFields)
  {
    os << " " << name;
  }
  os << "\n" << indent << "LastVisited: " << this->LastVisited << "\n";
  os << indent << "LastPruned: " << this->LastPruned << "\n";
  os << indent << "LastCulled: " << this->LastCulled << "\n";
  os << indent << "LastRangesKept: " << this->LastRangesKept << "\n";
  os << indent << "LastDualCells: " << this->LastDualCells << "\n";
  os << indent << "LastGhostsReceived: " << this->LastGhostsReceived << "\n";
  os << indent << "LastGhostBytesReceived: " << this->LastGhostBytesReceived << "\n";
  os << indent << "LastGhostSeconds: " << this->LastGhostSeconds << "\n";
}
