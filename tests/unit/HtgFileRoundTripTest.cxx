// The synthetic forest (the benchmarks' load), written by tools/HtgFileWriter and
// read back with the reader ParaView uses, is the same grid: every node that a
// cursor can reach has the same topology, mask and field values (vectors come
// back as one scalar array per component, see HtgFileWriter.h for why).
#include "HtgFileWriter.h"
#include "SyntheticForest.h"

#include "canopy/HtgBuilder.h"

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

struct Totals
{
  std::size_t nodes = 0;
  std::size_t masked = 0;
};

void compare(vtkHyperTreeGridNonOrientedGeometryCursor* a,
             vtkHyperTreeGridNonOrientedGeometryCursor* b, vtkHyperTreeGrid* ga,
             vtkHyperTreeGrid* gb, Totals& totals)
{
  ++totals.nodes;
  ASSERT_EQ(a->IsMasked(), b->IsMasked());
  // The writer prunes masked subtrees: a masked node may come back as a leaf.
  if (!a->IsMasked())
  {
    ASSERT_EQ(a->IsLeaf(), b->IsLeaf());
  }
  ASSERT_EQ(a->GetLevel(), b->GetLevel());
  for (const char* name : {"density", "velocity", "refinementLevel", "pressure"})
  {
    vtkDataArray* va = ga->GetCellData()->GetArray(name);
    const int components = va->GetNumberOfComponents();
    for (int c = 0; c < components; ++c)
    {
      const std::string fileName =
          components == 1 ? name : tools::componentArrayName(name, c, components);
      vtkDataArray* vb = gb->GetCellData()->GetArray(fileName.c_str());
      ASSERT_NE(vb, nullptr) << fileName;
      ASSERT_EQ(vb->GetNumberOfComponents(), 1);
      ASSERT_EQ(va->GetComponent(a->GetGlobalNodeIndex(), c),
                vb->GetComponent(b->GetGlobalNodeIndex(), 0))
          << fileName;
    }
  }
  if (a->IsMasked())
  {
    ++totals.masked;
    return;
  }
  if (a->IsLeaf())
  {
    return;
  }
  for (unsigned char c = 0; c < a->GetNumberOfChildren(); ++c)
  {
    a->ToChild(c);
    b->ToChild(c);
    compare(a, b, ga, gb, totals);
    a->ToParent();
    b->ToParent();
  }
}

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
  ASSERT_EQ(tools::writeHtgFile(built, file.string()), "");
  // The grid itself keeps its vector array.
  ASSERT_EQ(built->GetCellData()->GetArray("velocity")->GetNumberOfComponents(), 3);

  vtkNew<vtkXMLHyperTreeGridReader> reader;
  reader->SetFileName(file.string().c_str());
  reader->Update();
  vtkHyperTreeGrid* read = reader->GetOutput();
  ASSERT_EQ(read->GetDimension(), built->GetDimension());
  ASSERT_EQ(read->GetBranchFactor(), built->GetBranchFactor());
  ASSERT_EQ(read->HasMask(), options.cutaway);

  Totals totals;
  vtkHyperTreeGrid::vtkHyperTreeGridIterator trees;
  built->InitializeTreeIterator(trees);
  vtkIdType index = 0;
  std::size_t treeCount = 0;
  while (trees.GetNextTree(index))
  {
    ++treeCount;
    vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> a;
    vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> b;
    built->InitializeNonOrientedGeometryCursor(a, index);
    read->InitializeNonOrientedGeometryCursor(b, index);
    compare(a, b, built, read, totals);
  }
  EXPECT_EQ(treeCount, forest.description().trees.size());
  // The file keeps what a cursor reaches: masked subtrees are pruned on write.
  EXPECT_EQ(static_cast<std::size_t>(read->GetNumberOfCells()), totals.nodes);
  if (options.cutaway)
  {
    EXPECT_GT(totals.masked, 0u) << "the cut-away should mask something";
    EXPECT_LT(totals.nodes, forest.numberOfNodes());
  }
  else
  {
    EXPECT_EQ(totals.nodes, forest.numberOfNodes());
  }
  std::filesystem::remove(file);
}

INSTANTIATE_TEST_SUITE_P(DimensionsAndMask, HtgFileRoundTrip,
                         ::testing::Combine(::testing::Values(2, 3), ::testing::Bool()));

} // namespace
} // namespace canopy::testing
