// A grid packed for Catalyst Live (vtkCanopyHyperTreeGridPacker) and unpacked
// in the viewer (vtkCanopyHyperTreeGridUnpacker) is the same grid, node by
// node, masks and vector fields included; bytes that are not packed pieces are
// refused saying where. Several ranks' pieces: live.miniapp_np2.
#include "ErrorMessages.h"
#include "SameGrid.h"
#include "SyntheticForest.h"

#include <canopy/HtgBuilder.h>

#include <canopy/io/vtkCanopyHyperTreeGridPacker.h>
#include <canopy/io/vtkCanopyHyperTreeGridUnpacker.h>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkFieldData.h>
#include <vtkHyperTreeGrid.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <cstring>
#include <tuple>

namespace canopy::testing
{
namespace
{

const std::vector<const char*> Fields = {"density", "velocity", "refinementLevel", "pressure"};

tools::SyntheticForestOptions forestOptions(int dimension, bool cutaway)
{
  tools::SyntheticForestOptions options;
  options.dimension = dimension;
  options.cutaway = cutaway;
  options.branchFactor = dimension == 2 ? 3 : 2;
  options.rootsPerAxis = 3;
  options.maxLevels = 5;
  return options;
}

class PackedGrid : public ::testing::TestWithParam<std::tuple<int, bool>>
{
};

TEST_P(PackedGrid, UnpackedIsTheSameGrid)
{
  tools::SyntheticForest forest(forestOptions(std::get<0>(GetParam()), std::get<1>(GetParam())));
  auto built = buildHyperTreeGrid(forest.description());

  vtkNew<vtkCanopyHyperTreeGridPacker> packer;
  packer->SetInputData(built);
  packer->Update();
  auto* packed = packer->GetOutput();
  // What crosses the socket: one point holding every piece's bytes.
  ASSERT_EQ(packed->GetNumberOfPoints(), 1);
  auto* bytes = vtkUnsignedCharArray::SafeDownCast(
      packed->GetFieldData()->GetArray(vtkCanopyHyperTreeGridPacker::ArrayName()));
  ASSERT_NE(bytes, nullptr);
  EXPECT_EQ(bytes->GetNumberOfValues(), packer->GetTotalBytes());
  EXPECT_EQ(packer->GetLocalBytes(), packer->GetTotalBytes()) << "one rank: one piece";
  ASSERT_GT(bytes->GetNumberOfValues(), 12);
  EXPECT_EQ(std::memcmp(bytes->GetPointer(0), "CNPY", 4), 0);

  vtkNew<vtkCanopyHyperTreeGridUnpacker> unpacker;
  unpacker->SetInputData(packed);
  ASSERT_TRUE(errorsOfUpdate(unpacker).empty());
  auto* blocks = vtkMultiBlockDataSet::SafeDownCast(unpacker->GetOutputDataObject(0));
  ASSERT_EQ(blocks->GetNumberOfBlocks(), 1u);
  EXPECT_EQ(unpacker->GetNumberOfPieces(), 1u);
  auto* grid = vtkHyperTreeGrid::SafeDownCast(blocks->GetBlock(0));
  ASSERT_NE(grid, nullptr);
  EXPECT_EQ(grid->GetNumberOfCells(), built->GetNumberOfCells());
  const auto totals = expectSameGrid(built, grid, Fields);
  EXPECT_EQ(totals.trees, forest.description().trees.size());
  EXPECT_EQ(totals.masked > 0, std::get<1>(GetParam()));
}

INSTANTIATE_TEST_SUITE_P(DimensionsAndMask, PackedGrid,
                         ::testing::Combine(::testing::Values(2, 3), ::testing::Bool()));

TEST(PackedGridBytes, AreRefusedWhenNotPackedPiecesSayingWhere)
{
  tools::SyntheticForest forest(forestOptions(2, false));
  auto built = buildHyperTreeGrid(forest.description());
  vtkNew<vtkCanopyHyperTreeGridPacker> packer;
  packer->SetInputData(built);
  packer->Update();
  vtkNew<vtkPolyData> packed;
  packed->DeepCopy(packer->GetOutput());
  auto* bytes = vtkUnsignedCharArray::SafeDownCast(
      packed->GetFieldData()->GetArray(vtkCanopyHyperTreeGridPacker::ArrayName()));
  bytes->SetValue(0, 'X');

  vtkNew<vtkCanopyHyperTreeGridUnpacker> unpacker;
  unpacker->SetInputData(packed);
  const auto errors = errorsOfUpdate(unpacker);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("byte 0 of " + std::to_string(bytes->GetNumberOfValues()) +
                           ": not the start of a packed piece"),
            std::string::npos)
      << errors[0];
  EXPECT_EQ(
      vtkMultiBlockDataSet::SafeDownCast(unpacker->GetOutputDataObject(0))->GetNumberOfBlocks(),
      0u);

  // A polydata that never was packed: said so.
  vtkNew<vtkPolyData> other;
  other->DeepCopy(packed);
  other->GetFieldData()->RemoveArray(vtkCanopyHyperTreeGridPacker::ArrayName());
  unpacker->SetInputData(other);
  const auto unrelated = errorsOfUpdate(unpacker);
  ASSERT_EQ(unrelated.size(), 1u);
  EXPECT_NE(unrelated[0].find("it is not the output of vtkCanopyHyperTreeGridPacker"),
            std::string::npos)
      << unrelated[0];
}

TEST(PackedGridBytes, NothingYetUnpacksToNothing)
{
  // A Live extract before its first delivery is an empty polydata.
  vtkNew<vtkPolyData> nothing;
  vtkNew<vtkCanopyHyperTreeGridUnpacker> unpacker;
  unpacker->SetInputData(nothing);
  EXPECT_TRUE(errorsOfUpdate(unpacker).empty());
  EXPECT_EQ(
      vtkMultiBlockDataSet::SafeDownCast(unpacker->GetOutputDataObject(0))->GetNumberOfBlocks(),
      0u);
}

TEST(PackedGridBytes, AGridThatWasNeverPackedIsPassedOnInPlace)
{
  tools::SyntheticForest forest(forestOptions(3, true));
  auto built = buildHyperTreeGrid(forest.description());
  vtkNew<vtkCanopyHyperTreeGridUnpacker> unpacker;
  unpacker->SetInputData(built);
  EXPECT_TRUE(errorsOfUpdate(unpacker).empty());
  auto* blocks = vtkMultiBlockDataSet::SafeDownCast(unpacker->GetOutputDataObject(0));
  ASSERT_EQ(blocks->GetNumberOfBlocks(), 1u);
  auto* grid = vtkHyperTreeGrid::SafeDownCast(blocks->GetBlock(0));
  ASSERT_NE(grid, nullptr);
  // The same arrays, not copies.
  EXPECT_EQ(grid->GetCellData()->GetArray("density"), built->GetCellData()->GetArray("density"));
  EXPECT_EQ(grid->GetNumberOfCells(), built->GetNumberOfCells());
}

} // namespace
} // namespace canopy::testing
