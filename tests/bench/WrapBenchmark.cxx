// Wrap cost per cell: Canopy's zero-copy build against the obvious alternative
// (walk each tree with a vtkHyperTreeGrid cursor, SubdivideLeaf where the
// simulation refined, copy every field value into new VTK arrays), in one run,
// on the same forests, 1e5 to 1e7 cells: the synthetic forest and the mini-app's
// own forests at a late step (real data: leaves-only fields, which both builds
// complete with coarse averages).
//
// Usage: canopy_bench_wrap [--max-levels L] [--csv FILE] [--repetitions R]
//          [--data synthetic|miniapp|all] [--miniapp DIM,ROOTS,MAX_LEVEL,STEPS]...
// Prints a Markdown table: ns per cell for both, their ratio, heap bytes each
// build adds per cell while its grid is alive, and field bytes copied per cell;
// then GridBuilder's step-to-step table.
#include "CursorBaseline.h"
#include "ForestFingerprint.h"
#include "ForestSlice.h"
#include "MiniAppForest.h"
#include "SyntheticForest.h"

#include <canopy/GridBuilder.h>
#include <canopy/HtgBuilder.h>

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
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace
{

using Clock = std::chrono::steady_clock;
using canopy::bench::emptyGridLike;
using canopy::bench::heapInUse;
using canopy::bench::sameContent;
using canopy::tools::SyntheticForest;

const std::vector<std::string> Fields{"density", "velocity", "refinementLevel"};
/// The mini-app's fields of the same kinds (a scalar, a vector, the level).
const std::vector<std::string> MiniAppFields{"scalar", "velocity", "level"};
/// Mini-app forests measured by default: 2D and 3D, a late step.
const std::vector<std::string> DefaultMiniAppForests{"2,32,9,20", "3,8,4,20"};

/// The obvious adaptor: cursor build plus field copies. Values land at the
/// global index VTK gives each node.
vtkSmartPointer<vtkHyperTreeGrid> buildByCursorAndCopy(const SyntheticForest& forest)
{
  const canopy::ForestDescription& d = forest.description();
  auto htg = emptyGridLike(d);
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

/// The obvious adaptor for leaves-only fields (the mini-app's layout: per leaf,
/// tree after tree, breadth-first within a tree; AoS doubles): cursor build, leaf
/// values copied to their nodes, and each coarse node given the mean of its
/// children on the way back up, summed in child order as Canopy does, so that
/// both grids hold the same values to the bit.
vtkSmartPointer<vtkHyperTreeGrid>
buildLeavesOnlyByCursorAndCopy(const canopy::ForestDescription& d,
                               const std::vector<std::string>& names)
{
  auto htg = emptyGridLike(d);
  const auto total = static_cast<vtkIdType>(canopy::tools::countNodes(d));
  std::vector<const double*> sources;
  std::vector<int> components;
  std::vector<vtkSmartPointer<vtkDoubleArray>> arrays;
  for (const auto& name : names)
  {
    const auto field =
        std::find_if(d.fields.begin(), d.fields.end(),
                     [&](const canopy::FieldDescription& f) { return f.name == name; });
    if (field == d.fields.end() || field->centering != canopy::Centering::LeavesOnly ||
        field->layout != canopy::Layout::AoS || field->type != canopy::ValueType::Float64)
    {
      std::cerr << "bench: '" << name << "' is not a leaves-only AoS double field\n";
      std::exit(1);
    }
    sources.push_back(static_cast<const double*>(field->data));
    components.push_back(field->components);
    auto array = vtkSmartPointer<vtkDoubleArray>::New();
    array->SetName(name.c_str());
    array->SetNumberOfComponents(field->components);
    array->SetNumberOfTuples(total);
    arrays.push_back(array);
  }

  vtkIdType offset = 0;
  std::size_t leafOffset = 0;
  vtkNew<vtkHyperTreeGridNonOrientedCursor> cursor;
  std::vector<std::size_t> firstChild;
  std::vector<std::size_t> leafOf;
  const unsigned perNode = htg->GetNumberOfChildren();
  std::vector<vtkIdType> childGlobal(perNode);
  for (const canopy::TreeDescription& tree : d.trees)
  {
    firstChild.assign(tree.numberOfNodes, 0);
    leafOf.assign(tree.numberOfNodes, 0);
    std::size_t next = 1;
    std::size_t leaves = 0;
    for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
    {
      if (tree.refinement[n])
      {
        firstChild[n] = next;
        next += perNode;
      }
      else
      {
        leafOf[n] = leaves++;
      }
    }
    htg->InitializeNonOrientedCursor(cursor, tree.rootIndex, /*create=*/true);
    cursor->SetGlobalIndexStart(offset);
    auto visit = [&](auto& self, std::size_t n) -> void
    {
      const vtkIdType global = cursor->GetGlobalNodeIndex();
      if (!tree.refinement[n])
      {
        for (std::size_t f = 0; f < arrays.size(); ++f)
        {
          arrays[f]->SetTypedTuple(global, sources[f] + (leafOffset + leafOf[n]) * components[f]);
        }
        return;
      }
      cursor->SubdivideLeaf();
      std::vector<vtkIdType> children(perNode);
      for (unsigned c = 0; c < perNode; ++c)
      {
        cursor->ToChild(static_cast<unsigned char>(c));
        children[c] = cursor->GetGlobalNodeIndex();
        self(self, firstChild[n] + c);
        cursor->ToParent();
      }
      for (std::size_t f = 0; f < arrays.size(); ++f)
      {
        double* values = arrays[f]->GetPointer(0);
        const int nc = components[f];
        for (int k = 0; k < nc; ++k)
        {
          double sum = 0.0;
          for (unsigned c = 0; c < perNode; ++c)
            sum += values[children[c] * nc + k];
          values[global * nc + k] = sum / static_cast<double>(perNode);
        }
      }
    };
    visit(visit, 0);
    offset += static_cast<vtkIdType>(tree.numberOfNodes);
    leafOffset += leaves;
  }
  for (auto& array : arrays)
    htg->GetCellData()->AddArray(array);
  return htg;
}

/// Bytes of cell-field values the grid holds outside the simulation's records.
std::size_t copiedFieldBytes(vtkHyperTreeGrid* htg, const char* begin, const char* end)
{
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

/// Bytes of the synthetic forest's records.
std::pair<const char*, const char*> recordBytes(const SyntheticForest& forest)
{
  const auto* begin = reinterpret_cast<const char*>(forest.cells().data());
  return {begin, begin + forest.cells().size() * sizeof(SyntheticForest::CellRecord)};
}

/// Median ns per cell of `build` over the repetitions; heap growth and copied field
/// bytes (outside [begin, end), the simulation's memory) per cell.
template <typename Build>
Measurement measure(std::size_t numberOfCells, std::pair<const char*, const char*> simulation,
                    int repetitions, Build&& build)
{
  std::vector<double> times;
  Measurement m;
  const double cells = static_cast<double>(numberOfCells);
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
    m.fieldBytesPerCell =
        static_cast<double>(copiedFieldBytes(htg, simulation.first, simulation.second)) / cells;
    if (htg->GetNumberOfCells() != static_cast<vtkIdType>(numberOfCells))
    {
      std::cerr << "bench: wrong number of cells\n";
      std::exit(1);
    }
  }
  std::sort(times.begin(), times.end());
  m.nsPerCell = times[times.size() / 2];
  return m;
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
void printStepRow(canopy::ForestDescription d, const std::string& storage,
                  const std::vector<std::string>& names, int repetitions)
{
  const auto request = canopy::FieldRequest::only(names);
  const std::size_t numberOfCells = canopy::tools::countNodes(d);
  const double cells = static_cast<double>(numberOfCells);
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
  std::cout << std::fixed << std::setprecision(2) << "| " << storage << " | " << numberOfCells
            << " | " << full << " | " << unchanged << " (" << std::setprecision(1)
            << 100 * unchanged / full << "%) | " << std::setprecision(2) << maskChanged << " ("
            << std::setprecision(1) << 100 * maskChanged / full << "%) | ";
  if (twoChanged >= 0)
    std::cout << std::setprecision(2) << twoChanged << " (" << std::setprecision(1)
              << 100 * twoChanged / full << "%) |\n";
  else
    std::cout << "n/a (no two trees of equal size) |\n";
}

} // namespace

/// Real step-to-step change: GridBuilder on the mini-app's next steps (trees
/// refined and coarsened by the simulation), against a full build of the same step.
void printNextStepRow(canopy::tools::MiniAppForest& forest, int repetitions)
{
  const auto request = canopy::FieldRequest::only(MiniAppFields);
  canopy::GridBuilder builder;
  builder.build(forest.description(), request);
  std::vector<double> next;
  std::vector<double> full;
  std::size_t rebuilt = 0;
  std::size_t kept = 0;
  double cells = 0;
  for (int r = 0; r < repetitions; ++r)
  {
    forest.advance();
    const canopy::ForestDescription d = forest.description();
    cells = static_cast<double>(canopy::tools::countNodes(d));
    auto start = Clock::now();
    builder.build(d, request);
    next.push_back(std::chrono::duration<double, std::nano>(Clock::now() - start).count() / cells);
    rebuilt += builder.lastBuild().treesRebuilt;
    kept += builder.lastBuild().treesKept;
    canopy::GridBuilder fresh;
    start = Clock::now();
    fresh.build(d, request);
    full.push_back(std::chrono::duration<double, std::nano>(Clock::now() - start).count() / cells);
  }
  std::sort(next.begin(), next.end());
  std::sort(full.begin(), full.end());
  const double n = next[next.size() / 2];
  const double f = full[full.size() / 2];
  std::cout << std::fixed << std::setprecision(2) << "| " << forest.label() << " | "
            << static_cast<std::size_t>(cells) << " | " << f << " | " << n << " ("
            << std::setprecision(1) << 100 * n / f << "%) | " << rebuilt / repetitions << " / "
            << kept / repetitions << " |\n";
}

int main(int argc, char** argv)
{
  int maxLevels = 8;
  int repetitions = 5;
  std::string csvPath;
  std::string data = "all";
  std::vector<std::string> miniAppSpecs;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--max-levels" && i + 1 < argc)
      maxLevels = std::atoi(argv[++i]);
    else if (arg == "--repetitions" && i + 1 < argc)
      repetitions = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--csv" && i + 1 < argc)
      csvPath = argv[++i];
    else if (arg == "--data" && i + 1 < argc)
      data = argv[++i];
    else if (arg == "--miniapp" && i + 1 < argc)
      miniAppSpecs.push_back(argv[++i]);
    else
    {
      std::cerr
          << "usage: canopy_bench_wrap [--max-levels L] [--repetitions R] [--csv FILE]\n"
             "         [--data synthetic|miniapp|all] [--miniapp DIM,ROOTS,MAX_LEVEL,STEPS]...\n";
      return 2;
    }
  }
  const bool synthetic = data == "all" || data == "synthetic";
  const bool miniApp = data == "all" || data == "miniapp";
  if (!synthetic && !miniApp)
  {
    std::cerr << "canopy_bench_wrap: --data is synthetic, miniapp or all\n";
    return 2;
  }
  if (miniAppSpecs.empty())
    miniAppSpecs = DefaultMiniAppForests;

  // The mini-app's forests first (the simulation needs MPI; one process is enough).
  const bool mpiStarted = miniApp && canopy::tools::initializeMpiIfNeeded(&argc, &argv);
  std::vector<std::unique_ptr<canopy::tools::MiniAppForest>> miniAppForests;
  if (miniApp)
  {
    for (const auto& spec : miniAppSpecs)
    {
      const auto options = canopy::tools::parseMiniAppForest(spec);
      miniAppForests.push_back(std::make_unique<canopy::tools::MiniAppForest>(options));
      std::cerr << "bench: " << miniAppForests.back()->label() << ": "
                << miniAppForests.back()->globalLeaves() << " leaves ("
                << miniAppForests.back()->commandLine() << ")\n"
                << canopy::tools::describeInput(miniAppForests.back()->label(),
                                                miniAppForests.back()->description())
                << "\n";
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
  auto printRow = [&](const std::string& storage, int levels, std::size_t cells,
                      const Measurement& canopyBuild, const Measurement& cursorBuild,
                      double computedBytesPerCell)
  {
    const double speedup = cursorBuild.nsPerCell / canopyBuild.nsPerCell;
    std::cout << std::fixed << "| " << storage << " | " << cells << " | " << std::setprecision(2)
              << canopyBuild.nsPerCell << " | " << cursorBuild.nsPerCell << " | "
              << std::setprecision(1) << speedup << "x | " << std::setprecision(2)
              << canopyBuild.bytesPerCell << " | " << cursorBuild.bytesPerCell << " | "
              << std::setprecision(0) << canopyBuild.fieldBytesPerCell;
    if (computedBytesPerCell > 0)
      std::cout << std::setprecision(1) << " (+" << computedBytesPerCell << " computed)";
    std::cout << std::setprecision(0) << " / " << cursorBuild.fieldBytesPerCell << " |"
              << std::endl;
    if (csv)
    {
      csv << storage << "," << levels << "," << cells << "," << canopyBuild.nsPerCell << ","
          << cursorBuild.nsPerCell << "," << speedup << "," << canopyBuild.bytesPerCell << ","
          << cursorBuild.bytesPerCell << "," << canopyBuild.fieldBytesPerCell << ","
          << cursorBuild.fieldBytesPerCell << "\n";
    }
  };
  for (bool depthFirst : {false, true})
  {
    for (int levels = 5; synthetic && levels <= maxLevels; ++levels)
    {
      canopy::tools::SyntheticForestOptions options;
      options.dimension = 3;
      options.branchFactor = 2;
      options.rootsPerAxis = 6;
      options.maxLevels = levels;
      options.cutaway = false;
      options.depthFirstStorage = depthFirst;
      SyntheticForest forest(options);
      std::cerr << canopy::tools::describeInput("synthetic 3D, 6^3 roots, " +
                                                    std::to_string(levels) + " levels, " +
                                                    (depthFirst ? "depth-first" : "breadth-first"),
                                                forest.description())
                << "\n";
      const int reps = forest.numberOfNodes() > 5'000'000 ? std::min(repetitions, 3) : repetitions;

      const auto request = canopy::FieldRequest::only(Fields);
      const Measurement canopyBuild =
          measure(forest.numberOfNodes(), recordBytes(forest), reps,
                  [&] { return canopy::buildHyperTreeGrid(forest.description(), request); });
      const Measurement cursorBuild = measure(forest.numberOfNodes(), recordBytes(forest), reps,
                                              [&] { return buildByCursorAndCopy(forest); });
      auto a = canopy::buildHyperTreeGrid(forest.description(), request);
      auto b = buildByCursorAndCopy(forest);
      if (!sameContent(a, b, Fields))
      {
        std::cerr << "bench: the two builds disagree; timings are meaningless\n";
        return 1;
      }
      printRow(depthFirst ? "depth-first + slot map" : "breadth-first", levels,
               forest.numberOfNodes(), canopyBuild, cursorBuild, 0);
    }
  }
  for (const auto& forest : miniAppForests)
  {
    // Leaves-only fields: the simulation's memory is its leaf arrays; the coarse
    // averages both builds compute are counted apart.
    const canopy::ForestDescription d = forest->description();
    const std::size_t cells = canopy::tools::countNodes(d);
    const std::size_t leaves = canopy::tools::countLeaves(d);
    const int reps = cells > 5'000'000 ? std::min(repetitions, 3) : repetitions;
    const auto request = canopy::FieldRequest::only(MiniAppFields);
    int components = 0;
    for (const auto& field : d.fields)
      if (std::find(MiniAppFields.begin(), MiniAppFields.end(), field.name) != MiniAppFields.end())
        components += field.components;
    const Measurement canopyBuild = measure(cells, {nullptr, nullptr}, reps,
                                            [&] { return canopy::buildHyperTreeGrid(d, request); });
    Measurement cursorBuild =
        measure(cells, {nullptr, nullptr}, reps,
                [&] { return buildLeavesOnlyByCursorAndCopy(d, MiniAppFields); });
    // The baseline's arrays hold every value: leaves copied, coarse computed.
    const double computed = static_cast<double>((cells - leaves) * components * 8) / cells;
    cursorBuild.fieldBytesPerCell -= computed;
    auto a = canopy::buildHyperTreeGrid(d, request);
    auto b = buildLeavesOnlyByCursorAndCopy(d, MiniAppFields);
    if (!sameContent(a, b, MiniAppFields))
    {
      std::cerr << "bench: the two builds of " << forest->label()
                << " disagree; timings are meaningless\n";
      return 1;
    }
    printRow(forest->label() + " (breadth-first, leaves-only)", -1, cells, canopyBuild, cursorBuild,
             computed);
  }

  std::cout << "\nSteps after the first with canopy::GridBuilder (ns per cell, median; % of a "
               "full build):\n\n"
            << "| storage | cells | full build | nothing changed | one mask byte changed | "
               "two trees changed |\n"
            << "|---|---:|---:|---:|---:|---:|\n";
  for (bool depthFirst : {false, true})
  {
    for (int levels = 5; synthetic && levels <= maxLevels; ++levels)
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
      printStepRow(forest.description(), depthFirst ? "depth-first + slot map" : "breadth-first",
                   Fields, reps);
    }
  }
  for (const auto& forest : miniAppForests)
    printStepRow(forest->description(), forest->label() + " (breadth-first, leaves-only)",
                 MiniAppFields, repetitions);
  if (!miniAppForests.empty())
  {
    std::cout << "\nThe mini-app's next steps (real refinement and coarsening) with "
                 "canopy::GridBuilder (ns per cell, median over "
              << std::min(repetitions, 3) << " steps):\n\n"
              << "| forest | cells | full build | next step with GridBuilder | trees rebuilt / "
                 "kept |\n|---|---:|---:|---:|---:|\n";
    for (const auto& forest : miniAppForests)
      printNextStepRow(*forest, std::min(repetitions, 3));
  }
  printVtkFloor();
  miniAppForests.clear();
  if (mpiStarted)
    MPI_Finalize();
  return 0;
}
