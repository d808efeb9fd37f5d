// Wrap cost per cell: Canopy's zero-copy build against the obvious alternative
// (walk each tree with a vtkHyperTreeGrid cursor, SubdivideLeaf where the
// simulation refined, copy every field value into new VTK arrays), in one run,
// on the same forests, 1e5 to 1e7 cells.
//
// Usage: canopy_bench_wrap [--max-levels L] [--csv FILE] [--repetitions R]
// Prints a Markdown table: ns per cell for both, their ratio, heap bytes each
// build adds per cell while its grid is alive, and field bytes copied per cell.
#include "SyntheticForest.h"

#include "canopy/GridBuilder.h"
#include "canopy/HtgBuilder.h"

#include <vtkBitArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedCursor.h>
#include <vtkIntArray.h>
#include <vtkNew.h>

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

namespace
{

using Clock = std::chrono::steady_clock;
using canopy::tools::SyntheticForest;

/// Heap bytes in use (small blocks + mmapped blocks).
std::size_t heapInUse()
{
  const struct mallinfo2 info = mallinfo2();
  return info.uordblks + info.hblkhd;
}

const std::vector<std::string> Fields{"density", "velocity", "refinementLevel"};

/// The obvious adaptor: cursor build plus field copies. Values land at the
/// global index VTK gives each node.
vtkSmartPointer<vtkHyperTreeGrid> buildByCursorAndCopy(const SyntheticForest& forest)
{
  const canopy::ForestDescription& d = forest.description();
  auto htg = vtkSmartPointer<vtkHyperTreeGrid>::New();
  const auto& g = d.rootGrid;
  htg->SetDimensions(static_cast<unsigned>(g.pointsX), static_cast<unsigned>(g.pointsY),
                     static_cast<unsigned>(g.pointsZ));
  htg->SetBranchFactor(static_cast<unsigned>(d.branchFactor));
  for (int a = 0; a < 3; ++a)
  {
    const double* c = a == 0 ? g.x : a == 1 ? g.y : g.z;
    const std::size_t n = a == 0 ? g.pointsX : a == 1 ? g.pointsY : g.pointsZ;
    vtkNew<vtkDoubleArray> coords;
    coords->SetNumberOfTuples(static_cast<vtkIdType>(n));
    std::copy(c, c + n, coords->GetPointer(0));
    a == 0   ? htg->SetXCoordinates(coords)
    : a == 1 ? htg->SetYCoordinates(coords)
             : htg->SetZCoordinates(coords);
  }
  const auto total = static_cast<vtkIdType>(forest.numberOfNodes());
  vtkNew<vtkDoubleArray> density;
  density->SetName("density");
  density->SetNumberOfTuples(total);
  vtkNew<vtkDoubleArray> velocity;
  velocity->SetName("velocity");
  velocity->SetNumberOfComponents(3);
  velocity->SetNumberOfTuples(total);
  vtkNew<vtkIntArray> level;
  level->SetName("refinementLevel");
  level->SetNumberOfTuples(total);
  const auto& cells = forest.cells();

  vtkIdType offset = 0;
  vtkNew<vtkHyperTreeGridNonOrientedCursor> cursor;
  std::vector<std::size_t> firstChild;
  for (const canopy::TreeDescription& tree : d.trees)
  {
    const std::size_t perNode = htg->GetNumberOfChildren();
    firstChild.assign(tree.numberOfNodes, 0);
    std::size_t next = 1;
    for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
    {
      if (tree.refinement[n])
      {
        firstChild[n] = next;
        next += perNode;
      }
    }
    htg->InitializeNonOrientedCursor(cursor, tree.rootIndex, /*create=*/true);
    cursor->SetGlobalIndexStart(offset);
    auto visit = [&](auto& self, std::size_t n) -> void
    {
      const vtkIdType global = cursor->GetGlobalNodeIndex();
      const std::size_t slot = tree.storageSlots ? static_cast<std::size_t>(tree.storageSlots[n])
                                                 : static_cast<std::size_t>(offset) + n;
      const SyntheticForest::CellRecord& cell = cells[slot];
      density->SetValue(global, cell.density);
      velocity->SetTypedTuple(global, cell.velocity);
      level->SetValue(global, cell.refinementLevel);
      if (!tree.refinement[n])
      {
        return;
      }
      cursor->SubdivideLeaf();
      for (unsigned char c = 0; c < perNode; ++c)
      {
        cursor->ToChild(c);
        self(self, firstChild[n] + c);
        cursor->ToParent();
      }
    };
    visit(visit, 0);
    offset += static_cast<vtkIdType>(tree.numberOfNodes);
  }
  htg->GetCellData()->AddArray(density);
  htg->GetCellData()->AddArray(velocity);
  htg->GetCellData()->AddArray(level);
  return htg;
}

/// Bytes of cell-field values the grid holds outside the simulation's records.
std::size_t copiedFieldBytes(vtkHyperTreeGrid* htg, const SyntheticForest& forest)
{
  const auto* begin = reinterpret_cast<const char*>(forest.cells().data());
  const auto* end = begin + forest.cells().size() * sizeof(SyntheticForest::CellRecord);
  std::size_t copied = 0;
  for (int a = 0; a < htg->GetCellData()->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = htg->GetCellData()->GetArray(a);
    // Only AoS arrays expose a pointer without side effects; Canopy's strided
    // arrays borrow by construction (checked by the unit tests), so count the
    // ones whose storage is a VTK-owned AoS buffer outside the records.
    if (auto* aos = vtkDoubleArray::SafeDownCast(array))
    {
      const auto* p = reinterpret_cast<const char*>(aos->GetPointer(0));
      copied += (p >= begin && p < end) ? 0 : static_cast<std::size_t>(aos->GetDataSize()) * 8;
    }
    else if (auto* ints = vtkIntArray::SafeDownCast(array))
    {
      const auto* p = reinterpret_cast<const char*>(ints->GetPointer(0));
      copied += (p >= begin && p < end) ? 0 : static_cast<std::size_t>(ints->GetDataSize()) * 4;
    }
  }
  return copied;
}

struct Measurement
{
  double nsPerCell = 0;
  double bytesPerCell = 0;
  double fieldBytesPerCell = 0;
};

template <typename Build>
Measurement measure(const SyntheticForest& forest, int repetitions, Build&& build)
{
  std::vector<double> times;
  Measurement m;
  const double cells = static_cast<double>(forest.numberOfNodes());
  for (int r = 0; r < repetitions; ++r)
  {
    malloc_trim(0);
    const std::size_t before = heapInUse();
    const auto start = Clock::now();
    vtkSmartPointer<vtkHyperTreeGrid> htg = build();
    const double ns = std::chrono::duration<double, std::nano>(Clock::now() - start).count();
    times.push_back(ns / cells);
    const std::size_t after = heapInUse();
    m.bytesPerCell = static_cast<double>(after > before ? after - before : 0) / cells;
    m.fieldBytesPerCell = static_cast<double>(copiedFieldBytes(htg, forest)) / cells;
    if (htg->GetNumberOfCells() != static_cast<vtkIdType>(forest.numberOfNodes()))
    {
      std::cerr << "bench: wrong number of cells\n";
      std::exit(1);
    }
  }
  std::sort(times.begin(), times.end());
  m.nsPerCell = times[times.size() / 2];
  return m;
}

/// Both grids must hold the same values at the same nodes, or the timing means nothing.
bool sameContent(vtkHyperTreeGrid* a, vtkHyperTreeGrid* b)
{
  vtkHyperTreeGrid::vtkHyperTreeGridIterator trees;
  a->InitializeTreeIterator(trees);
  vtkIdType index = 0;
  vtkNew<vtkHyperTreeGridNonOrientedCursor> ca;
  vtkNew<vtkHyperTreeGridNonOrientedCursor> cb;
  bool same = true;
  int checked = 0;
  while (trees.GetNextTree(index) && same)
  {
    a->InitializeNonOrientedCursor(ca, index);
    b->InitializeNonOrientedCursor(cb, index);
    auto walk = [&](auto& self) -> void
    {
      for (const auto& name : Fields)
      {
        vtkDataArray* fa = a->GetCellData()->GetArray(name.c_str());
        vtkDataArray* fb = b->GetCellData()->GetArray(name.c_str());
        for (int c = 0; c < fa->GetNumberOfComponents(); ++c)
        {
          same = same && fa->GetComponent(ca->GetGlobalNodeIndex(), c) ==
                             fb->GetComponent(cb->GetGlobalNodeIndex(), c);
        }
      }
      ++checked;
      same = same && ca->IsLeaf() == cb->IsLeaf();
      if (!same || ca->IsLeaf())
      {
        return;
      }
      for (unsigned char c = 0; c < ca->GetNumberOfChildren(); ++c)
      {
        ca->ToChild(c);
        cb->ToChild(c);
        self(self);
        ca->ToParent();
        cb->ToParent();
      }
    };
    walk(walk);
  }
  return same && checked > 0;
}

/// What VTK's own primitives cost here, so the table can be read against a floor:
/// creating a tree, building it from a breadth-first descriptor, and filling an
/// explicit global-index table (first fill and overwrite).
void printVtkFloor()
{
  const int coarse = 37449; // full octree of 7 levels: nodes above the deepest level
  const int nodes = 299593; // all nodes
  vtkNew<vtkBitArray> bits;
  bits->SetNumberOfValues(coarse);
  for (int i = 0; i < coarse; ++i)
  {
    bits->SetValue(i, 1);
  }
  auto ns = [](Clock::time_point a, Clock::time_point b)
  { return std::chrono::duration<double, std::nano>(b - a).count(); };
  vtkNew<vtkHyperTreeGrid> one;
  one->SetDimensions(2, 2, 2);
  one->SetBranchFactor(2);
  const auto t0 = Clock::now();
  vtkHyperTree* tree = one->GetTree(0, true);
  tree->BuildFromBreadthFirstOrderDescriptor(bits, coarse, 0);
  const auto t1 = Clock::now();
  tree->SetGlobalIndexFromLocal(nodes - 1, nodes - 1);
  for (vtkIdType n = 0; n < nodes; ++n)
  {
    tree->SetGlobalIndexFromLocal(n, n);
  }
  const auto t2 = Clock::now();
  for (vtkIdType n = 0; n < nodes; ++n)
  {
    tree->SetGlobalIndexFromLocal(n, nodes - n);
  }
  const auto t3 = Clock::now();
  vtkNew<vtkHyperTreeGrid> many;
  many->SetDimensions(101, 101, 2);
  many->SetBranchFactor(2);
  const auto t4 = Clock::now();
  for (vtkIdType t = 0; t < 10000; ++t)
  {
    many->GetTree(t, true);
  }
  const auto t5 = Clock::now();
  std::cout << std::fixed << std::setprecision(2)
            << "\nVTK primitives on this machine (one full 7-level octree, " << nodes
            << " nodes):\n"
            << "- vtkHyperTree::BuildFromBreadthFirstOrderDescriptor: " << ns(t0, t1) / nodes
            << " ns/node\n"
            << "- vtkHyperTree::SetGlobalIndexFromLocal, first fill: " << ns(t1, t2) / nodes
            << " ns/node; overwrite: " << ns(t2, t3) / nodes << " ns/node\n"
            << "- vtkHyperTreeGrid::GetTree(index, create=true): " << ns(t4, t5) / 10000
            << " ns/tree\n";
}

/// Median over `repetitions` of one call, in ns per cell.
template <typename Call>
double medianNsPerCell(double cells, int repetitions, Call&& call)
{
  std::vector<double> times;
  for (int r = 0; r < repetitions; ++r)
  {
    const auto start = Clock::now();
    call();
    times.push_back(std::chrono::duration<double, std::nano>(Clock::now() - start).count() / cells);
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

/// Steps after the first with canopy::GridBuilder: nothing changed, one mask byte
/// changed (trees kept, mask and tables redone), two trees changed (two trees of
/// the same size swap their refinement, so the fields still fit).
void printStepRow(const SyntheticForest& forest, const char* storage, int repetitions)
{
  const auto request = canopy::FieldRequest::only(Fields);
  const double cells = static_cast<double>(forest.numberOfNodes());
  canopy::ForestDescription d = forest.description();
  canopy::GridBuilder builder;
  const double full = medianNsPerCell(cells, repetitions,
                                      [&]
                                      {
                                        builder.reset();
                                        builder.build(d, request);
                                      });
  builder.build(d, request);
  const double unchanged = medianNsPerCell(cells, repetitions, [&] { builder.build(d, request); });
  const auto* reuse = &builder.lastBuild();
  if (reuse->treesRebuilt != 0)
  {
    std::cerr << "bench: an unchanged step rebuilt trees\n";
    std::exit(1);
  }
  // One mask byte: a private copy of tree 0's mask (or a new mask) with one byte flipped.
  std::vector<std::uint8_t> mask(d.trees[0].numberOfNodes, 0);
  if (d.trees[0].masked)
  {
    std::copy(d.trees[0].masked, d.trees[0].masked + mask.size(), mask.begin());
  }
  const std::uint8_t* originalMask = d.trees[0].masked;
  const double maskChanged = medianNsPerCell(cells, repetitions,
                                             [&]
                                             {
                                               mask.back() ^= 1;
                                               d.trees[0].masked = mask.data();
                                               builder.build(d, request);
                                             });
  d.trees[0].masked = originalMask;
  builder.build(d, request);
  // Two trees with the same node count and different refinement.
  std::size_t a = 0;
  std::size_t b = 0;
  for (std::size_t i = 0; i < d.trees.size() && !b; ++i)
    for (std::size_t j = i + 1; j < d.trees.size() && !b; ++j)
      if (d.trees[i].numberOfNodes == d.trees[j].numberOfNodes && d.trees[i].numberOfNodes > 1 &&
          std::memcmp(d.trees[i].refinement, d.trees[j].refinement, d.trees[i].numberOfNodes) !=
              0 &&
          !d.trees[i].storageSlots)
      {
        a = i;
        b = j;
      }
  double twoChanged = -1;
  if (b != 0)
  {
    twoChanged = medianNsPerCell(cells, repetitions,
                                 [&]
                                 {
                                   std::swap(d.trees[a].refinement, d.trees[b].refinement);
                                   builder.build(d, request);
                                 });
  }
  std::cout << std::fixed << std::setprecision(2) << "| " << storage << " | "
            << forest.numberOfNodes() << " | " << full << " | " << unchanged << " ("
            << std::setprecision(1) << 100 * unchanged / full << "%) | " << std::setprecision(2)
            << maskChanged << " (" << std::setprecision(1) << 100 * maskChanged / full << "%) | ";
  if (twoChanged >= 0)
    std::cout << std::setprecision(2) << twoChanged << " (" << std::setprecision(1)
              << 100 * twoChanged / full << "%) |\n";
  else
    std::cout << "n/a (no two trees of equal size) |\n";
}

} // namespace

int main(int argc, char** argv)
{
  int maxLevels = 8;
  int repetitions = 5;
  std::string csvPath;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--max-levels" && i + 1 < argc)
      maxLevels = std::atoi(argv[++i]);
    else if (arg == "--repetitions" && i + 1 < argc)
      repetitions = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--csv" && i + 1 < argc)
      csvPath = argv[++i];
    else
    {
      std::cerr << "usage: canopy_bench_wrap [--max-levels L] [--repetitions R] [--csv FILE]\n";
      return 2;
    }
  }

  std::ofstream csv;
  if (!csvPath.empty())
  {
    csv.open(csvPath);
    csv << "storage,levels,cells,canopy_ns_per_cell,cursor_copy_ns_per_cell,speedup,"
           "canopy_bytes_per_cell,cursor_copy_bytes_per_cell,canopy_field_bytes_copied_per_"
           "cell,cursor_copy_field_bytes_copied_per_cell\n";
  }
  std::cout << "| storage | cells | Canopy ns/cell | cursor+copy ns/cell | speedup | Canopy "
               "bytes/cell | cursor+copy bytes/cell | field bytes copied/cell (Canopy / "
               "cursor+copy) |\n"
            << "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (bool depthFirst : {false, true})
  {
    for (int levels = 5; levels <= maxLevels; ++levels)
    {
      canopy::tools::SyntheticForestOptions options;
      options.dimension = 3;
      options.branchFactor = 2;
      options.rootsPerAxis = 6;
      options.maxLevels = levels;
      options.cutaway = false;
      options.depthFirstStorage = depthFirst;
      SyntheticForest forest(options);
      const int reps = forest.numberOfNodes() > 5'000'000 ? std::min(repetitions, 3) : repetitions;

      const auto request = canopy::FieldRequest::only(Fields);
      const Measurement canopyBuild = measure(
          forest, reps, [&] { return canopy::buildHyperTreeGrid(forest.description(), request); });
      const Measurement cursorBuild =
          measure(forest, reps, [&] { return buildByCursorAndCopy(forest); });
      auto a = canopy::buildHyperTreeGrid(forest.description(), request);
      auto b = buildByCursorAndCopy(forest);
      if (!sameContent(a, b))
      {
        std::cerr << "bench: the two builds disagree; timings are meaningless\n";
        return 1;
      }
      const double speedup = cursorBuild.nsPerCell / canopyBuild.nsPerCell;
      const char* storage = depthFirst ? "depth-first + slot map" : "breadth-first";
      std::cout << std::fixed << "| " << storage << " | " << forest.numberOfNodes() << " | "
                << std::setprecision(2) << canopyBuild.nsPerCell << " | " << cursorBuild.nsPerCell
                << " | " << std::setprecision(1) << speedup << "x | " << std::setprecision(2)
                << canopyBuild.bytesPerCell << " | " << cursorBuild.bytesPerCell << " | "
                << std::setprecision(0) << canopyBuild.fieldBytesPerCell << " / "
                << cursorBuild.fieldBytesPerCell << " |" << std::endl;
      if (csv)
      {
        csv << (depthFirst ? "depth-first" : "breadth-first") << "," << levels << ","
            << forest.numberOfNodes() << "," << canopyBuild.nsPerCell << ","
            << cursorBuild.nsPerCell << "," << speedup << "," << canopyBuild.bytesPerCell << ","
            << cursorBuild.bytesPerCell << "," << canopyBuild.fieldBytesPerCell << ","
            << cursorBuild.fieldBytesPerCell << "\n";
      }
    }
  }
  std::cout << "\nSteps after the first with canopy::GridBuilder (ns per cell, median; % of a "
               "full build):\n\n"
            << "| storage | cells | full build | nothing changed | one mask byte changed | "
               "two trees changed |\n"
            << "|---|---:|---:|---:|---:|---:|\n";
  for (bool depthFirst : {false, true})
  {
    for (int levels = 5; levels <= maxLevels; ++levels)
    {
      canopy::tools::SyntheticForestOptions options;
      options.dimension = 3;
      options.branchFactor = 2;
      options.rootsPerAxis = 6;
      options.maxLevels = levels;
      options.cutaway = false;
      options.depthFirstStorage = depthFirst;
      SyntheticForest forest(options);
      const int reps = forest.numberOfNodes() > 5'000'000 ? std::min(repetitions, 3) : repetitions;
      printStepRow(forest, depthFirst ? "depth-first + slot map" : "breadth-first", reps);
    }
  }
  printVtkFloor();
  return 0;
}
