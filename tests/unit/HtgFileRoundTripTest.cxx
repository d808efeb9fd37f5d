// The synthetic forest (the benchmarks' load), written by Canopy's .htg writer
// (adaptor/io/HtgFileWriter) and read back with the reader ParaView 5.11 uses,
// is the same grid: every node has the same topology, mask and field values,
// vector fields included, masked subtrees included.
#include "SameGrid.h"
#include "SyntheticForest.h"

#include <canopy/io/HtgFileWriter.h>
#include <canopy/io/HyperTreeGridPiece.h>

#include <canopy/HtgBuilder.h>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkNew.h>
#include <vtkXMLHyperTreeGridReader.h>

#include <filesystem>
#include <tuple>

namespace canopy::testing
{
namespace
{

class HtgFileRoundTrip : public ::testing::TestWithParam<std::tuple<int, bool>>
{
};

TEST_P(HtgFileRoundTrip, ReaderSeesTheBuiltGrid)
{
  tools::SyntheticForestOptions options;
  options.dimension = std::get<0>(GetParam());
  options.cutaway = std::get<1>(GetParam());
  options.branchFactor = options.dimension == 2 ? 3 : 2;
  options.rootsPerAxis = 3;
  options.maxLevels = 5;
  tools::SyntheticForest forest(options);
  auto built = buildHyperTreeGrid(forest.description());

  const auto file = std::filesystem::temp_directory_path() /
                    ("canopy_roundtrip_" + std::to_string(options.dimension) +
                     (options.cutaway ? "_masked" : "") + ".htg");
  ASSERT_EQ(io::writeHtgFile(built, file.string()), "");
  // The grid itself keeps its vector array.
  ASSERT_EQ(built->GetCellData()->GetArray("velocity")->GetNumberOfComponents(), 3);

  vtkNew<vtkXMLHyperTreeGridReader> reader;
  reader->SetFileName(file.string().c_str());
  reader->Update();
  vtkHyperTreeGrid* read = reader->GetOutput();
  ASSERT_EQ(read->HasMask(), options.cutaway);
  const auto totals =
      expectSameGrid(built, read, {"density", "velocity", "refinementLevel", "pressure"});
  EXPECT_EQ(totals.trees, forest.description().trees.size());
  EXPECT_EQ(totals.masked > 0, options.cutaway) << "the cut-away masks cells, nothing else does";

  // Every node, masked subtrees included: the same trees, breadth-first refinement,
  // cells per level, mask, and the same values at every cell.
  EXPECT_EQ(static_cast<std::size_t>(read->GetNumberOfCells()), forest.numberOfNodes());
  const auto before = io::HyperTreeGridPiece::describe(built);
  const auto after = io::HyperTreeGridPiece::describe(read);
  EXPECT_EQ(after.treeIds, before.treeIds);
  EXPECT_EQ(after.cellsPerTreeDepth, before.cellsPerTreeDepth);
  EXPECT_EQ(after.descriptors.bytes(), before.descriptors.bytes());
  EXPECT_EQ(after.mask.bytes(), before.mask.bytes());
  ASSERT_EQ(after.runs.size(), 1u) << "cells read back breadth-first, tree by tree";
  for (const char* name : {"density", "velocity", "refinementLevel", "pressure"})
  {
    vtkDataArray* va = built->GetCellData()->GetArray(name);
    vtkDataArray* vb = read->GetCellData()->GetArray(name);
    for (vtkIdType cell = 0; cell < read->GetNumberOfCells(); ++cell)
    {
      for (int c = 0; c < va->GetNumberOfComponents(); ++c)
      {
        ASSERT_EQ(va->GetComponent(cell, c), vb->GetComponent(cell, c))
            << name << " cell " << cell << " component " << c;
      }
    }
  }
  std::filesystem::remove(file);
}

INSTANTIATE_TEST_SUITE_P(DimensionsAndMask, HtgFileRoundTrip,
                         ::testing::Combine(::testing::Values(2, 3), ::testing::Bool()));

} // namespace
} // namespace canopy::testing
