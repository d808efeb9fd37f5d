// canopy::io::HyperTreeGridPiece on a grid whose trees map their nodes to cells
// through a per-node table (VTK's explicit global indices, as readers and other
// producers build them) rather than Canopy's implicit breadth-first numbering:
// the writers must still fetch each node's own cell, trees in memory order.
#include <canopy/io/HyperTreeGridPiece.h>

#include <gtest/gtest.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedCursor.h>
#include <vtkNew.h>

#include <vector>

namespace canopy::testing
{
namespace
{

TEST(HyperTreeGridPiece, ExplicitGlobalIndicesGiveEachNodesOwnCell)
{
  vtkNew<vtkHyperTreeGrid> htg;
  htg->SetDimensions(3, 2, 1); // two 2D roots along x
  htg->SetBranchFactor(2);

  // Tree 0: the root refined, its second child refined again; cells numbered
  // backwards from 20 in breadth-first order. Tree 1: a leaf root at cell 5.
  vtkNew<vtkHyperTreeGridNonOrientedCursor> cursor;
  htg->InitializeNonOrientedCursor(cursor, 0, true);
  cursor->SetGlobalIndexFromLocal(20);
  cursor->SubdivideLeaf();
  for (unsigned char child = 0; child < 4; ++child)
  {
    cursor->ToChild(child);
    cursor->SetGlobalIndexFromLocal(19 - child);
    cursor->ToParent();
  }
  cursor->ToChild(1);
  cursor->SubdivideLeaf();
  for (unsigned char child = 0; child < 4; ++child)
  {
    cursor->ToChild(child);
    cursor->SetGlobalIndexFromLocal(15 - child);
    cursor->ToParent();
  }
  htg->InitializeNonOrientedCursor(cursor, 1, true);
  cursor->SetGlobalIndexFromLocal(5);
  ASSERT_LT(htg->GetTree(0)->GetGlobalIndexStart(), 0) << "tree 0 uses a per-node table";

  const auto piece = io::HyperTreeGridPiece::describe(htg);
  EXPECT_EQ(piece.treeIds, (std::vector<std::int64_t>{1, 0})) << "trees by their first cell";
  EXPECT_EQ(piece.depthPerTree, (std::vector<std::int64_t>{1, 3}));
  EXPECT_EQ(piece.cellsPerTreeDepth, (std::vector<std::int64_t>{1, 1, 4, 4}));
  EXPECT_EQ(piece.numberOfCells, 10);
  EXPECT_EQ(piece.numberOfLeaves, 8);
  // Tree 1 has no descriptor bits (one level); tree 0: root 1, children 0 1 0 0.
  ASSERT_EQ(piece.descriptors.size(), 5);
  EXPECT_EQ(piece.descriptors.bytes(), (std::vector<unsigned char>{0xA0}));
  std::vector<vtkIdType> cells;
  for (const auto& run : piece.runs)
  {
    for (vtkIdType c = 0; c < run.count; ++c)
    {
      cells.push_back(run.first + c);
    }
  }
  EXPECT_EQ(cells, (std::vector<vtkIdType>{5, 20, 19, 18, 17, 16, 15, 14, 13, 12}));
  EXPECT_FALSE(piece.contiguous());
}

} // namespace
} // namespace canopy::testing
