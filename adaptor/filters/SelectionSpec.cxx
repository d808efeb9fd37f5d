#include "SelectionSpec.h"

#include "ByteHash.h"
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkInformation.h>
#include <vtkSelection.h>
#include <vtkSelectionNode.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace canopy
{

namespace
{

using Modes = vtkCanopyExtractSelection::SelectionModes;

/// The first node of a connected vtkSelection (none: an empty selection, which
/// selects nothing).
std::string readSelectionNode(vtkSelection* selection, SelectionSpec& spec)
{
  vtkSelectionNode* node = selection->GetNumberOfNodes() > 0 ? selection->GetNode(0) : nullptr;
  vtkDataArray* list = node ? vtkArrayDownCast<vtkDataArray>(node->GetSelectionList()) : nullptr;
  std::ostringstream problem;
  if (!node)
  {
    spec.mode = Modes::IDS;
  }
  else if (!list)
  {
    problem << "the selection node has no numeric selection list";
  }
  else if (node->GetContentType() == vtkSelectionNode::LOCATIONS)
  {
    spec.mode = Modes::LOCATIONS;
    if (list->GetNumberOfComponents() != 3)
    {
      problem << "a LOCATIONS selection needs 3-component points, got "
              << list->GetNumberOfComponents();
      return problem.str();
    }
    for (vtkIdType i = 0; i < list->GetNumberOfTuples(); ++i)
    {
      spec.points.push_back(
          {{list->GetComponent(i, 0), list->GetComponent(i, 1), list->GetComponent(i, 2)}});
    }
  }
  else if (node->GetContentType() == vtkSelectionNode::GLOBALIDS ||
           node->GetContentType() == vtkSelectionNode::INDICES)
  {
    spec.mode = Modes::IDS;
    for (vtkIdType i = 0; i < list->GetNumberOfTuples(); ++i)
    {
      spec.ids.push_back(static_cast<vtkIdType>(list->GetComponent(i, 0)));
    }
  }
  else if (node->GetContentType() == vtkSelectionNode::THRESHOLDS)
  {
    spec.mode = Modes::VALUE_RANGE;
    if (list->GetNumberOfValues() < 2 || !list->GetName())
    {
      problem << "a THRESHOLDS selection needs a named list with a [low, high] pair";
      return problem.str();
    }
    spec.field = list->GetName();
    spec.range[0] = list->GetComponent(0, 0);
    spec.range[1] =
        list->GetNumberOfComponents() > 1 ? list->GetComponent(0, 1) : list->GetComponent(1, 0);
    spec.component = node->GetProperties()->Has(vtkSelectionNode::COMPONENT_NUMBER())
                         ? node->GetProperties()->Get(vtkSelectionNode::COMPONENT_NUMBER())
                         : 0;
  }
  else if (node->GetContentType() == vtkSelectionNode::FRUSTUM)
  {
    spec.mode = Modes::FRUSTUM;
    // As vtkFrustumSelector reads it: 32 values, x y z w per corner, w ignored.
    if (list->GetNumberOfValues() != 32)
    {
      problem << "a FRUSTUM selection needs 8 corners (x, y, z, w: 32 values), got "
              << list->GetNumberOfValues() << " values";
      return problem.str();
    }
    std::array<Vec3, 8> corners;
    for (vtkIdType c = 0; c < 8; ++c)
    {
      for (int a = 0; a < 3; ++a)
      {
        const vtkIdType v = 4 * c + a;
        corners[static_cast<std::size_t>(c)][static_cast<std::size_t>(a)] = list->GetComponent(
            v / list->GetNumberOfComponents(), static_cast<int>(v % list->GetNumberOfComponents()));
      }
    }
    const std::string wrong = Frustum::fromCorners(corners, spec.frustum);
    if (!wrong.empty())
    {
      problem << "invalid frustum: " << wrong;
    }
  }
  else
  {
    problem << "selection content type "
            << vtkSelectionNode::GetContentTypeAsString(node->GetContentType())
            << " is not supported (LOCATIONS, GLOBALIDS, INDICES, THRESHOLDS, FRUSTUM are)";
  }
  return problem.str();
}

/// The convenience properties (no vtkSelection connected).
std::string readProperties(const SelectionProperties& properties, SelectionSpec& spec)
{
  std::string wrongFrustum;
  if (spec.mode == Modes::LOCATIONS)
  {
    const std::vector<double>& xyz = properties.locations;
    for (std::size_t i = 0; i + 2 < xyz.size(); i += 3)
    {
      spec.points.push_back({{xyz[i], xyz[i + 1], xyz[i + 2]}});
    }
  }
  else if (spec.mode == Modes::IDS)
  {
    spec.ids = properties.ids;
  }
  else if (spec.mode == Modes::FRUSTUM && properties.frustumCorners.empty())
  {
    for (std::size_t p = 0; p < 6; ++p)
    {
      std::copy(properties.frustumPlanes + 4 * p, properties.frustumPlanes + 4 * p + 4,
                spec.frustum.planes[p].begin());
    }
    wrongFrustum = spec.frustum.problem();
  }
  else if (spec.mode == Modes::FRUSTUM && properties.frustumCorners.size() == 24)
  {
    std::array<Vec3, 8> corners;
    for (std::size_t c = 0; c < 8; ++c)
    {
      std::copy(properties.frustumCorners.begin() + static_cast<std::ptrdiff_t>(3 * c),
                properties.frustumCorners.begin() + static_cast<std::ptrdiff_t>(3 * c + 3),
                corners[c].begin());
    }
    wrongFrustum = Frustum::fromCorners(corners, spec.frustum);
  }
  else if (spec.mode == Modes::FRUSTUM)
  {
    wrongFrustum = "a frustum needs 8 corners or none (then its 6 planes), got " +
                   std::to_string(properties.frustumCorners.size() / 3) + " corners";
  }
  return wrongFrustum.empty() ? std::string() : "invalid frustum: " + wrongFrustum;
}

/// What the reading cannot see: a box's order, finite points, the field of a
/// value range in the input.
std::string check(vtkHyperTreeGrid* input, SelectionSpec& spec)
{
  std::ostringstream problem;
  for (int a = 0; spec.mode == Modes::BOX && a < 3; ++a)
  {
    if (!(spec.box[2 * a] <= spec.box[2 * a + 1]))
    {
      problem << "box [" << spec.box[2 * a] << ", " << spec.box[2 * a + 1] << "] along axis "
              << "xyz"[a] << " needs min <= max (and no NaN)";
      return problem.str();
    }
  }
  for (std::size_t i = 0; i < spec.points.size(); ++i)
  {
    const Vec3& p = spec.points[i];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    {
      problem << "location " << i << " is not finite: (" << p[0] << ", " << p[1] << ", " << p[2]
              << ")";
      return problem.str();
    }
  }
  if (spec.mode == Modes::VALUE_RANGE)
  {
    spec.values = input->GetCellData()->GetArray(spec.field.c_str());
    if (!spec.values)
    {
      problem << "no cell field named '" << spec.field << "' in the input";
    }
    else if (spec.component >= spec.values->GetNumberOfComponents() || spec.component < -1)
    {
      problem << "field '" << spec.field << "' has " << spec.values->GetNumberOfComponents()
              << " components; component " << spec.component << " does not exist";
    }
  }
  return problem.str();
}

} // namespace

bool SelectionSpec::byRegion() const
{
  return mode == Modes::BOX || mode == Modes::FRUSTUM;
}

bool SelectionSpec::readsByCellNumber() const
{
  return mode == Modes::IDS || mode == Modes::VALUE_RANGE;
}

std::uint64_t SelectionSpec::fingerprint(const HyperTreeAccess& grid, bool allowMasked) const
{
  std::uint64_t h = hashCombine(0xCA40B1ull, static_cast<std::uint64_t>(mode));
  h = hashCombine(h, (invert ? 1u : 0u) | (allowMasked ? 2u : 0u));
  h = hashCombine(h, static_cast<std::uint64_t>(grid.dimension() * 64 + grid.childrenPerNode()));
  switch (mode)
  {
  case Modes::LOCATIONS:
    return hashBytes(points.data(), points.size() * sizeof(Vec3), h);
  case Modes::IDS:
    return hashBytes(ids.data(), ids.size() * sizeof(vtkIdType), h);
  case Modes::VALUE_RANGE:
    h = hashCombine(h, reinterpret_cast<std::uintptr_t>(values));
    h = hashCombine(h, values ? values->GetMTime() : 0);
    h = hashCombine(h, static_cast<std::uint64_t>(component + 1));
    return hashBytes(range.data(), 2 * sizeof(double), h);
  case Modes::BOX:
    return hashBytes(box.data(), sizeof(box), h);
  default:
    return hashBytes(frustum.planes.data(), sizeof(frustum.planes), h);
  }
}

std::string readSelectionSpec(const SelectionProperties& properties, vtkSelection* selection,
                              vtkHyperTreeGrid* input, SelectionSpec& spec)
{
  spec = SelectionSpec();
  spec.mode = properties.mode;
  spec.field = properties.field;
  spec.component = properties.component;
  spec.range = {{properties.range[0], properties.range[1]}};
  std::copy(properties.box, properties.box + 6, spec.box.begin());
  std::string problem =
      selection ? readSelectionNode(selection, spec) : readProperties(properties, spec);
  if (problem.empty())
  {
    problem = check(input, spec);
  }
  spec.invert = properties.invert;
  if (selection && selection->GetNumberOfNodes() > 0)
  {
    vtkInformation* nodeProperties = selection->GetNode(0)->GetProperties();
    if (nodeProperties->Has(vtkSelectionNode::INVERSE()) &&
        nodeProperties->Get(vtkSelectionNode::INVERSE()) != 0)
    {
      spec.invert = !spec.invert;
    }
  }
  return problem;
}

} // namespace canopy
