// Block forests (octrees of blocks, Athena++/Parthenon style: BlockForest.h), in
// one run, in 3D:
//
// 1. Wrapping (--part wrap): canopy::buildHyperTreeGrid and GridBuilder::build on
//    a second step with the same trees, against
//    (a) cursor + copy: a vtkHyperTreeGrid built with a cursor (SubdivideLeaf per
//        node, the blocks' cells included), every cell's value copied into a
//        vtkDoubleArray, coarse cells given their children's mean (what Canopy's
//        grid reads lazily), as WrapBenchmark.cxx's baseline (CursorBaseline.h);
//    (b) the Ascent/Catalyst route: each block copied into a vtkImageData (n^3
//        interior cells; or (n + 2g)^3 with a vtkGhostType array marking the ghost
//        cells), gathered into a vtkMultiBlockDataSet; and, for context, the same
//        with ghosts borrowed zero-copy (one ghost array shared by every block).
//    Heap and resident memory each adds per cell; the first full reads of
//    Canopy's grid (coarse values are computed when first read); where Canopy's
//    build goes (its internal steps, GridAssembly.h, timed one by one, and VTK's
//    BuildFromBreadthFirstOrderDescriptor, which Canopy used before, against
//    InitializeForReader, which it uses, on the same bits).
// 2. Images (--part image; renders, run under tests/support/with_xvfb.sh): the
//    adaptive surface (the whole domain; with the octant towards the camera cut
//    away by masking its blocks) and three adaptive slices, 1024x1024, in a
//    perspective view of the whole domain, one 4 times as far (cells below a
//    pixel) and one 16 times as far (blocks about a pixel). For each: a step
//    (GridBuilder::build with the same trees, then the filter), the filters'
//    per-topology pass alone (HyperTreeAccess: paid by a step whose topology
//    changed; kept across steps that change only values), a camera move (the filter alone),
//    the first camera move after a step, the render and read-back; quads drawn,
//    blocks drawn (distinct blocks with a drawn cell, found through Canopy's
//    BlockCells index), nodes visited (slices); against vtkHyperTreeGridGeometry
//    (surfaces) and vtkHyperTreeGridAxisCut + Geometry (slices) on the same grid,
//    in a child process (they may abort), once only above 2e7 cells
//    (--skip-upstream-large: not at all there).
//
// Times are the best of --repetitions (the filters' after a first execution): the
// machine's 2 cores are shared with other jobs, the minimum is the least disturbed;
// medians are in the CSVs (wrap.csv, image.csv, with a PNG per image row).
//
// Usage: canopy_bench_block_forest [--part wrap|image|all] [--repetitions N]
//          [--forest N,BLOCKS,MAX_LEVEL]... [--output DIR] [--canopy-only]
//          [--skip-upstream-large] [--check-trees T]
//   default forests 16,244,2 (1e6 cells) and 32,3052,3 (1e8); 4^3 roots over [0,1]^3,
//   refined around a sphere of radius 0.1 at the centre; two variables (density,
//   energy), both wrapped; --canopy-only skips the baselines (for profiling);
//   --check-trees T: the first T trees are checked cell by cell against the cursor
//   baseline (default: every tree up to 2e7 cells; beyond, the first and the most
//   refined).
#include "BlockForest.h"
#include "ChildProcess.h"
#include "CursorBaseline.h"
#include "ForestFingerprint.h"
#include "OffscreenRenderer.h"

#include "BlockCells.h"
#include "ForestLayout.h"
#include "GridAssembly.h"
#include "HyperTreeAccess.h"

#include <canopy/GridBuilder.h>
#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSlice.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>

#include <vtkBitArray.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridAxisCut.h>
#include <vtkHyperTreeGridGeometry.h>
#include <vtkHyperTreeGridNonOrientedCursor.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>

#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace
{

using canopy::bench::BlockForest;
using canopy::bench::heapInUse;
using Clock = std::chrono::steady_clock;

int Repetitions = 3;
bool CanopyOnly = false;
bool UpstreamLarge = true; ///< --skip-upstream-large: not above UpstreamLimit
long CheckTrees = -1; ///< -1: every tree up to 2e7 cells; beyond, the first and the most refined
/// Above this many cells the upstream image filters run once, not Repetitions times
/// (and not at all with --skip-upstream-large).
constexpr std::size_t UpstreamLimit = 20'000'000;

double secondsSince(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Resident bytes of this process.
std::size_t residentBytes()
{
  std::ifstream statm("/proc/self/statm");
  std::size_t pages = 0;
  std::size_t resident = 0;
  statm >> pages >> resident;
  return resident * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
}

struct Timing
{
  double best = 0;
  double median = 0;
};

/// Best and median of `repetitions` runs of `run` (seconds); `prepare` before
/// each, not timed.
Timing timeRuns(
    int repetitions, const std::function<void()>& run, const std::function<void()>& prepare = [] {})
{
  std::vector<double> times;
  for (int r = 0; r < repetitions; ++r)
  {
    prepare();
    const auto start = Clock::now();
    run();
    times.push_back(secondsSince(start));
  }
  std::sort(times.begin(), times.end());
  return {times.front(), times[times.size() / 2]};
}

/// What a build leaves alive, per cell of the grid.
struct Footprint
{
  double heapBytes = 0;     ///< heap growth (allocated: mallinfo2)
  double residentBytes = 0; ///< resident growth (touched pages)
};

/// Times `build` (best/median of Repetitions) and measures, on each run, what
/// the result adds while alive; keeps the last result in `kept`.
template <typename Result>
Timing measureBuild(const std::function<vtkSmartPointer<Result>()>& build, double cells,
                    Footprint& footprint, vtkSmartPointer<Result>& kept, int repetitions)
{
  std::vector<double> times;
  for (int r = 0; r < repetitions; ++r)
  {
    kept = nullptr;
    malloc_trim(0);
    const std::size_t heap = heapInUse();
    const std::size_t resident = residentBytes();
    const auto start = Clock::now();
    kept = build();
    times.push_back(secondsSince(start));
    const std::size_t heapAfter = heapInUse();
    const std::size_t residentAfter = residentBytes();
    footprint.heapBytes = static_cast<double>(heapAfter > heap ? heapAfter - heap : 0) / cells;
    footprint.residentBytes =
        static_cast<double>(residentAfter > resident ? residentAfter - resident : 0) / cells;
  }
  std::sort(times.begin(), times.end());
  return {times.front(), times[times.size() / 2]};
}

/// The grid's cells: described nodes plus, below each block's root, its cells'
/// levels (8 + 64 + ... + n^3).
std::size_t gridCells(const BlockForest& forest)
{
  std::size_t perBlock = 0;
  for (std::size_t level = 8; level <= static_cast<std::size_t>(forest.cellsPerSide()) *
                                           forest.cellsPerSide() * forest.cellsPerSide();
       level *= 8)
    perBlock += level;
  return forest.describedNodes() + forest.blocks().size() * perBlock;
}

int blockLevels(const BlockForest& forest)
{
  int m = 0;
  while ((1 << m) < forest.cellsPerSide())
    ++m;
  return m;
}

/// (a) Cursor + copy: every node subdivided with a cursor, the blocks' cells
/// included; leaf values copied from the blocks' interiors, each coarse cell
/// given the mean of its children summed in child order (Canopy's volume
/// averages, to the bit).
vtkSmartPointer<vtkHyperTreeGrid> buildByCursorAndCopy(const BlockForest& forest)
{
  const canopy::ForestDescription d = forest.description();
  auto htg = canopy::bench::emptyGridLike(d);
  const auto total = static_cast<vtkIdType>(gridCells(forest));
  const int m = blockLevels(forest);
  std::array<vtkSmartPointer<vtkDoubleArray>, BlockForest::Variables> arrays;
  std::array<double*, BlockForest::Variables> values;
  for (int v = 0; v < BlockForest::Variables; ++v)
  {
    arrays[v] = vtkSmartPointer<vtkDoubleArray>::New();
    arrays[v]->SetName(BlockForest::variableName(v));
    arrays[v]->SetNumberOfTuples(total);
    values[v] = arrays[v]->GetPointer(0);
  }
  auto mean = [&](vtkIdType global, const std::array<vtkIdType, 8>& children)
  {
    for (int v = 0; v < BlockForest::Variables; ++v)
    {
      double sum = 0.0;
      for (vtkIdType child : children)
        sum += values[v][child];
      values[v][global] = sum / 8.0;
    }
  };

  vtkIdType offset = 0;
  std::size_t block = 0;
  vtkNew<vtkHyperTreeGridNonOrientedCursor> cursor;
  std::vector<std::size_t> firstChild;
  std::vector<std::size_t> blockOf; // blocks are the leaves breadth-first, tree by tree
  for (const canopy::TreeDescription& tree : d.trees)
  {
    firstChild.assign(tree.numberOfNodes, 0);
    blockOf.assign(tree.numberOfNodes, 0);
    for (std::size_t n = 0, next = 1; n < tree.numberOfNodes; ++n)
    {
      if (tree.refinement[n])
      {
        firstChild[n] = next;
        next += 8;
      }
      else
      {
        blockOf[n] = block++;
      }
    }
    htg->InitializeNonOrientedCursor(cursor, tree.rootIndex, /*create=*/true);
    cursor->SetGlobalIndexStart(offset);
    // Cell `p` (per axis) of block b, s levels below the block's root.
    auto visitCell = [&](auto& self, std::size_t b, int s, std::array<int, 3> p) -> void
    {
      const vtkIdType global = cursor->GetGlobalNodeIndex();
      if (s == m)
      {
        for (int v = 0; v < BlockForest::Variables; ++v)
          values[v][global] = forest.interior(b, v, p[0], p[1], p[2]);
        return;
      }
      cursor->SubdivideLeaf();
      std::array<vtkIdType, 8> children;
      for (unsigned char c = 0; c < 8; ++c)
      {
        cursor->ToChild(c);
        children[c] = cursor->GetGlobalNodeIndex();
        self(self, b, s + 1,
             {{2 * p[0] + (c & 1), 2 * p[1] + ((c >> 1) & 1), 2 * p[2] + ((c >> 2) & 1)}});
        cursor->ToParent();
      }
      mean(global, children);
    };
    auto visitNode = [&](auto& self, std::size_t n) -> void
    {
      if (!tree.refinement[n])
      {
        visitCell(visitCell, blockOf[n], 0, {{0, 0, 0}});
        return;
      }
      const vtkIdType global = cursor->GetGlobalNodeIndex();
      cursor->SubdivideLeaf();
      std::array<vtkIdType, 8> children;
      for (unsigned char c = 0; c < 8; ++c)
      {
        cursor->ToChild(c);
        children[c] = cursor->GetGlobalNodeIndex();
        self(self, firstChild[n] + c);
        cursor->ToParent();
      }
      mean(global, children);
    };
    visitNode(visitNode, 0);
    offset += cursor->GetTree()->GetNumberOfVertices();
  }
  for (auto& array : arrays)
    htg->GetCellData()->AddArray(array);
  return htg;
}

/// How route (b) hands a block to VTK.
enum class ImageMode
{
  Interior,      ///< n^3 interior cells copied
  Ghosts,        ///< (n + 2g)^3 cells copied, a vtkGhostType array per block
  GhostsZeroCopy ///< (n + 2g)^3 cells borrowed (SetArray), one vtkGhostType array shared
};

/// (b) Ascent/Catalyst: one vtkImageData per block, gathered into a
/// vtkMultiBlockDataSet: the interior copied; or the whole (n + 2g)^3 array copied
/// with a vtkGhostType array marking the ghost cells DUPLICATECELL; or (what a
/// zero-copy adaptor can do with ghosts) the whole array borrowed, every block
/// sharing one ghost array.
vtkSmartPointer<vtkMultiBlockDataSet> buildImages(const BlockForest& forest, ImageMode mode)
{
  const int n = forest.cellsPerSide();
  const int g = forest.ghostCells();
  const int p = forest.paddedSide();
  const bool ghosts = mode != ImageMode::Interior;
  const int side = ghosts ? p : n;
  const auto cells = static_cast<vtkIdType>(side) * side * side;
  auto newGhostMarks = [&]
  {
    auto marks = vtkSmartPointer<vtkUnsignedCharArray>::New();
    marks->SetName(vtkDataSetAttributes::GhostArrayName());
    marks->SetNumberOfTuples(cells);
    unsigned char* mark = marks->GetPointer(0);
    for (int k = 0; k < p; ++k)
      for (int j = 0; j < p; ++j)
        for (int i = 0; i < p; ++i)
          *mark++ = (i < g || j < g || k < g || i >= n + g || j >= n + g || k >= n + g)
                        ? vtkDataSetAttributes::DUPLICATECELL
                        : 0;
    return marks;
  };
  vtkSmartPointer<vtkUnsignedCharArray> shared =
      mode == ImageMode::GhostsZeroCopy ? newGhostMarks() : nullptr;
  auto images = vtkSmartPointer<vtkMultiBlockDataSet>::New();
  images->SetNumberOfBlocks(static_cast<unsigned>(forest.blocks().size()));
  for (std::size_t b = 0; b < forest.blocks().size(); ++b)
  {
    const BlockForest::Block& block = forest.blocks()[b];
    vtkNew<vtkImageData> image;
    image->SetDimensions(side + 1, side + 1, side + 1);
    const double h = block.size / n;
    const double shift = ghosts ? g * h : 0.0;
    image->SetOrigin(block.lo[0] - shift, block.lo[1] - shift, block.lo[2] - shift);
    image->SetSpacing(h, h, h);
    for (int v = 0; v < BlockForest::Variables; ++v)
    {
      vtkNew<vtkDoubleArray> array;
      array->SetName(BlockForest::variableName(v));
      const double* from = forest.variable(b, v);
      if (mode == ImageMode::GhostsZeroCopy)
      {
        array->SetArray(const_cast<double*>(from), cells, /*save=*/1);
      }
      else if (mode == ImageMode::Ghosts)
      {
        array->SetNumberOfTuples(cells);
        std::copy(from, from + cells, array->GetPointer(0));
      }
      else
      {
        array->SetNumberOfTuples(cells);
        double* to = array->GetPointer(0);
        for (int k = 0; k < n; ++k)
          for (int j = 0; j < n; ++j)
          {
            const double* row =
                from + g +
                static_cast<std::size_t>(p) * ((j + g) + static_cast<std::size_t>(p) * (k + g));
            to = std::copy(row, row + n, to);
          }
      }
      image->GetCellData()->AddArray(array);
    }
    if (ghosts)
    {
      image->GetCellData()->AddArray(shared ? shared : newGhostMarks());
    }
    images->SetBlock(static_cast<unsigned>(b), image);
  }
  return images;
}

/// One interior cell per block read back from the images: they hold the blocks.
bool imagesHoldTheBlocks(const BlockForest& forest, vtkMultiBlockDataSet* images, ImageMode mode)
{
  const int n = forest.cellsPerSide();
  const bool ghosts = mode != ImageMode::Interior;
  const int side = ghosts ? forest.paddedSide() : n;
  const int at = ghosts ? forest.ghostCells() : 0;
  for (std::size_t b = 0; b < forest.blocks().size(); ++b)
  {
    auto* image = vtkImageData::SafeDownCast(images->GetBlock(static_cast<unsigned>(b)));
    const int i = static_cast<int>(b % n);
    const int j = static_cast<int>((b / 3) % n);
    const int k = n - 1;
    const vtkIdType cell = (i + at) + side * ((j + at) + static_cast<vtkIdType>(side) * (k + at));
    for (int v = 0; v < BlockForest::Variables; ++v)
    {
      if (!image || image->GetNumberOfCells() != static_cast<vtkIdType>(side) * side * side ||
          image->GetCellData()->GetArray(BlockForest::variableName(v))->GetComponent(cell, 0) !=
              forest.interior(b, v, i, j, k))
        return false;
    }
  }
  return true;
}

/// Bytes of the grid's vtkHyperTrees as VTK counts them (their tables' sizes).
std::size_t treeBytes(vtkHyperTreeGrid* htg)
{
  vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
  htg->InitializeTreeIterator(it);
  std::size_t bytes = 0;
  vtkIdType index = 0;
  while (vtkHyperTree* tree = it.GetNextTree(index))
    bytes += tree->GetActualMemorySizeBytes();
  return bytes;
}

/// Reads every cell's value of every field once (GetComponent, as a VTK filter
/// that does not know the array's class reads it). Returns the sum.
double readEveryCell(vtkHyperTreeGrid* htg)
{
  double sum = 0;
  for (int v = 0; v < BlockForest::Variables; ++v)
  {
    vtkDataArray* array = htg->GetCellData()->GetArray(BlockForest::variableName(v));
    const vtkIdType tuples = array->GetNumberOfTuples();
    for (vtkIdType t = 0; t < tuples; ++t)
      sum += array->GetComponent(t, 0);
  }
  return sum;
}

std::string forestLabel(const BlockForest& forest)
{
  std::ostringstream label;
  const int n = forest.cellsPerSide();
  label << n << "^3 blocks x " << forest.blocks().size() << " (";
  const auto levels = forest.blocksPerLevel();
  bool first = true;
  for (std::size_t l = 0; l < levels.size(); ++l)
  {
    if (levels[l] == 0)
      continue;
    label << (first ? "" : " / ") << levels[l] << " at L" << l;
    first = false;
  }
  label << ")";
  return label.str();
}

// ---------------------------------------------------------------------------
// 1. Wrapping

struct WrapRow
{
  std::string label;
  std::size_t cells = 0;
  std::size_t leaves = 0;
  Timing canopy, step, cursor;
  Footprint canopyMemory, cursorMemory;
  std::array<Timing, 3> images; ///< per ImageMode
  std::array<Footprint, 3> imagesMemory;
  double treeBytesPerCell = 0;
  Footprint afterReads; ///< Canopy's grid after the reads below, from before its build
  double rangeSeconds = 0, firstReadSeconds = 0, secondReadSeconds = 0, plainReadSeconds = 0;
  std::string checked;
  /// buildHyperTreeGrid's steps (GridAssembly.h), seconds: layout (validation),
  /// block index, trees, topology arrays, fields.
  std::array<double, 5> phases{{0, 0, 0, 0, 0}};
  std::size_t descriptorBits = 0;
  double breadthFirstSeconds = 0; ///< VTK's BuildFromBreadthFirstOrderDescriptor, every tree
  double readerSeconds = 0;       ///< VTK's InitializeForReader on the same bits
  double breadthFirstHeap = 0;    ///< heap bytes per grid cell the trees hold, each way
  double readerHeap = 0;
  bool sameTrees = false;
};

/// Where Canopy's build goes: its steps timed one by one (best of Repetitions),
/// then the trees alone, through VTK's BuildFromBreadthFirstOrderDescriptor (which
/// grows each tree's child table bit by bit) and through VTK's InitializeForReader,
/// what Canopy calls, from the same bits (one exact allocation per tree; checked to
/// give the same trees).
void wrapPhases(const canopy::ForestDescription& d, WrapRow& row)
{
  const double cells = static_cast<double>(row.cells);
  row.phases.fill(1e30);
  for (int r = 0; r < Repetitions; ++r)
  {
    auto t0 = Clock::now();
    const canopy::ForestLayout layout = canopy::layoutForest(d);
    auto t1 = Clock::now();
    const auto fields = canopy::assembly::selectFields(d, canopy::FieldRequest::all());
    vtkSmartPointer<vtkHyperTreeGrid> htg = canopy::assembly::newGrid(d);
    canopy::assembly::FieldTables tables;
    tables.blocks = canopy::assembly::indexBlocks(d, layout);
    auto t2 = Clock::now();
    canopy::assembly::buildTrees(htg, d, layout, std::vector<bool>(d.trees.size(), true),
                                 tables.blocks.get());
    auto t3 = Clock::now();
    canopy::assembly::setTopologyArrays(htg, d, layout, tables.blocks.get());
    auto t4 = Clock::now();
    canopy::assembly::setFields(htg, d, layout, fields, tables);
    auto t5 = Clock::now();
    const Clock::time_point at[6] = {t0, t1, t2, t3, t4, t5};
    for (std::size_t p = 0; p < 5; ++p)
      row.phases[p] =
          std::min(row.phases[p], std::chrono::duration<double>(at[p + 1] - at[p]).count());
  }
  // The trees alone, both ways, from the descriptor Canopy writes.
  const canopy::ForestLayout layout = canopy::layoutForest(d);
  const auto index = canopy::assembly::indexBlocks(d, layout);
  row.descriptorBits = layout.totalDescriptorBits;
  auto bits = vtkSmartPointer<vtkBitArray>::New();
  bits->SetNumberOfValues(static_cast<vtkIdType>(layout.totalDescriptorBits));
  std::fill_n(bits->GetPointer(0), (layout.totalDescriptorBits + 7) / 8, 0);
  std::vector<vtkSmartPointer<vtkBitArray>> perTree;
  for (std::size_t t = 0, at = 0; t < d.trees.size(); ++t)
  {
    const std::size_t count = layout.trees[t].descriptorBits;
    index->writeDescriptor(layout.trees[t].firstCell, count, bits->GetPointer(0), at);
    auto own = vtkSmartPointer<vtkBitArray>::New();
    own->SetNumberOfValues(static_cast<vtkIdType>(count));
    for (std::size_t i = 0; i < count; ++i)
      own->SetValue(static_cast<vtkIdType>(i), bits->GetValue(static_cast<vtkIdType>(at + i)));
    perTree.push_back(own);
    at += count;
  }
  auto newTree = []
  { return vtkSmartPointer<vtkHyperTree>::Take(vtkHyperTree::CreateInstance(2, 3)); };
  std::vector<vtkSmartPointer<vtkHyperTree>> breadthFirst;
  std::vector<vtkSmartPointer<vtkHyperTree>> reader;
  row.breadthFirstSeconds = row.readerSeconds = 1e30;
  for (int r = 0; r < Repetitions; ++r)
  {
    breadthFirst.clear();
    reader.clear();
    malloc_trim(0);
    std::size_t heap = heapInUse();
    auto start = Clock::now();
    vtkIdType from = 0;
    for (std::size_t t = 0; t < d.trees.size(); ++t)
    {
      breadthFirst.push_back(newTree());
      const auto count = static_cast<vtkIdType>(layout.trees[t].descriptorBits);
      breadthFirst.back()->BuildFromBreadthFirstOrderDescriptor(bits, count, from);
      from += count;
    }
    row.breadthFirstSeconds = std::min(row.breadthFirstSeconds, secondsSince(start));
    row.breadthFirstHeap = static_cast<double>(heapInUse() - heap) / cells;
    heap = heapInUse();
    start = Clock::now();
    for (std::size_t t = 0; t < d.trees.size(); ++t)
    {
      const canopy::TreeLayout& shape = layout.trees[t];
      reader.push_back(newTree());
      reader.back()->InitializeForReader(shape.levels, static_cast<vtkIdType>(shape.cells),
                                         static_cast<vtkIdType>(shape.cells - shape.descriptorBits),
                                         perTree[t], nullptr, nullptr);
    }
    row.readerSeconds = std::min(row.readerSeconds, secondsSince(start));
    row.readerHeap = static_cast<double>(heapInUse() - heap) / cells;
  }
  row.sameTrees = true;
  for (std::size_t t = 0; t < d.trees.size(); ++t)
  {
    std::size_t na = 0;
    std::size_t nb = 0;
    const unsigned int* a = breadthFirst[t]->GetElderChildIndexArray(na);
    const unsigned int* b = reader[t]->GetElderChildIndexArray(nb);
    row.sameTrees = row.sameTrees && na == nb && std::equal(a, a + na, b) &&
                    breadthFirst[t]->GetNumberOfVertices() == reader[t]->GetNumberOfVertices() &&
                    breadthFirst[t]->GetNumberOfLevels() == reader[t]->GetNumberOfLevels();
  }
}

WrapRow wrap(const BlockForest& forest)
{
  WrapRow row;
  row.label = forestLabel(forest);
  row.leaves = forest.leafCells();
  const canopy::ForestDescription d = forest.description();
  const auto request = canopy::FieldRequest::all();
  const double cells = static_cast<double>(gridCells(forest));
  row.cells = gridCells(forest);
  const int reps = Repetitions;

  // Canopy, from scratch.
  vtkSmartPointer<vtkHyperTreeGrid> grid;
  row.canopy = measureBuild<vtkHyperTreeGrid>(
      [&] { return canopy::buildHyperTreeGrid(d, request); }, cells, row.canopyMemory, grid, reps);
  if (static_cast<std::size_t>(grid->GetNumberOfCells()) != row.cells)
  {
    std::cerr << "bench: Canopy's grid has " << grid->GetNumberOfCells() << " cells, expected "
              << row.cells << "\n";
    std::exit(1);
  }
  row.treeBytesPerCell = static_cast<double>(treeBytes(grid)) / cells;

  // The next step, same trees (the simulation's values changed: fields wrapped again).
  {
    canopy::GridBuilder builder;
    builder.build(d, request);
    row.step = timeRuns(std::max(reps, 5), [&] { builder.build(d, request); });
    if (builder.lastBuild().treesRebuilt != 0)
    {
      std::cerr << "bench: a step with the same trees rebuilt trees\n";
      std::exit(1);
    }
  }

  wrapPhases(d, row);

  // First reads of a fresh grid: the range (leaves only), every cell once (coarse
  // values computed), every cell again.
  grid = nullptr;
  malloc_trim(0);
  {
    const std::size_t heap = heapInUse();
    const std::size_t resident = residentBytes();
    grid = canopy::buildHyperTreeGrid(d, request);
    auto start = Clock::now();
    for (int v = 0; v < BlockForest::Variables; ++v)
    {
      double range[2];
      grid->GetCellData()->GetArray(BlockForest::variableName(v))->GetRange(range, 0);
      if (range[1] >= BlockForest::GhostSentinel)
      {
        std::cerr << "bench: a ghost cell was read\n";
        std::exit(1);
      }
    }
    row.rangeSeconds = secondsSince(start);
    start = Clock::now();
    const double first = readEveryCell(grid);
    row.firstReadSeconds = secondsSince(start);
    start = Clock::now();
    const double second = readEveryCell(grid);
    row.secondReadSeconds = secondsSince(start);
    if (first != second)
    {
      std::cerr << "bench: two reads of the grid differ\n";
      std::exit(1);
    }
    row.afterReads.heapBytes = static_cast<double>(heapInUse() - heap) / cells;
    row.afterReads.residentBytes = static_cast<double>(residentBytes() - resident) / cells;
  }
  if (CanopyOnly)
    return row;

  // (a) cursor + copy.
  vtkSmartPointer<vtkHyperTreeGrid> cursorGrid;
  row.cursor = measureBuild<vtkHyperTreeGrid>([&] { return buildByCursorAndCopy(forest); }, cells,
                                              row.cursorMemory, cursorGrid, reps);
  {
    const auto start = Clock::now();
    readEveryCell(cursorGrid);
    row.plainReadSeconds = secondsSince(start);
  }
  // Both grids must be the same, cell by cell: every tree up to 2e7 cells; beyond
  // (the cursor walk costs about 1 us a cell), the first tree and the most refined
  // one (--check-trees T: the first T trees instead).
  {
    std::vector<vtkIdType> trees;
    if (CheckTrees >= 0)
    {
      for (std::size_t t = 0; t < d.trees.size() && static_cast<long>(t) < CheckTrees; ++t)
        trees.push_back(d.trees[t].rootIndex);
    }
    else if (row.cells > 20'000'000)
    {
      std::size_t most = 0;
      for (std::size_t t = 1; t < d.trees.size(); ++t)
        most = d.trees[t].numberOfNodes > d.trees[most].numberOfNodes ? t : most;
      trees = {d.trees.front().rootIndex, d.trees[most].rootIndex};
    }
    if (!canopy::bench::sameContent(grid, cursorGrid, {"density", "energy"},
                                    trees.empty() ? nullptr : &trees))
    {
      std::cerr << "bench: Canopy's grid and the cursor + copy grid differ; timings are "
                   "meaningless\n";
      std::exit(1);
    }
    if (trees.empty())
    {
      row.checked = "every cell";
    }
    else
    {
      std::size_t cells = 0;
      vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
      grid->InitializeTreeIterator(it);
      vtkIdType index = 0;
      while (vtkHyperTree* tree = it.GetNextTree(index))
        if (std::find(trees.begin(), trees.end(), index) != trees.end())
          cells += static_cast<std::size_t>(tree->GetNumberOfVertices());
      row.checked = "every cell of " + std::to_string(trees.size()) + " of " +
                    std::to_string(d.trees.size()) + " trees (" + std::to_string(cells) + " cells)";
    }
  }
  cursorGrid = nullptr;

  // (b) images, each way.
  for (const ImageMode mode : {ImageMode::Interior, ImageMode::Ghosts, ImageMode::GhostsZeroCopy})
  {
    const auto m = static_cast<std::size_t>(mode);
    vtkSmartPointer<vtkMultiBlockDataSet> images;
    row.images[m] = measureBuild<vtkMultiBlockDataSet>([&] { return buildImages(forest, mode); },
                                                       cells, row.imagesMemory[m], images, reps);
    if (!imagesHoldTheBlocks(forest, images, mode))
    {
      std::cerr << "bench: the images do not hold the blocks' values\n";
      std::exit(1);
    }
  }
  return row;
}

void printWrap(const std::vector<WrapRow>& rows, std::ofstream& csv)
{
  auto ms = [](double s)
  {
    std::ostringstream o;
    o << std::fixed << std::setprecision(s < 0.001 ? 3 : (s < 1 ? 1 : 0)) << s * 1e3;
    return o.str();
  };
  auto ratio = [](double baseline, double canopy)
  {
    std::ostringstream o;
    const double x = baseline / canopy;
    o << std::fixed << std::setprecision(x < 10 ? 2 : (x < 100 ? 1 : 0)) << x << "x";
    return o.str();
  };
  const char* imageNames[3] = {"(b) images, interior copied", "(b) images + ghosts copied",
                               "(b) images + ghosts, zero-copy, one shared vtkGhostType"};
  std::cout << "\n## Wrapping (ms, best of " << Repetitions
            << "; in brackets baseline / Canopy's buildHyperTreeGrid)\n\n"
            << "| forest | grid cells | Canopy buildHyperTreeGrid | GridBuilder, next step "
               "(same trees) | (a) cursor + copy";
  for (const char* name : imageNames)
    std::cout << " | " << name;
  std::cout << " |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const WrapRow& r : rows)
  {
    std::cout << "| " << r.label << " | " << r.cells << " | " << ms(r.canopy.best) << " | "
              << ms(r.step.best) << " | ";
    if (CanopyOnly)
    {
      std::cout << "- | - | - | - |\n";
      continue;
    }
    std::cout << ms(r.cursor.best) << " (" << ratio(r.cursor.best, r.canopy.best) << ")";
    for (const Timing& t : r.images)
      std::cout << " | " << ms(t.best) << " (" << ratio(t.best, r.canopy.best) << ")";
    std::cout << " |\n";
  }
  std::cout << "\n## Memory each adds, bytes per grid cell (heap in use / resident)\n\n"
            << "| forest | grid cells | Canopy | of which VTK's trees (their own count) | Canopy "
               "after reading every cell | (a) cursor + copy";
  for (const char* name : imageNames)
    std::cout << " | " << name;
  std::cout << " |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  auto bytes = [](const Footprint& f)
  {
    std::ostringstream o;
    o << std::fixed << std::setprecision(2) << f.heapBytes << " / " << f.residentBytes;
    return o.str();
  };
  for (const WrapRow& r : rows)
  {
    std::cout << "| " << r.label << " | " << r.cells << " | " << bytes(r.canopyMemory) << " | "
              << std::fixed << std::setprecision(2) << r.treeBytesPerCell << " | "
              << bytes(r.afterReads) << " | " << (CanopyOnly ? "-" : bytes(r.cursorMemory));
    for (const Footprint& f : r.imagesMemory)
      std::cout << " | " << (CanopyOnly ? "-" : bytes(f));
    std::cout << " |\n";
  }
  std::cout << "\n## Reading Canopy's grid (both fields; coarse values are computed when "
               "first read)\n\n"
            << "| forest | grid cells | GetRange (leaves) ms | first read of every cell ms "
               "(ns/value) | second read ms (ns/value) | the cursor grid's vtkDoubleArrays, "
               "same read ms (ns/value) | checked against (a) |\n"
            << "|---|---:|---:|---:|---:|---:|---|\n";
  for (const WrapRow& r : rows)
  {
    const double values = BlockForest::Variables * static_cast<double>(r.cells);
    std::cout << std::fixed << "| " << r.label << " | " << r.cells << " | " << std::setprecision(1)
              << r.rangeSeconds * 1e3 << " | " << r.firstReadSeconds * 1e3 << " ("
              << r.firstReadSeconds * 1e9 / values << ") | " << r.secondReadSeconds * 1e3 << " ("
              << r.secondReadSeconds * 1e9 / values << ") | ";
    if (CanopyOnly)
      std::cout << "- | - |\n";
    else
      std::cout << r.plainReadSeconds * 1e3 << " (" << r.plainReadSeconds * 1e9 / values << ") | "
                << r.checked << " |\n";
  }
  std::cout << "\n## Where Canopy's build goes (ms, best of " << Repetitions
            << "; internal steps, GridAssembly.h)\n\n"
            << "| forest | validation + layout | block index | VTK trees (Canopy's "
               "descriptor + InitializeForReader) | mask | fields | VTK "
               "descriptor bits per grid cell | BuildFromBreadthFirstOrderDescriptor alone: "
               "ns/bit, heap B/cell | InitializeForReader, same bits: ns/bit, heap B/cell "
               "(same trees) |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const WrapRow& r : rows)
  {
    const double bits = static_cast<double>(r.descriptorBits);
    std::cout << std::fixed << "| " << r.label << " | " << std::setprecision(3) << r.phases[0] * 1e3
              << " | " << r.phases[1] * 1e3 << " | " << std::setprecision(1) << r.phases[2] * 1e3
              << " | " << std::setprecision(3) << r.phases[3] * 1e3 << " | " << r.phases[4] * 1e3
              << " | " << bits / static_cast<double>(r.cells) << " | " << std::setprecision(1)
              << r.breadthFirstSeconds * 1e9 / bits << ", " << std::setprecision(2)
              << r.breadthFirstHeap << " | " << std::setprecision(1) << r.readerSeconds * 1e9 / bits
              << ", " << std::setprecision(2) << r.readerHeap << " ("
              << (r.sameTrees ? "yes" : "NO") << ") |\n";
  }
  std::cout << std::flush;
  for (const WrapRow& r : rows)
  {
    csv << '"' << r.label << "\"," << r.cells << "," << r.leaves << "," << r.canopy.best << ","
        << r.canopy.median << "," << r.step.best << "," << r.step.median << "," << r.cursor.best
        << "," << r.cursor.median;
    for (const Timing& t : r.images)
      csv << "," << t.best << "," << t.median;
    csv << "," << r.canopyMemory.heapBytes << "," << r.canopyMemory.residentBytes << ","
        << r.treeBytesPerCell << "," << r.afterReads.heapBytes << "," << r.afterReads.residentBytes
        << "," << r.cursorMemory.heapBytes;
    for (const Footprint& f : r.imagesMemory)
      csv << "," << f.heapBytes;
    csv << "," << r.rangeSeconds << "," << r.firstReadSeconds << "," << r.secondReadSeconds << ","
        << r.plainReadSeconds << "\n";
  }
}

// ---------------------------------------------------------------------------
// 2. Images

constexpr double SliceOffset = 0.0065; ///< planes off the centre, off every cell face

void setView(vtkCamera* camera, double distance)
{
  // The domain is [0, 1]^3: a perspective view from the octant the cut-away opens.
  camera->SetFocalPoint(0.5, 0.5, 0.5);
  camera->SetPosition(0.5 + 1.3 * distance, 0.5 + 1.0 * distance, 0.5 + 1.6 * distance);
  camera->SetViewUp(0, 1, 0);
  camera->ParallelProjectionOff();
  camera->SetViewAngle(30);
}

/// What a filter's output shows of the blocks: cells by where they are.
struct Drawn
{
  vtkIdType quads = 0;
  std::size_t blocks = 0;              ///< distinct blocks with a drawn cell (or root)
  std::size_t aboveBlocks = 0;         ///< drawn nodes coarser than a block
  std::vector<std::size_t> bySubLevel; ///< drawn cells per level inside their block
};

Drawn drawn(vtkPolyData* output, const canopy::BlockCells& index)
{
  Drawn d;
  d.quads = output->GetNumberOfCells();
  d.bySubLevel.assign(static_cast<std::size_t>(index.blockLevels()) + 1, 0);
  std::vector<unsigned char> seen(index.numberOfBlocks(), 0);
  auto* ids = vtkIdTypeArray::SafeDownCast(output->GetCellData()->GetArray("OriginalCellId"));
  for (vtkIdType q = 0; ids && q < ids->GetNumberOfTuples(); ++q)
  {
    const canopy::BlockCells::Location where =
        index.locate(static_cast<std::uint64_t>(ids->GetValue(q)));
    std::int64_t block = where.block;
    if (where.subLevel == 0)
    {
      block = index.blockOfNode(static_cast<std::size_t>(where.node));
      if (block < 0)
      {
        ++d.aboveBlocks;
        continue;
      }
    }
    ++d.bySubLevel[static_cast<std::size_t>(where.subLevel)];
    seen[static_cast<std::size_t>(block)] = 1;
  }
  d.blocks = static_cast<std::size_t>(std::count(seen.begin(), seen.end(), 1));
  return d;
}

struct ImageRow
{
  std::string label, view, picture;
  std::size_t cells = 0, blocks = 0;
  double first = 0;
  Timing build, filterInStep, cameraMove;
  double firstMove = 0;     ///< the first camera move after a step
  double firstMoveHeap = 0; ///< heap bytes per grid cell it left allocated
  double topologyPass = 0;  ///< the filters' per-topology pass (HyperTreeAccess) alone
  double render = 0;
  Drawn what;
  vtkIdType visited = -1;
  double upstream = -1;
  vtkIdType upstreamQuads = -1;
  std::string upstreamNote;
};

/// A filter and what feeds it: the forest's description, its builder, and how
/// to run the upstream route on the same grid (in a child process).
struct Picture
{
  std::string name;
  bool cutaway = false;
  bool slices = false;
};

void image(const BlockForest& forest, const Picture& picture, double distance,
           const std::string& viewName, canopy::testing::OffscreenRenderer& r,
           const std::filesystem::path& out, std::vector<ImageRow>& rows)
{
  ImageRow row;
  row.label = forestLabel(forest);
  row.view = viewName;
  row.picture = picture.name;
  row.cells = gridCells(forest);
  row.blocks = forest.blocks().size();
  const canopy::ForestDescription d = forest.description(picture.cutaway);
  const auto request = canopy::FieldRequest::only({"density"});
  const canopy::BlockCells index = canopy::BlockCells::build(d, canopy::layoutForest(d));
  canopy::GridBuilder builder;
  vtkSmartPointer<vtkHyperTreeGrid> grid = builder.build(d, request);
  setView(r.camera(), distance);

  vtkSmartPointer<vtkCanopyViewDependentFilter> filter;
  vtkCanopyAdaptiveSlice* slice = nullptr;
  if (picture.slices)
  {
    auto s = vtkSmartPointer<vtkCanopyAdaptiveSlice>::New();
    for (int axis = 0; axis < 3; ++axis)
      s->AddPlane(axis, 0.5 + SliceOffset);
    slice = s;
    filter = s;
  }
  else
  {
    filter = vtkSmartPointer<vtkCanopyAdaptiveSurface>::New();
  }
  filter->SetInputData(grid);
  filter->SetRenderer(r.renderer());
  filter->AddField("density");
  auto start = Clock::now();
  filter->Update();
  row.first = secondsSince(start);
  // A camera move: the filter alone, the grid unchanged.
  row.cameraMove = timeRuns(
      Repetitions, [&] { filter->Update(); }, [&] { filter->Modified(); });
  // A step: the simulation's next step with the same trees (GridBuilder keeps
  // them, wraps the fields again, marks the grid modified), then the filter.
  std::vector<double> builds;
  std::vector<double> filters;
  for (int rep = 0; rep < Repetitions; ++rep)
  {
    start = Clock::now();
    if (builder.build(d, request) != grid)
    {
      std::cerr << "bench: GridBuilder returned another grid for the same trees\n";
      std::exit(1);
    }
    builds.push_back(secondsSince(start));
    start = Clock::now();
    filter->Update();
    filters.push_back(secondsSince(start));
  }
  // The first camera move after a step: the topology is kept from the step's
  // execution, and the 3D surface fills its per-node memos (on first use per
  // topology) in this execution; what it leaves allocated is what they hold.
  {
    const std::size_t heap = heapInUse();
    filter->Modified();
    start = Clock::now();
    filter->Update();
    row.firstMove = secondsSince(start);
    const std::size_t after = heapInUse();
    row.firstMoveHeap =
        static_cast<double>(after > heap ? after - heap : 0) / static_cast<double>(row.cells);
  }
  // What a step whose topology changed pays before walking: the filters' view of
  // the grid's topology (HyperTreeAccess, kept across steps while the topology
  // holds), built as the filter asks.
  row.topologyPass =
      timeRuns(Repetitions,
               [&] { canopy::HyperTreeAccess access(grid, !picture.slices, !picture.slices); })
          .best;
  std::sort(builds.begin(), builds.end());
  std::sort(filters.begin(), filters.end());
  row.build = {builds.front(), builds[builds.size() / 2]};
  row.filterInStep = {filters.front(), filters[filters.size() / 2]};
  vtkPolyData* output = filter->GetPolyDataOutput();
  row.what = drawn(output, index);
  row.visited = slice ? slice->GetLastVisited() : -1;
  // Render and read back (the first render of a new output compiles and uploads):
  // the best of the following ones.
  canopy::testing::Image picturePixels;
  std::vector<double> renders;
  for (int rep = 0; rep <= Repetitions; ++rep)
  {
    output->Modified();
    start = Clock::now();
    picturePixels = r.render(output, "density", 1, 4, /*lighting=*/!picture.slices);
    if (rep > 0)
      renders.push_back(secondsSince(start));
  }
  row.render = *std::min_element(renders.begin(), renders.end());
  std::ostringstream name;
  name << "block-forest-" << forest.cellsPerSide() << "-" << forest.blocks().size() << "-"
       << (picture.slices    ? "slices"
           : picture.cutaway ? "cutaway"
                             : "surface")
       << "-" << viewName << ".png";
  canopy::testing::writePng(picturePixels, (out / name.str()).string());

  const bool upstream = !CanopyOnly && (row.cells <= UpstreamLimit || UpstreamLarge);
  if (upstream)
  {
    const int reps = row.cells <= UpstreamLimit ? Repetitions : 1;
    const std::string result = canopy::bench::inChild(
        [&]
        {
          std::vector<vtkSmartPointer<vtkHyperTreeGridAxisCut>> cuts;
          std::vector<vtkSmartPointer<vtkHyperTreeGridGeometry>> geometries;
          for (int axis = 0; axis < (picture.slices ? 3 : 1); ++axis)
          {
            auto geometry = vtkSmartPointer<vtkHyperTreeGridGeometry>::New();
            if (picture.slices)
            {
              auto cut = vtkSmartPointer<vtkHyperTreeGridAxisCut>::New();
              cut->SetInputData(grid);
              cut->SetPlaneNormalAxis(axis);
              cut->SetPlanePosition(0.5 + SliceOffset);
              geometry->SetInputConnection(cut->GetOutputPort());
              cuts.push_back(cut);
            }
            else
            {
              geometry->SetInputData(grid);
            }
            geometries.push_back(geometry);
          }
          const Timing t = timeRuns(
              reps,
              [&]
              {
                for (auto& geometry : geometries)
                  geometry->Update();
              },
              [&]
              {
                for (auto& geometry : geometries)
                  geometry->Modified();
                for (auto& cut : cuts)
                  cut->Modified();
              });
          vtkIdType quads = 0;
          for (auto& geometry : geometries)
            quads += vtkPolyData::SafeDownCast(geometry->GetOutput())->GetNumberOfCells();
          std::ostringstream text;
          text << std::setprecision(17) << t.best << " " << quads;
          return text.str();
        });
    if (result.empty())
      row.upstreamNote = "aborts";
    else
      std::istringstream(result) >> row.upstream >> row.upstreamQuads;
  }
  else
  {
    row.upstreamNote = CanopyOnly ? "-" : "not run (--skip-upstream-large)";
  }
  rows.push_back(row);

  std::cout << std::fixed << "| " << row.label << " | " << row.view << " | " << row.picture << " | "
            << std::setprecision(1) << row.build.best * 1e3 << " + " << row.filterInStep.best * 1e3
            << " | " << row.topologyPass * 1e3 << " | " << row.cameraMove.best * 1e3 << " | "
            << row.firstMove * 1e3 << " (+" << std::setprecision(2) << row.firstMoveHeap
            << " B/cell) | " << std::setprecision(1) << row.first * 1e3 << " | " << row.render * 1e3
            << " | " << row.what.quads << " | " << row.what.blocks << " / " << row.blocks << " | "
            << row.what.aboveBlocks << " | ";
  for (std::size_t s = 0; s < row.what.bySubLevel.size(); ++s)
    std::cout << (s ? " / " : "") << row.what.bySubLevel[s];
  std::cout << " | " << (row.visited >= 0 ? std::to_string(row.visited) : std::string("-"))
            << " | ";
  if (row.upstream >= 0)
    std::cout << std::setprecision(1) << row.upstream * 1e3 << " ("
              << std::setprecision(row.upstream / row.cameraMove.best < 100 ? 1 : 0)
              << row.upstream / row.cameraMove.best << "x camera move, "
              << row.upstream / (row.build.best + row.filterInStep.best) << "x step) | "
              << row.upstreamQuads << " |" << std::endl;
  else
    std::cout << row.upstreamNote << " | - |" << std::endl;
}

} // namespace

int main(int argc, char** argv)
{
  std::string part = "all";
  std::filesystem::path out = "bench-block-forest";
  struct ForestSpec
  {
    int cellsPerSide;
    std::size_t blocks;
    int maxLevel;
  };
  std::vector<ForestSpec> specs;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--part" && i + 1 < argc)
      part = argv[++i];
    else if (arg == "--repetitions" && i + 1 < argc)
      Repetitions = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--output" && i + 1 < argc)
      out = argv[++i];
    else if (arg == "--canopy-only")
      CanopyOnly = true;
    else if (arg == "--skip-upstream-large")
      UpstreamLarge = false;
    else if (arg == "--check-trees" && i + 1 < argc)
      CheckTrees = std::atol(argv[++i]);
    else if (arg == "--forest" && i + 1 < argc)
    {
      ForestSpec spec{};
      char c1 = 0;
      char c2 = 0;
      std::istringstream text(argv[++i]);
      if (!(text >> spec.cellsPerSide >> c1 >> spec.blocks >> c2 >> spec.maxLevel) || c1 != ',' ||
          c2 != ',' || spec.cellsPerSide < 2 || (spec.cellsPerSide & (spec.cellsPerSide - 1)) ||
          spec.maxLevel < 0)
      {
        std::cerr << "canopy_bench_block_forest: --forest N,BLOCKS,MAX_LEVEL (N a power of 2), "
                     "got "
                  << argv[i] << "\n";
        return 2;
      }
      specs.push_back(spec);
    }
    else
    {
      std::cerr << "usage: canopy_bench_block_forest [--part wrap|image|all] [--repetitions N]\n"
                   "         [--forest N,BLOCKS,MAX_LEVEL]... [--output DIR] [--canopy-only]\n"
                   "         [--skip-upstream-large] [--check-trees T]\n";
      return 2;
    }
  }
  if (part != "wrap" && part != "image" && part != "all")
  {
    std::cerr << "canopy_bench_block_forest: --part is wrap, image or all\n";
    return 2;
  }
  if (specs.empty())
    specs = {{16, 244, 2}, {32, 3052, 3}};
  std::filesystem::create_directories(out);
  std::cout << "# Block forests (Debian's VTK has assertions on; best of " << Repetitions << ")\n";

  std::vector<std::unique_ptr<BlockForest>> forests;
  auto makeForest = [&](const ForestSpec& spec)
  {
    canopy::bench::BlockForestOptions o;
    o.cellsPerSide = spec.cellsPerSide;
    o.targetBlocks = spec.blocks;
    o.maxLevel = spec.maxLevel;
    o.frontRadius = 0.1;
    const auto start = Clock::now();
    auto forest = std::make_unique<BlockForest>(o);
    std::cerr << "bench: " << forestLabel(*forest) << ", " << gridCells(*forest) << " grid cells, "
              << forest->leafCells() << " interior cells, " << forest->blockBytes() / 1e9
              << " GB of blocks, made in " << secondsSince(start) << " s\n"
              << canopy::tools::describeInput(forestLabel(*forest), forest->description()) << "\n";
    return forest;
  };

  if (part != "image")
  {
    std::ofstream csv(out / "wrap.csv");
    csv << "forest,grid_cells,interior_cells,canopy_s,canopy_median_s,step_s,step_median_s,"
           "cursor_s,cursor_median_s,images_s,images_median_s,ghost_images_s,"
           "ghost_images_median_s,zero_copy_images_s,zero_copy_images_median_s,"
           "canopy_heap_b_per_cell,canopy_resident_b_per_cell,vtk_tree_b_per_cell,"
           "after_reads_heap_b_per_cell,after_reads_resident_b_per_cell,cursor_heap_b_per_cell,"
           "images_heap_b_per_cell,ghost_images_heap_b_per_cell,zero_copy_images_heap_b_per_cell,"
           "range_s,first_read_s,second_read_s,cursor_grid_read_s\n";
    std::vector<WrapRow> rows;
    for (const ForestSpec& spec : specs)
    {
      // One forest at a time: the 1e8-cell one holds 2.3 GB of blocks.
      auto forest = makeForest(spec);
      rows.push_back(wrap(*forest));
    }
    printWrap(rows, csv);
  }
  if (part != "wrap")
  {
    std::ofstream csv(out / "image.csv");
    csv << "forest,view,picture,grid_cells,blocks,first_s,step_build_s,step_filter_s,"
           "step_filter_median_s,topology_pass_s,camera_move_s,camera_move_median_s,first_move_"
           "after_step_s,"
           "first_move_heap_b_per_cell,render_s,quads,"
           "blocks_drawn,above_blocks_drawn,nodes_visited,upstream_s,upstream_quads\n";
    canopy::testing::OffscreenRenderer renderer(1024, 1024);
    std::cout << "\n## Images at 1024x1024 (ms, best of " << Repetitions
              << "; step = GridBuilder::build with the same trees + the filter)\n\n"
              << "| forest | view | picture | step: build + filter | the topology pass alone "
                 "(HyperTreeAccess, when the topology changed) | filter, camera move | "
                 "first camera move after a step (heap it keeps) | first execution | render + "
                 "read-back | quads | blocks drawn | nodes above "
                 "blocks drawn | drawn cells per level in their block (root .. cells) | nodes "
                 "visited | upstream ms (ratio) | upstream quads |\n"
              << "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|"
              << std::endl;
    std::vector<ImageRow> rows;
    for (const ForestSpec& spec : specs)
    {
      auto forest = makeForest(spec);
      for (const auto& [distance, viewName] : std::vector<std::pair<double, std::string>>{
               {1.6, "whole"}, {6.4, "far"}, {25.6, "distant"}})
      {
        for (const Picture& picture :
             {Picture{"surface", false, false}, Picture{"surface, octant cut away", true, false},
              Picture{"3 slices", false, true}})
          image(*forest, picture, distance, viewName, renderer, out, rows);
      }
    }
    for (const ImageRow& r : rows)
      csv << '"' << r.label << "\"," << r.view << ",\"" << r.picture << "\"," << r.cells << ","
          << r.blocks << "," << r.first << "," << r.build.best << "," << r.filterInStep.best << ","
          << r.filterInStep.median << "," << r.topologyPass << "," << r.cameraMove.best << ","
          << r.cameraMove.median << "," << r.firstMove << "," << r.firstMoveHeap << "," << r.render
          << "," << r.what.quads << "," << r.what.blocks << "," << r.what.aboveBlocks << ","
          << r.visited << "," << r.upstream << "," << r.upstreamQuads << "\n";
  }
  return 0;
}
