// Selection extraction against brute-force scans of all leaves (VTK's cursors):
// by location (points inside cells, on shared faces, edges and corners, on the
// domain's upper boundary, outside), by id (leaves, coarse cells, out of range,
// duplicates) and by value range; both output modes.
#include "ErrorMessages.h"
#include "HtgWalk.h"
#include "PaperCaseDefinitions.h"
#include "RandomForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkIdTypeArray.h>
#include <vtkPoints.h>
#include <vtkSelection.h>
#include <vtkSelectionNode.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <string>

namespace canopy::testing
{
namespace
{

using Point = std::array<double, 3>;

/// The documented rule, by brute force: lo <= p < hi on each active axis, or
/// p == hi where hi is the domain's upper bound.
std::set<vtkIdType> expectedAt(vtkHyperTreeGrid* htg, const std::vector<Point>& points)
{
  double d[6];
  htg->GetBounds(d);
  const auto leaves = visibleLeafBoxes(htg);
  std::set<vtkIdType> ids;
  for (const Point& p : points)
  {
    for (const LeafBox& leaf : leaves)
    {
      bool inside = true;
      for (int a = 0; a < 3 && inside; ++a)
      {
        if (leaf.bounds[2 * a] == leaf.bounds[2 * a + 1])
        {
          continue; // flat axis: ignored
        }
        // The last cell along an axis ends at the domain's bound (VTK's cursor
        // bounds of ternary cells can miss it by an ulp).
        const double top = d[2 * a + 1];
        const bool upper = std::abs(leaf.bounds[2 * a + 1] - top) <= 1e-12 * (1 + std::abs(top));
        inside =
            p[a] >= leaf.bounds[2 * a] && (p[a] < leaf.bounds[2 * a + 1] || (upper && p[a] == top));
      }
      if (inside)
      {
        ids.insert(leaf.global);
        break;
      }
    }
  }
  return ids;
}

std::set<vtkIdType> idsOf(vtkUnstructuredGrid* out)
{
  std::set<vtkIdType> ids;
  auto* a = vtkIdTypeArray::SafeDownCast(out->GetCellData()->GetArray("OriginalCellId"));
  for (vtkIdType i = 0; a && i < a->GetNumberOfTuples(); ++i)
  {
    ids.insert(a->GetValue(i));
  }
  return ids;
}

/// Points that stress the rule: leaf corners, edge and face midpoints, centres,
/// the domain's upper corner and faces, and points outside. Points on shared
/// faces are only meaningful where cell bounds are exact in binary (binary trees
/// over dyadic root coordinates): elsewhere VTK's cursor bounds and the exact
/// ones may differ in the last bit, so `onFaces` false keeps cell centres only.
std::vector<Point> trickyPoints(vtkHyperTreeGrid* htg, std::uint64_t seed, bool onFaces = true)
{
  std::mt19937_64 random(seed);
  std::vector<Point> points;
  const auto leaves = visibleLeafBoxes(htg);
  for (std::size_t i = 0; i < leaves.size(); i += 3)
  {
    const double* b = leaves[i].bounds;
    const int pick = static_cast<int>(random() % 4);
    Point p;
    for (int a = 0; a < 3; ++a)
    {
      const double lo = b[2 * a];
      const double hi = b[2 * a + 1];
      const double options[] = {lo, hi, 0.5 * (lo + hi)};
      p[a] = onFaces ? options[(pick + a) % 3] : 0.5 * (lo + hi);
    }
    points.push_back(p);
  }
  double d[6];
  htg->GetBounds(d);
  points.push_back({{d[1], d[3], d[5]}});                               // upper corner
  points.push_back({{d[1], 0.5 * (d[2] + d[3]), d[4]}});                // upper face
  points.push_back({{d[0] - 1e-9, d[2], d[4]}});                        // just outside
  points.push_back({{d[1] + 1.0, 0.5 * (d[2] + d[3]), d[5]}});          // outside
  points.push_back({{0.5 * (d[0] + d[1]), 0.5 * (d[2] + d[3]), d[4]}}); // inside
  return points;
}

vtkSmartPointer<vtkUnstructuredGrid> selectAt(vtkHyperTreeGrid* htg,
                                              const std::vector<Point>& points,
                                              vtkCanopyExtractSelection* filter = nullptr)
{
  vtkNew<vtkCanopyExtractSelection> own;
  vtkCanopyExtractSelection* f = filter ? filter : own.Get();
  f->SetInputData(htg);
  f->SetSelectionMode(vtkCanopyExtractSelection::LOCATIONS);
  f->ClearLocations();
  for (const Point& p : points)
  {
    f->AddLocation(p[0], p[1], p[2]);
  }
  f->Update();
  vtkSmartPointer<vtkUnstructuredGrid> out = vtkUnstructuredGrid::SafeDownCast(f->GetOutput());
  return out;
}

TEST(ExtractSelection, ByLocationFollowsTheBoundaryRuleOnPaperCases)
{
  for (bool withMask : {false, true})
  {
    for (bool caseB : {false, true})
    {
      DescriptorForest forest(caseB ? paperCaseB(withMask) : paperCaseA(withMask));
      auto htg = buildHyperTreeGrid(forest.description());
      // Case A's bounds are exact dyadics; case B (ternary, scale 0.7) is not.
      const auto points = trickyPoints(htg, caseB * 2 + withMask, !caseB);
      vtkNew<vtkCanopyExtractSelection> filter;
      auto out = selectAt(htg, points, filter);
      const auto expected = expectedAt(htg, points);
      EXPECT_EQ(idsOf(out), expected)
          << (caseB ? "case B" : "case A") << (withMask ? " with mask" : "");
      EXPECT_GE(filter->GetLastOutside(), 2);
      EXPECT_EQ(static_cast<std::size_t>(out->GetNumberOfCells()), expected.size());
    }
  }
}

TEST(ExtractSelection, ByLocationOnRandomForestsInEveryPlane)
{
  for (std::uint64_t seed = 1; seed <= 9; ++seed)
  {
    RandomForestOptions o;
    o.dimension = seed % 3 == 0 ? 3 : 2;
    o.flatAxis = static_cast<int>(seed % 3);
    o.branchFactor = seed % 2 ? 3 : 2;
    o.rootCells = {{3, 2, 2}};
    o.maxLevels = o.branchFactor == 2 ? 5 : 3;
    o.maskProbability = 0.1;
    o.skipEveryOtherRoot = seed % 4 == 0;
    o.order = seed % 2 ? StorageOrder::DepthFirst : StorageOrder::BreadthFirst;
    o.origin = {{-3.5, 1e3, 7.25}};
    o.seed = seed;
    RandomForest forest(o);
    // Dyadic root coordinates, so binary trees have exact bounds everywhere.
    auto& coords = const_cast<std::array<std::vector<double>, 3>&>(forest.coordinates());
    for (int a = 0; a < 3; ++a)
    {
      for (std::size_t i = 0; i < coords[a].size(); ++i)
      {
        coords[a][i] = o.origin[a] + 0.75 * static_cast<double>(i) + (i % 2 ? 0.25 : 0.0);
      }
    }
    auto htg = buildHyperTreeGrid(forest.description());
    const auto points = trickyPoints(htg, seed, o.branchFactor == 2);
    const auto got = idsOf(selectAt(htg, points));
    const auto expected = expectedAt(htg, points);
    std::vector<vtkIdType> onlyGot, onlyExpected;
    std::set_difference(got.begin(), got.end(), expected.begin(), expected.end(),
                        std::back_inserter(onlyGot));
    std::set_difference(expected.begin(), expected.end(), got.begin(), got.end(),
                        std::back_inserter(onlyExpected));
    EXPECT_EQ(got, expected) << "seed " << seed << ": " << onlyGot.size() << " only selected, "
                             << onlyExpected.size() << " only expected"
                             << (onlyGot.empty() ? "" : ", e.g. " + std::to_string(onlyGot[0]))
                             << (onlyExpected.empty()
                                     ? ""
                                     : ", e.g. " + std::to_string(onlyExpected[0]));
  }
}

TEST(ExtractSelection, UnstructuredOutputHasMergedPointsFieldsAndIds)
{
  for (bool caseB : {false, true})
  {
    DescriptorForest forest(caseB ? paperCaseB(true) : paperCaseA(true));
    auto htg = buildHyperTreeGrid(forest.description());
    const auto points = trickyPoints(htg, 5, !caseB);
    auto out = selectAt(htg, points);
    ASSERT_GT(out->GetNumberOfCells(), 0);
    // Corners rounded to 1e-9: VTK's cursor bounds of ternary cells may differ
    // in the last bit between neighbours; the filter's are computed exactly.
    std::set<std::array<long long, 3>> corners;
    auto* ids = vtkIdTypeArray::SafeDownCast(out->GetCellData()->GetArray("OriginalCellId"));
    vtkDataArray* depth = out->GetCellData()->GetArray("Depth");
    ASSERT_NE(depth, nullptr);
    std::map<vtkIdType, LeafBox> byId;
    for (const LeafBox& l : visibleLeafBoxes(htg))
    {
      byId[l.global] = l;
    }
    for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
    {
      EXPECT_EQ(out->GetCellType(c), caseB ? VTK_HEXAHEDRON : VTK_QUAD);
      const vtkIdType id = ids->GetValue(c);
      EXPECT_EQ(depth->GetTuple1(c), forest.depth()[static_cast<std::size_t>(id)]);
      double cb[6];
      out->GetCell(c)->GetBounds(cb);
      for (int i = 0; i < 6; ++i)
      {
        EXPECT_NEAR(cb[i], byId.at(id).bounds[i], 1e-12);
      }
      const LeafBox& l = byId.at(id);
      for (int k = 0; k < 8; ++k)
      {
        corners.insert({{std::llround(l.bounds[(k & 1) ? 1 : 0] * 1e9),
                         std::llround(l.bounds[(k & 2) ? 3 : 2] * 1e9),
                         std::llround(l.bounds[(k & 4) ? 5 : 4] * 1e9)}});
      }
    }
    EXPECT_EQ(static_cast<std::size_t>(out->GetNumberOfPoints()), corners.size());
  }
}

TEST(ExtractSelection, ByIdSelectsLeavesAndCoarseCellsAndCountsTheRest)
{
  DescriptorForest forest(paperCaseA(true));
  auto htg = buildHyperTreeGrid(forest.description());
  // Leaves and coarse cells, visible or masked, by brute force.
  std::set<vtkIdType> visibleNodes;
  forEachVisibleNode(htg, [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor)
                     { visibleNodes.insert(cursor->GetGlobalNodeIndex()); });
  vtkNew<vtkCanopyExtractSelection> filter;
  filter->SetInputData(htg);
  filter->SetSelectionMode(vtkCanopyExtractSelection::IDS);
  std::set<vtkIdType> expected;
  std::size_t masked = 0;
  for (vtkIdType id = 0; id < 98; id += 3)
  {
    filter->AddId(id);
    (visibleNodes.count(id) ? expected.insert(id), 0 : ++masked);
  }
  filter->AddId(0);  // duplicate
  filter->AddId(-1); // out of range
  filter->AddId(98); // out of range
  filter->Update();
  auto* out = vtkUnstructuredGrid::SafeDownCast(filter->GetOutput());
  EXPECT_EQ(idsOf(out), expected);
  EXPECT_EQ(filter->GetLastOutOfRange(), 2);
  EXPECT_EQ(filter->GetLastDuplicates(), 1);
  EXPECT_EQ(static_cast<std::size_t>(filter->GetLastMasked()), masked);
  // With AllowMasked, masked cells are selectable too.
  filter->AllowMaskedOn();
  filter->Update();
  EXPECT_EQ(idsOf(vtkUnstructuredGrid::SafeDownCast(filter->GetOutput())).size(),
            expected.size() + masked);
  EXPECT_EQ(filter->GetLastMasked(), 0);
  filter->AllowMaskedOff();
  // A coarse id (the root of tree 0) gives that coarse cell, one quad of its size.
  filter->ClearIds();
  filter->AddId(0);
  filter->Update();
  out = vtkUnstructuredGrid::SafeDownCast(filter->GetOutput());
  ASSERT_EQ(out->GetNumberOfCells(), 1);
  double b[6];
  out->GetCell(0)->GetBounds(b);
  EXPECT_EQ(b[1] - b[0], 1.5);
  EXPECT_EQ(b[3] - b[2], 1.0);
}

TEST(ExtractSelection, ByValueRangeIsInclusiveAndSkipsNaN)
{
  DescriptorForest forest(paperCaseB(true));
  std::vector<double> values(forest.numberOfNodes());
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    values[i] = std::fmod(i * 0.37, 3.0);
  }
  values[100] = std::nan("");
  forest.description().fields.push_back(FieldDescription::aos("v", values.data(), values.size()));
  auto htg = buildHyperTreeGrid(forest.description());
  const double low = 0.5;
  const double high = values[200]; // an exact value, to test inclusiveness
  std::set<vtkIdType> expected;
  for (const LeafBox& l : visibleLeafBoxes(htg))
  {
    const double v = values[static_cast<std::size_t>(l.global)];
    if (v >= low && v <= high)
    {
      expected.insert(l.global);
    }
  }
  vtkNew<vtkCanopyExtractSelection> filter;
  filter->SetInputData(htg);
  filter->SetSelectionMode(vtkCanopyExtractSelection::VALUE_RANGE);
  filter->SetValueArrayName("v");
  filter->SetValueRange(low, high);
  filter->Update();
  EXPECT_EQ(idsOf(vtkUnstructuredGrid::SafeDownCast(filter->GetOutput())), expected);
  EXPECT_GT(expected.size(), 10u);

  // Magnitude of a 2-component field: sqrt(v^2 + (2v)^2) = sqrt(5) |v|.
  std::vector<double> pairs(2 * values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    pairs[2 * i] = values[i];
    pairs[2 * i + 1] = 2 * values[i];
  }
  forest.description().fields.push_back(FieldDescription::aos("w", pairs.data(), values.size(), 2));
  auto withPairs = buildHyperTreeGrid(forest.description());
  std::set<vtkIdType> expectedMagnitude;
  for (const LeafBox& l : visibleLeafBoxes(withPairs))
  {
    const double v = std::sqrt(5.0) * std::abs(values[static_cast<std::size_t>(l.global)]);
    if (v >= 1.0 && v <= 3.0)
    {
      expectedMagnitude.insert(l.global);
    }
  }
  filter->SetInputData(withPairs);
  filter->SetValueArrayName("w");
  filter->SetValueComponent(-1);
  filter->SetValueRange(1.0, 3.0);
  filter->Update();
  EXPECT_EQ(idsOf(vtkUnstructuredGrid::SafeDownCast(filter->GetOutput())), expectedMagnitude);
  EXPECT_GT(expectedMagnitude.size(), 10u);
}

TEST(ExtractSelection, PreserveTopologyLeavesExactlyTheSelectionVisible)
{
  DescriptorForest forest(paperCaseB(true));
  auto htg = buildHyperTreeGrid(forest.description());
  const auto points = trickyPoints(htg, 9, false);
  vtkNew<vtkCanopyExtractSelection> filter;
  filter->PreserveTopologyOn();
  filter->SetInputData(htg);
  filter->SetSelectionMode(vtkCanopyExtractSelection::LOCATIONS);
  for (const Point& p : points)
  {
    filter->AddLocation(p[0], p[1], p[2]);
  }
  filter->Update();
  auto* out = vtkHyperTreeGrid::SafeDownCast(filter->GetOutput());
  ASSERT_NE(out, nullptr);
  std::set<vtkIdType> visible;
  for (const LeafBox& l : visibleLeafBoxes(out))
  {
    visible.insert(l.global);
  }
  EXPECT_EQ(visible, expectedAt(htg, points));
  // The output shares the input's arrays.
  EXPECT_EQ(out->GetCellData()->GetArray("Depth"), htg->GetCellData()->GetArray("Depth"));
}

TEST(ExtractSelection, VtkSelectionInputDrivesTheFilter)
{
  DescriptorForest forest(paperCaseA(false));
  auto htg = buildHyperTreeGrid(forest.description());
  vtkNew<vtkSelection> selection;
  vtkNew<vtkSelectionNode> node;
  node->SetContentType(vtkSelectionNode::GLOBALIDS);
  node->SetFieldType(vtkSelectionNode::CELL);
  vtkNew<vtkIdTypeArray> list;
  list->InsertNextValue(7);
  list->InsertNextValue(42);
  node->SetSelectionList(list);
  selection->AddNode(node);
  vtkNew<vtkCanopyExtractSelection> filter;
  filter->SetInputData(0, htg);
  filter->SetInputData(1, selection);
  filter->Update();
  EXPECT_EQ(idsOf(vtkUnstructuredGrid::SafeDownCast(filter->GetOutput())),
            (std::set<vtkIdType>{7, 42}));
}

TEST(ExtractSelection, BadInputIsReportedNotCrashed)
{
  DescriptorForest forest(paperCaseA(false));
  auto htg = buildHyperTreeGrid(forest.description());
  {
    vtkNew<vtkCanopyExtractSelection> f;
    f->SetInputData(htg);
    f->AddLocation(std::nan(""), 0, 0);
    EXPECT_EQ(errorsOfUpdate(f).size(), 1u);
  }
  {
    vtkNew<vtkCanopyExtractSelection> f;
    f->SetInputData(htg);
    f->SetSelectionMode(vtkCanopyExtractSelection::VALUE_RANGE);
    f->SetValueArrayName("Pressure");
    EXPECT_EQ(errorsOfUpdate(f).size(), 1u);
  }
  {
    vtkNew<vtkSelection> selection;
    vtkNew<vtkSelectionNode> node;
    node->SetContentType(vtkSelectionNode::FRUSTUM);
    vtkNew<vtkDoubleArray> list;
    list->SetNumberOfComponents(4);
    list->InsertNextTuple4(0, 0, 0, 1);
    node->SetSelectionList(list);
    selection->AddNode(node);
    vtkNew<vtkCanopyExtractSelection> f;
    f->SetInputData(0, htg);
    f->SetInputData(1, selection);
    EXPECT_EQ(errorsOfUpdate(f).size(), 1u);
  }
  {
    // An empty selection is an empty result, not an error.
    vtkNew<vtkCanopyExtractSelection> f;
    f->SetInputData(htg);
    f->SetSelectionMode(vtkCanopyExtractSelection::IDS);
    EXPECT_EQ(errorsOfUpdate(f).size(), 0u);
    EXPECT_EQ(vtkUnstructuredGrid::SafeDownCast(f->GetOutput())->GetNumberOfCells(), 0);
  }
}

/// A random 1D forest along `axis` whose binary trees have exact (dyadic) bounds.
std::unique_ptr<RandomForest> lineForest(std::uint64_t seed, int axis, int branchFactor)
{
  RandomForestOptions o;
  o.dimension = 1;
  o.activeAxis = axis;
  o.branchFactor = branchFactor;
  o.rootCells = {{5, 6, 7}};
  o.maxLevels = branchFactor == 2 ? 10 : 6;
  o.refineProbability = 0.6;
  o.maskProbability = 0.1;
  o.skipEveryOtherRoot = seed % 3 == 0;
  o.order = seed % 2 ? StorageOrder::DepthFirst : StorageOrder::BreadthFirst;
  o.origin = {{-3.5, 1e3, 7.25}};
  o.seed = seed;
  auto forest = std::make_unique<RandomForest>(o);
  auto& coords = const_cast<std::array<std::vector<double>, 3>&>(forest->coordinates());
  for (std::size_t i = 0; i < coords[axis].size(); ++i)
  {
    coords[axis][i] = o.origin[axis] + 0.75 * static_cast<double>(i) + (i % 2 ? 0.25 : 0.0);
  }
  return forest;
}

TEST(ExtractSelection, OnLinesLocationsIdsAndValuesEqualBruteForce)
{
  std::size_t valuesSelected = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed)
  {
    const int axis = static_cast<int>(seed % 3);
    const int f = seed % 4 < 2 ? 2 : 3;
    auto forest = lineForest(seed, axis, f);
    std::vector<double> values(forest->numberOfNodes());
    for (std::size_t i = 0; i < values.size(); ++i)
    {
      values[i] = std::fmod(static_cast<double>(i) * 0.37, 3.0);
    }
    values[values.size() / 2] = std::nan("");
    forest->description().fields.push_back(
        FieldDescription::aos("v", values.data(), values.size()));
    auto htg = buildHyperTreeGrid(forest->description());
    const std::string label = "seed " + std::to_string(seed) + " along " + "xyz"[axis] +
                              ", branch factor " + std::to_string(f);
    // Locations: ends, centres, the line's upper end, outside; off the line on the
    // flat axes (ignored).
    auto points = trickyPoints(htg, seed, f == 2);
    double d[6];
    htg->GetBounds(d);
    Point before{{d[0], d[2], d[4]}};
    before[axis] -= 1e-9;
    Point after{{d[1], d[3], d[5]}};
    after[axis] += 0.5;
    points.push_back(before);
    points.push_back(after);
    for (auto& p : points)
    {
      p[(axis + 1) % 3] += 0.5;
    }
    for (bool preserve : {false, true})
    {
      vtkNew<vtkCanopyExtractSelection> filter;
      filter->SetPreserveTopology(preserve);
      for (const Point& p : points)
      {
        filter->AddLocation(p[0], p[1], p[2]);
      }
      filter->SetInputData(htg);
      filter->Update();
      std::set<vtkIdType> got;
      if (preserve)
      {
        for (const LeafBox& l :
             visibleLeafBoxes(vtkHyperTreeGrid::SafeDownCast(filter->GetOutput())))
        {
          got.insert(l.global);
        }
      }
      else
      {
        got = idsOf(vtkUnstructuredGrid::SafeDownCast(filter->GetOutput()));
      }
      EXPECT_EQ(got, expectedAt(htg, points)) << label << (preserve ? " (masked grid)" : "");
      EXPECT_GE(filter->GetLastOutside(), 2) << label;
    }
    // Ids: every third node, coarse ones included; masked ones are counted.
    std::set<vtkIdType> visibleNodes;
    forEachVisibleNode(htg, [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor)
                       { visibleNodes.insert(cursor->GetGlobalNodeIndex()); });
    vtkNew<vtkCanopyExtractSelection> byId;
    byId->SetInputData(htg);
    byId->SetSelectionMode(vtkCanopyExtractSelection::IDS);
    std::set<vtkIdType> expectedIds;
    for (vtkIdType id = 0; id < htg->GetNumberOfCells(); id += 3)
    {
      byId->AddId(id);
      if (visibleNodes.count(id))
      {
        expectedIds.insert(id);
      }
    }
    byId->Update();
    EXPECT_EQ(idsOf(vtkUnstructuredGrid::SafeDownCast(byId->GetOutput())), expectedIds) << label;
    // Values within [0.5, 2] on visible leaves, never NaN; a cell's value is in its slot.
    std::map<vtkIdType, std::size_t> slotOfCell;
    for (std::size_t t = 0; t < forest->nodes().size(); ++t)
      for (std::size_t n = 0; n < forest->nodes()[t].size(); ++n)
        slotOfCell[forest->cellOf(t, n)] = static_cast<std::size_t>(forest->nodes()[t][n].slot);
    std::set<vtkIdType> expectedValues;
    for (const LeafBox& l : visibleLeafBoxes(htg))
    {
      const double v = values[slotOfCell.at(l.global)];
      if (v >= 0.5 && v <= 2.0)
      {
        expectedValues.insert(l.global);
      }
    }
    vtkNew<vtkCanopyExtractSelection> byValue;
    byValue->SetInputData(htg);
    byValue->SetSelectionMode(vtkCanopyExtractSelection::VALUE_RANGE);
    byValue->SetValueArrayName("v");
    byValue->SetValueRange(0.5, 2.0);
    byValue->Update();
    EXPECT_EQ(idsOf(vtkUnstructuredGrid::SafeDownCast(byValue->GetOutput())), expectedValues)
        << label;
    valuesSelected += expectedValues.size();
  }
  EXPECT_GT(valuesSelected, 30u);
}

TEST(ExtractSelection, LineCellsAreVtkLinesWithMergedPointsFieldsAndIds)
{
  for (int axis = 0; axis < 3; ++axis)
  {
    auto forest = lineForest(7, axis, 2);
    auto htg = buildHyperTreeGrid(forest->description());
    double b[6];
    htg->GetBounds(b);
    vtkNew<vtkCanopyExtractSelection> filter;
    filter->SetInputData(htg);
    filter->SetSelectionMode(vtkCanopyExtractSelection::BOX);
    filter->SetBox(b); // every visible leaf
    filter->Update();
    auto* out = vtkUnstructuredGrid::SafeDownCast(filter->GetOutput());
    const auto leaves = visibleLeafBoxes(htg);
    ASSERT_EQ(out->GetNumberOfCells(), static_cast<vtkIdType>(leaves.size()));
    std::map<vtkIdType, const LeafBox*> byId;
    std::set<double> ends;
    for (const LeafBox& l : leaves)
    {
      byId[l.global] = &l;
      ends.insert(l.bounds[2 * axis]);
      ends.insert(l.bounds[2 * axis + 1]);
    }
    auto* ids = vtkIdTypeArray::SafeDownCast(out->GetCellData()->GetArray("OriginalCellId"));
    vtkDataArray* levels = out->GetCellData()->GetArray("Level");
    ASSERT_NE(levels, nullptr);
    for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
    {
      EXPECT_EQ(out->GetCellType(c), VTK_LINE);
      EXPECT_EQ(out->GetCell(c)->GetNumberOfPoints(), 2);
      const LeafBox& l = *byId.at(ids->GetValue(c));
      EXPECT_EQ(levels->GetTuple1(c), l.level);
      double cb[6];
      out->GetCell(c)->GetBounds(cb);
      for (int i = 0; i < 6; ++i)
      {
        EXPECT_EQ(cb[i], l.bounds[i]) << "axis " << axis;
      }
    }
    // Neighbours share their end point: one point per distinct end.
    EXPECT_EQ(static_cast<std::size_t>(out->GetNumberOfPoints()), ends.size());
  }
}

TEST(ExtractSelection, Depth30LocationsAreExact)
{
  // One 2D tree refined along a point down to 31 levels.
  std::array<double, 2> x{{0, 1}}, y{{0, 1}};
  std::array<double, 1> z{{0}};
  std::vector<std::uint8_t> refinement{1};
  for (int level = 1; level < 31; ++level)
  {
    for (int c = 0; c < 4; ++c)
    {
      refinement.push_back(level + 1 < 31 && c == 3 ? 1 : 0); // towards the upper corner
    }
  }
  ForestDescription d;
  d.dimension = 2;
  d.branchFactor = 2;
  d.maxLevels = 31;
  d.rootGrid = {x.data(), y.data(), z.data(), 2, 2, 1};
  TreeDescription t;
  t.refinement = refinement.data();
  t.numberOfNodes = refinement.size();
  d.trees.push_back(t);
  auto htg = buildHyperTreeGrid(d);
  const auto points = trickyPoints(htg, 30);
  EXPECT_EQ(idsOf(selectAt(htg, points)), expectedAt(htg, points));
}

} // namespace
} // namespace canopy::testing
