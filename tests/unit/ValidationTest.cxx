// A malformed description is rejected before anything is built, with a message
// that names the tree or field and the problem.
#include "PaperCaseDefinitions.h"

#include "ForestLayout.h" // layoutForest: the internal layout these tests check
#include <canopy/HtgBuilder.h>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <type_traits>
#include <utility>

namespace canopy::testing
{
namespace
{

/// Case A with a mask and a "Depth" field: valid as given.
class Validation : public ::testing::Test
{
protected:
  Validation() : Forest(paperCaseA(true)) {}

  ForestDescription& d() { return Forest.description(); }

  /// Expects the current description to be rejected with every fragment in the message.
  void expectRejected(const std::vector<std::string>& fragments)
  {
    try
    {
      buildHyperTreeGrid(d());
      FAIL() << "the description should have been rejected";
    }
    catch (const InvalidForest& e)
    {
      const std::string message = e.what();
      EXPECT_FALSE(e.problems().empty());
      for (const auto& fragment : fragments)
      {
        EXPECT_NE(message.find(fragment), std::string::npos)
            << "expected '" << fragment << "' in:\n"
            << message;
      }
    }
  }

  DescriptorForest Forest;
};

TEST_F(Validation, TheUnmodifiedForestIsValid)
{
  EXPECT_NO_THROW(validateForest(d()));
  const ForestLayout layout = layoutForest(d());
  EXPECT_EQ(layout.totalNodes, 98u);
  EXPECT_EQ(layout.totalLeaves, 75u);
  EXPECT_EQ(layout.numberOfRootCells, 6u);
  EXPECT_TRUE(layout.anyMask);
  EXPECT_FALSE(layout.explicitSlots);
}

TEST_F(Validation, BadDimension)
{
  d().dimension = 4;
  expectRejected({"dimension must be 1, 2 or 3, got 4"});
  d().dimension = 0;
  expectRejected({"dimension must be 1, 2 or 3, got 0"});
}

TEST(LineForestValidation, ALineOfRootsAlongAnyAxisAndNothingElse)
{
  // Three roots along one axis; tree 0 refined (binary: 2 children), tree 2 a leaf.
  const std::vector<double> line{0.0, 1.0, 2.5, 3.0};
  const std::vector<double> point{4.0};
  const std::vector<std::uint8_t> refined{1, 0, 1, 0, 0}, leaf{0};
  for (int axis = 0; axis < 3; ++axis)
  {
    ForestDescription forest;
    forest.dimension = 1;
    forest.branchFactor = 2;
    forest.maxLevels = 3;
    const double* coords[3] = {point.data(), point.data(), point.data()};
    std::size_t counts[3] = {1, 1, 1};
    coords[axis] = line.data();
    counts[axis] = line.size();
    forest.rootGrid = {coords[0], coords[1], coords[2], counts[0], counts[1], counts[2]};
    forest.trees.push_back({0, refined.data(), refined.size(), nullptr, nullptr});
    forest.trees.push_back({2, leaf.data(), leaf.size(), nullptr, nullptr});
    const ForestLayout layout = layoutForest(forest);
    EXPECT_EQ(layout.totalNodes, 6u) << "axis " << axis;
    EXPECT_EQ(layout.totalLeaves, 4u) << "axis " << axis;
    EXPECT_EQ(layout.numberOfRootCells, 3u) << "axis " << axis;
    // A ternary reading of the same bits needs 3 children per refined node.
    forest.branchFactor = 3;
    EXPECT_THROW(validateForest(forest), InvalidForest);
    forest.branchFactor = 2;
    // A 1D forest needs exactly two flat axes, a 2D forest exactly one.
    counts[(axis + 1) % 3] = 2;
    const std::vector<double> two{4.0, 5.0};
    coords[(axis + 1) % 3] = two.data();
    forest.rootGrid = {coords[0], coords[1], coords[2], counts[0], counts[1], counts[2]};
    try
    {
      validateForest(forest);
      ADD_FAILURE() << "a 1D forest over a plane of roots was accepted";
    }
    catch (const InvalidForest& e)
    {
      EXPECT_NE(std::string(e.what()).find("a 1D forest needs exactly two flat axes"),
                std::string::npos)
          << e.what();
    }
    counts[(axis + 1) % 3] = 1;
    coords[(axis + 1) % 3] = point.data();
    forest.rootGrid = {coords[0], coords[1], coords[2], counts[0], counts[1], counts[2]};
    forest.dimension = 2;
    EXPECT_THROW(validateForest(forest), InvalidForest) << "a 2D forest on a line";
  }
}

TEST_F(Validation, BadBranchFactor)
{
  d().branchFactor = 4;
  expectRejected({"branchFactor must be 2 or 3, got 4"});
}

TEST_F(Validation, TooFewNodesForTheRefinementBits)
{
  d().trees[1].numberOfNodes -= 4; // the bits describe more children than declared
  expectRejected({"tree 1 (root 1)", "refinement bits describe at least"});
}

TEST_F(Validation, MoreNodesThanTheRefinementBitsDescribe)
{
  // Tree 5 is a single leaf; claim two nodes.
  d().trees[5].numberOfNodes = 2;
  expectRejected({"tree 5 (root 5)", "refinement bits describe 1 nodes but numberOfNodes is 2"});
}

TEST_F(Validation, DepthBeyondTheStatedMaximum)
{
  d().maxLevels = 4; // case A has 6 levels
  expectRejected({"refined beyond maxLevels = 4"});
}

TEST_F(Validation, TooFewFieldValues)
{
  d().fields[0].numberOfTuples = 97;
  expectRejected({"field 0 'Depth'", "97 tuples given but the forest has 98 nodes"});
}

TEST_F(Validation, TooFewLeafValues)
{
  static const std::vector<double> leaves(74, 1.0);
  d().fields.push_back(
      FieldDescription::aos("energy", leaves.data(), leaves.size(), 1, Centering::LeavesOnly));
  expectRejected({"field 1 'energy'", "74 tuples given but the forest has 75 leaves"});
}

TEST_F(Validation, NullFieldPointer)
{
  d().fields[0].data = nullptr;
  expectRejected({"field 0 'Depth'", "data pointer is null"});
}

TEST_F(Validation, IndirectFieldWithANullAddressTable)
{
  d().fields.push_back(FieldDescription::indirect<double>("scattered", nullptr, 98));
  expectRejected({"field 1 'scattered'", "tupleAddresses pointer is null"});
}

TEST_F(Validation, IndirectFieldWithANullOrMisalignedTupleAddress)
{
  static std::vector<double> values(98, 1.0);
  static std::vector<const void*> addresses;
  addresses.clear();
  for (const double& v : values)
    addresses.push_back(&v);
  addresses[3] = nullptr;
  d().fields.push_back(FieldDescription::indirect<double>("scattered", addresses.data(), 98));
  expectRejected({"field 1 'scattered'", "the address of tuple 3 is null"});
  addresses[3] = reinterpret_cast<const char*>(&values[3]) + 1;
  expectRejected({"field 1 'scattered'", "the address of tuple 3 is not aligned"});
}

TEST_F(Validation, NullRefinementPointer)
{
  d().trees[2].refinement = nullptr;
  expectRejected({"tree 2 (root 2)", "refinement pointer is null"});
}

TEST_F(Validation, NullCoordinates)
{
  d().rootGrid.y = nullptr;
  expectRejected({"axis y coordinates pointer is null"});
}

TEST_F(Validation, SoAComponentCountMismatch)
{
  static const std::vector<double> u(98), v(98);
  FieldDescription f = FieldDescription::soa<double>("uv", {u.data(), v.data()}, 98);
  f.components = 3;
  d().fields.push_back(f);
  expectRejected({"field 1 'uv'", "2 component pointers for 3 components"});
}

TEST_F(Validation, SoANullComponent)
{
  static const std::vector<double> u(98);
  d().fields.push_back(FieldDescription::soa<double>("uv", {u.data(), nullptr}, 98));
  expectRejected({"field 1 'uv'", "component 1 pointer is null"});
}

TEST_F(Validation, StrideSmallerThanATuple)
{
  static const std::vector<double> records(3 * 98);
  d().fields.push_back(FieldDescription::strided("m", records.data(), 16, 98, 3));
  expectRejected({"field 1 'm'", "tupleStrideBytes 16 is smaller than one tuple (24 bytes)"});
}

TEST_F(Validation, RootIndexOutOfRange)
{
  d().trees[3].rootIndex = 6;
  expectRejected({"tree 3 (root 6)", "root index out of range [0, 6)"});
}

TEST_F(Validation, NegativeRootIndex)
{
  d().trees[0].rootIndex = -1;
  expectRejected({"tree 0 (root -1)", "root index out of range"});
}

TEST_F(Validation, DuplicateRoot)
{
  d().trees[4].rootIndex = 1;
  expectRejected({"tree 4 (root 1)", "duplicate root", "root cell 1"});
}

TEST_F(Validation, EmptyTree)
{
  d().trees[0].numberOfNodes = 0;
  expectRejected({"tree 0 (root 0)", "numberOfNodes is 0"});
}

TEST_F(Validation, CoordinatesNotIncreasing)
{
  static const std::vector<double> x{0.0, 1.5, 1.5};
  d().rootGrid.x = x.data();
  expectRejected({"axis x coordinates are not strictly increasing at point 2"});
}

TEST_F(Validation, NonFiniteCoordinate)
{
  static const std::vector<double> y{0.0, 1.0, std::nan(""), 3.0};
  d().rootGrid.y = y.data();
  expectRejected({"axis y coordinate 2 is not finite"});
}

TEST_F(Validation, TwoDimensionalForestWithoutAFlatAxis)
{
  static const std::vector<double> z{0.0, 10.0};
  d().rootGrid.z = z.data();
  d().rootGrid.pointsZ = 2;
  expectRejected({"a 2D forest needs exactly one flat axis"});
}

TEST_F(Validation, DuplicateFieldName)
{
  d().fields.push_back(d().fields[0]);
  expectRejected({"field 1 'Depth'", "duplicate field name"});
}

TEST_F(Validation, LeavesOnlyIntegerField)
{
  static const std::vector<std::int32_t> ids(75);
  d().fields.push_back(
      FieldDescription::aos("ids", ids.data(), ids.size(), 1, Centering::LeavesOnly));
  expectRejected({"field 1 'ids'", "leaves-only field must be floating point"});
}

TEST_F(Validation, StorageSlotsOnSomeTreesOnly)
{
  static const std::int64_t slot = 0;
  d().trees[5].storageSlots = &slot;
  expectRejected({"storage slots: 1 of 6 trees", "either every tree has one or none does"});
}

TEST_F(Validation, StorageSlotOutOfRangeOrReused)
{
  std::vector<std::vector<std::int64_t>> slots;
  std::int64_t next = 0;
  for (auto& tree : d().trees)
  {
    slots.emplace_back();
    for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
    {
      slots.back().push_back(next++);
    }
  }
  for (std::size_t t = 0; t < slots.size(); ++t)
  {
    d().trees[t].storageSlots = slots[t].data();
  }
  EXPECT_NO_THROW(validateForest(d()));
  slots[2][3] = 98;
  expectRejected({"tree 2 (root 2)", "node 3 has storage slot 98 outside [0, 98)"});
  slots[2][3] = 5;
  expectRejected({"tree 2 (root 2)", "node 3 reuses storage slot 5"});
}

TEST_F(Validation, EveryTreeProblemIsListedAtOnce)
{
  d().trees[4].rootIndex = 1;
  d().trees[2].refinement = nullptr;
  try
  {
    validateForest(d());
    FAIL() << "should throw";
  }
  catch (const InvalidForest& e)
  {
    ASSERT_EQ(e.problems().size(), 2u) << e.what();
    EXPECT_NE(e.problems()[0].find("tree 2 (root 2): refinement pointer is null"),
              std::string::npos);
    EXPECT_NE(e.problems()[1].find("tree 4 (root 1): duplicate root"), std::string::npos);
  }
}

TEST_F(Validation, StrideNotAMultipleOfTheValueSize)
{
  static const std::vector<double> records(2 * 98);
  d().fields.push_back(FieldDescription::strided("m", records.data(), 12, 98));
  expectRejected({"field 1 'm'", "tupleStrideBytes 12 is not a multiple of the value size 8"});
}

TEST_F(Validation, MaxLevelsOutOfRange)
{
  d().maxLevels = 0;
  expectRejected({"maxLevels must be in [1, 62] for branch factor 2, got 0"});
}

TEST_F(Validation, NoComponents)
{
  d().fields[0].components = 0;
  expectRejected({"field 0 'Depth'", "components must be >= 1, got 0"});
}

TEST_F(Validation, MisalignedPointer)
{
  static const std::vector<double> values(99);
  const auto* shifted =
      reinterpret_cast<const double*>(reinterpret_cast<const char*>(values.data()) + 4);
  d().fields.push_back(FieldDescription::aos("shifted", shifted, 98));
  expectRejected({"field 1 'shifted'", "not aligned to its 8-byte values"});
}

TEST_F(Validation, DepthMessageNamesTheLevelWithRefinedNodes)
{
  d().maxLevels = 5; // case A has refined nodes on level 4
  expectRejected({"refined beyond maxLevels = 5 (level 4 has refined nodes)"});
}

/// Whether buildHyperTreeGrid can be called with a stored layout: it cannot.
template <typename, typename = void>
struct TakesALayout : std::false_type
{
};
template <typename Layout>
struct TakesALayout<Layout, std::void_t<decltype(buildHyperTreeGrid(
                                std::declval<const ForestDescription&>(),
                                std::declval<const Layout&>(), FieldRequest::all()))>>
    : std::true_type
{
};

TEST(ValidationApi, NoBuildFromAStoredLayout)
{
  // A layout kept from an earlier step could no longer match the trees and be read
  // out of bounds; the only build validates the description it is given.
  static_assert(!TakesALayout<ForestLayout>::value, "the stored-layout overload is gone");
  SUCCEED();
}

TEST_F(Validation, MaxLevelsBeyondWhatTheFiltersWalk)
{
  EXPECT_EQ(maxSupportedLevels(2), 62);
  EXPECT_EQ(maxSupportedLevels(3), 39);
  d().maxLevels = 63;
  expectRejected({"maxLevels must be in [1, 62] for branch factor 2, got 63"});
  d().branchFactor = 3;
  d().maxLevels = 40;
  expectRejected({"maxLevels must be in [1, 39] for branch factor 3, got 40"});
}

TEST_F(Validation, RootCellCountOverflowingSixtyFourBits)
{
  // 2^22 x 2^22 x 2^20 root cells: 2^64, which wraps to 0 in 64-bit arithmetic.
  ForestDescription forest;
  forest.dimension = 3;
  forest.maxLevels = 2;
  std::vector<double> xy((1u << 22) + 1);
  std::vector<double> z((1u << 20) + 1);
  std::iota(xy.begin(), xy.end(), 0.0);
  std::iota(z.begin(), z.end(), 0.0);
  forest.rootGrid = {xy.data(), xy.data(), z.data(), xy.size(), xy.size(), z.size()};
  try
  {
    validateForest(forest);
    FAIL() << "an overflowing root grid was accepted";
  }
  catch (const InvalidForest& e)
  {
    EXPECT_NE(std::string(e.what()).find("root cells overflow a 64-bit cell index"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(Validation, UnknownRequestedField)
{
  try
  {
    buildHyperTreeGrid(d(), FieldRequest::only({"Density"}));
    FAIL() << "should throw";
  }
  catch (const InvalidForest& e)
  {
    EXPECT_NE(std::string(e.what()).find("requested field 'Density' is not in the forest"),
              std::string::npos);
  }
}

} // namespace
} // namespace canopy::testing

namespace canopy::testing
{
namespace
{

TEST(RankWithoutTrees, NullFieldsOfEveryLayoutBuildAnEmptyGrid)
{
  // A rank owning no tree passes no memory: null pointers with zero tuples, in
  // every layout and centering (no pointer arithmetic on null; UBSan checks it).
  const std::vector<double> x{0, 1, 2}, y{0, 1}, z{0};
  ForestDescription forest;
  forest.dimension = 2;
  forest.maxLevels = 3;
  forest.rootGrid = {x.data(), y.data(), z.data(), x.size(), y.size(), z.size()};
  forest.fields.push_back(FieldDescription::aos<double>("aos", nullptr, 0, 3));
  forest.fields.push_back(
      FieldDescription::aos<float>("leaves", nullptr, 0, 3, Centering::LeavesOnly));
  forest.fields.push_back(FieldDescription::strided<double>("strided", nullptr, 40, 0, 3));
  forest.fields.push_back(FieldDescription::strided<double>("strided_leaves", nullptr, 40, 0, 2,
                                                            Centering::LeavesOnly));
  forest.fields.push_back(FieldDescription::soa<double>("soa", {nullptr, nullptr}, 0));
  forest.fields.push_back(FieldDescription::indirect<std::int64_t>("indirect", nullptr, 0, 2));
  const auto htg = buildHyperTreeGrid(forest);
  EXPECT_EQ(htg->GetNumberOfCells(), 0);
  for (const auto& field : forest.fields)
  {
    vtkDataArray* array = htg->GetCellData()->GetArray(field.name.c_str());
    ASSERT_NE(array, nullptr) << field.name;
    EXPECT_EQ(array->GetNumberOfTuples(), 0) << field.name;
    EXPECT_EQ(array->GetNumberOfComponents(), field.components) << field.name;
  }
}

} // namespace
} // namespace canopy::testing
