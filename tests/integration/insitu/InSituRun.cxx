// A stand-in simulation for the in-situ tests: it owns a forest (paper case A
// or B, or a synthetic front that moves each step), gives each MPI rank its
// share (whole trees, or every tree split p4est-style with the parts a rank
// does not own masked), and calls canopy::InSitu every step exactly as a
// simulation would. Rank 0 prints each step's report and writes the
// brute-force totals the output checkers compare against (expected.json).
//
// Usage: canopy_insitu_run --output DIR --script PATH [--arg ARG]... [options]
//   --case A|A-masked|B|B-masked|moving-2d|moving-2d-masked|moving-3d   (A)
//   --steps N (1)  --distribute trees|split (trees)  --empty-rank R
//   --corrupt-rank R --corrupt-step S   (that rank passes a malformed tree then)
//   --limit-file-at-step S FILE   (from step S on, no file may grow more than
//                                  16 KiB beyond FILE's size then: writes fail)
//   --no-close (rely on MPI_Finalize)  --summary
//   --forest-json   (rank 0 also writes forest_<step>.json: the whole forest, who owns
//                    each tree, sampled values; for the extract checkers)
//   --rename-field OLD=NEW   (the simulation calls field OLD by the name NEW)
//   --time-limit SECONDS     (InSituOptions::stepTimeLimitSeconds)
//   --expected PATH          (where rank 0 writes the totals; OUTPUT/expected.json)
//   --fill-disk-step S       (for step S, the output's disk looks full: --leave-free
//                             BYTES (8192) free, then ENOSPC; through the write-fault
//                             shim the checker preloads, tests/support/write_fault_shim.c)
//   --write-fault-step S --write-fault "ERRNO BYTES [WORDS]"  (for step S, writes
//                             under the output fail with ERRNO after BYTES per rank,
//                             the free space looking ample: errors in the middle of
//                             writing; WORDS aim at one rank or kind of write, see the
//                             shim; the pair may be given for several steps)
//   --query EXPR             (InSituOptions::queries; printed each step: "  query TEXT = V")
//   --known-fields A,B       (InSituOptions::fields: triggers checked against them at open)
//   --will-execute           (willExecute(step, time, forest) before each execute;
//                             printed: "step S will execute 0|1")
//   --obstruct-step S --obstruct NAME  (before step S, a folder NAME in the output
//                             directory stands where a pipeline writes a file)
#include "DescriptorForest.h"
#include "ForestJson.h"
#include "PaperCaseDefinitions.h"
#include "SyntheticForest.h"

#include <canopy/InSitu.h>

#include <mpi.h>
#include <sys/resource.h>

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace
{

struct Arguments
{
  std::string output;
  std::string forestCase = "A";
  std::vector<canopy::PipelineScript> scripts;
  int steps = 1;
  std::string distribute = "trees";
  int emptyRank = -1;
  int corruptRank = -1;
  int corruptStep = -1;
  int limitStep = -1;
  std::string limitFile;
  bool close = true;
  std::vector<std::string> queries;
  std::vector<std::string> knownFields;
  bool willExecute = false;
  bool summary = false;
  bool forestJson = false;
  std::map<std::string, std::string> renamedFields;
  double timeLimit = 0.0;
  std::string expected;
  long long leaveFree = 8192;
  std::map<int, std::string> writeFaults; ///< step -> the shim's control line for it
  int lastFaultStep = -1;                 ///< the step the next --write-fault is for
  int obstructStep = -1;
  std::string obstruct;
};

Arguments parse(int argc, char** argv)
{
  Arguments a;
  for (int i = 1; i < argc; ++i)
  {
    const std::string key = argv[i];
    auto value = [&]() -> std::string
    {
      if (i + 1 >= argc)
      {
        throw std::invalid_argument(key + " needs a value");
      }
      return argv[++i];
    };
    if (key == "--output")
      a.output = value();
    else if (key == "--case")
      a.forestCase = value();
    else if (key == "--script")
      a.scripts.push_back({value(), {}});
    else if (key == "--arg")
    {
      if (a.scripts.empty())
        throw std::invalid_argument("--arg before any --script");
      a.scripts.back().arguments.push_back(value());
    }
    else if (key == "--steps")
      a.steps = std::stoi(value());
    else if (key == "--distribute")
      a.distribute = value();
    else if (key == "--empty-rank")
      a.emptyRank = std::stoi(value());
    else if (key == "--corrupt-rank")
      a.corruptRank = std::stoi(value());
    else if (key == "--corrupt-step")
      a.corruptStep = std::stoi(value());
    else if (key == "--limit-file-at-step")
    {
      a.limitStep = std::stoi(value());
      a.limitFile = value();
    }
    else if (key == "--no-close")
      a.close = false;
    else if (key == "--query")
      a.queries.push_back(value());
    else if (key == "--known-fields")
    {
      std::stringstream names(value());
      for (std::string name; std::getline(names, name, ',');)
        a.knownFields.push_back(name);
    }
    else if (key == "--will-execute")
      a.willExecute = true;
    else if (key == "--summary")
      a.summary = true;
    else if (key == "--forest-json")
      a.forestJson = true;
    else if (key == "--time-limit")
      a.timeLimit = std::stod(value());
    else if (key == "--expected")
      a.expected = value();
    else if (key == "--fill-disk-step" || key == "--write-fault-step")
    {
      a.lastFaultStep = std::stoi(value());
      a.writeFaults[a.lastFaultStep] = "ENOSPC " + std::to_string(a.leaveFree) + " statvfs";
    }
    else if (key == "--leave-free")
    {
      a.leaveFree = std::stoll(value());
      for (auto& [step, control] : a.writeFaults)
        if (control.rfind("ENOSPC", 0) == 0)
          control = "ENOSPC " + std::to_string(a.leaveFree) + " statvfs";
    }
    else if (key == "--write-fault")
    {
      if (a.lastFaultStep < 0)
        throw std::runtime_error("--write-fault needs a --write-fault-step before it");
      a.writeFaults[a.lastFaultStep] = value();
    }
    else if (key == "--obstruct-step")
      a.obstructStep = std::stoi(value());
    else if (key == "--obstruct")
      a.obstruct = value();
    else if (key == "--rename-field")
    {
      const std::string pair = value();
      const auto equals = pair.find('=');
      if (equals == std::string::npos)
        throw std::invalid_argument("--rename-field needs OLD=NEW");
      a.renamedFields[pair.substr(0, equals)] = pair.substr(equals + 1);
    }
    else
      throw std::invalid_argument("unknown option " + key);
  }
  if (a.output.empty())
  {
    throw std::invalid_argument("--output is required");
  }
  if (a.expected.empty())
  {
    a.expected = a.output + "/expected.json";
  }
  return a;
}

/// A whole forest, as the simulation holds it before distribution.
class SimulationState
{
public:
  virtual ~SimulationState() = default;
  virtual const canopy::ForestDescription& forest() const = 0;
};

class DescriptorState : public SimulationState
{
public:
  explicit DescriptorState(const canopy::testing::SourceParameters& p) : Forest(p) {}
  const canopy::ForestDescription& forest() const override { return Forest.description(); }

private:
  canopy::testing::DescriptorForest Forest;
};

class SyntheticState : public SimulationState
{
public:
  SyntheticState(int dimension, int step, bool masked = false)
  {
    canopy::tools::SyntheticForestOptions o;
    o.dimension = dimension;
    o.rootsPerAxis = dimension == 2 ? 8 : 4;
    o.maxLevels = dimension == 2 ? 7 : 5;
    o.cutaway = masked;
    o.frontRadius = 0.3 + 0.08 * step; // the front moves outwards every step
    Forest = std::make_unique<canopy::tools::SyntheticForest>(o);
  }
  const canopy::ForestDescription& forest() const override { return Forest->description(); }

private:
  std::unique_ptr<canopy::tools::SyntheticForest> Forest;
};

std::unique_ptr<SimulationState> makeState(const std::string& name, int step)
{
  using namespace canopy::testing;
  if (name == "A" || name == "A-masked")
    return std::make_unique<DescriptorState>(paperCaseA(name == "A-masked"));
  if (name == "B" || name == "B-masked")
    return std::make_unique<DescriptorState>(paperCaseB(name == "B-masked"));
  if (name == "moving-2d")
    return std::make_unique<SyntheticState>(2, step);
  if (name == "moving-2d-masked")
    return std::make_unique<SyntheticState>(2, step, true);
  if (name == "moving-3d")
    return std::make_unique<SyntheticState>(3, step);
  throw std::invalid_argument("unknown case " + name);
}

/// Per node of a tree, breadth-first: level and integer position at that level.
struct NodeInfo
{
  int level;
  std::int64_t position[3];
  bool visible;
};

std::vector<NodeInfo> walkTree(const canopy::ForestDescription& f,
                               const canopy::TreeDescription& tree, const std::uint8_t* mask)
{
  const int b = f.branchFactor;
  const int children = f.dimension == 2 ? b * b : b * b * b;
  std::vector<NodeInfo> nodes;
  nodes.reserve(tree.numberOfNodes);
  nodes.push_back({0, {0, 0, 0}, !(mask && mask[0])});
  // The flat axis of a 2D forest: the one with a single point.
  const std::size_t points[3] = {f.rootGrid.pointsX, f.rootGrid.pointsY, f.rootGrid.pointsZ};
  std::vector<int> axes;
  for (int a = 0; a < 3; ++a)
    if (f.dimension == 3 || points[a] > 1)
      axes.push_back(a);
  for (std::size_t n = 0; n < nodes.size() && nodes.size() < tree.numberOfNodes; ++n)
  {
    if (!tree.refinement[n])
      continue;
    for (int c = 0; c < children; ++c)
    {
      NodeInfo child{nodes[n].level + 1, {0, 0, 0}, false};
      int rest = c;
      for (int a = 0; a < 3; ++a)
        child.position[a] = nodes[n].position[a];
      for (int a : axes)
      {
        child.position[a] = nodes[n].position[a] * b + rest % b;
        rest /= b;
      }
      const std::size_t index = nodes.size();
      child.visible = nodes[n].visible && !(mask && mask[index]);
      nodes.push_back(child);
    }
  }
  return nodes;
}

/// Every node's storage slot, tree by tree (the description's own order).
std::vector<std::vector<std::int64_t>> slotsOf(const canopy::ForestDescription& f)
{
  std::vector<std::vector<std::int64_t>> slots;
  std::int64_t next = 0;
  for (const auto& tree : f.trees)
  {
    std::vector<std::int64_t> s(tree.numberOfNodes);
    for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
      s[n] = tree.storageSlots ? tree.storageSlots[n] : next + static_cast<std::int64_t>(n);
    next += static_cast<std::int64_t>(tree.numberOfNodes);
    slots.push_back(std::move(s));
  }
  return slots;
}

/// What this rank hands to Canopy: its own copy of the data of its trees, in
/// its own breadth-first order (as a distributed simulation stores it).
class RankForest
{
public:
  RankForest(const canopy::ForestDescription& whole, const std::vector<std::size_t>& ownTrees)
  {
    Description.dimension = whole.dimension;
    Description.branchFactor = whole.branchFactor;
    Description.maxLevels = whole.maxLevels;
    Description.rootGrid = whole.rootGrid;
    const auto slots = slotsOf(whole);
    // Leaves-only fields are indexed by leaf rank in slot order.
    std::vector<std::int64_t> leafIndexOfSlot;
    {
      std::int64_t total = 0;
      for (const auto& s : slots)
        total += static_cast<std::int64_t>(s.size());
      std::vector<char> isLeaf(static_cast<std::size_t>(total), 0);
      for (std::size_t t = 0; t < whole.trees.size(); ++t)
        for (std::size_t n = 0; n < whole.trees[t].numberOfNodes; ++n)
          isLeaf[static_cast<std::size_t>(slots[t][n])] = whole.trees[t].refinement[n] ? 0 : 1;
      leafIndexOfSlot.assign(isLeaf.size(), -1);
      std::int64_t leaf = 0;
      for (std::size_t s = 0; s < isLeaf.size(); ++s)
        if (isLeaf[s])
          leafIndexOfSlot[s] = leaf++;
    }
    for (const auto& field : whole.fields)
    {
      const std::size_t valueBytes = canopy::sizeOf(field.type);
      const std::size_t tupleBytes = valueBytes * static_cast<std::size_t>(field.components);
      auto& bytes = Storage.emplace_back();
      std::size_t tuples = 0;
      for (std::size_t t : ownTrees)
      {
        const auto& tree = whole.trees[t];
        for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
        {
          std::int64_t index = slots[t][n];
          if (field.centering == canopy::Centering::LeavesOnly)
          {
            if (tree.refinement[n])
              continue;
            index = leafIndexOfSlot[static_cast<std::size_t>(index)];
          }
          const auto i = static_cast<std::size_t>(index);
          for (int c = 0; c < field.components; ++c)
          {
            const char* source = nullptr;
            const auto cc = static_cast<std::size_t>(c);
            switch (field.layout)
            {
            case canopy::Layout::AoS:
              source = static_cast<const char*>(field.data) + i * tupleBytes + cc * valueBytes;
              break;
            case canopy::Layout::Strided:
              source = static_cast<const char*>(field.data) + i * field.tupleStrideBytes +
                       cc * valueBytes;
              break;
            case canopy::Layout::SoA:
              source = static_cast<const char*>(field.componentData[cc]) + i * valueBytes;
              break;
            case canopy::Layout::Indirect:
              source = static_cast<const char*>(field.tupleAddresses[i]) + cc * valueBytes;
              break;
            case canopy::Layout::Blocks:
              throw std::invalid_argument("InSituRun splits forests of tuples, not of blocks");
            }
            bytes.insert(bytes.end(), source, source + valueBytes);
          }
          ++tuples;
        }
      }
      canopy::FieldDescription local = field;
      local.layout = canopy::Layout::AoS;
      local.componentData.clear();
      local.tupleStrideBytes = 0;
      local.data = bytes.data();
      local.numberOfTuples = tuples;
      Description.fields.push_back(local);
    }
    for (std::size_t t : ownTrees)
    {
      canopy::TreeDescription tree = whole.trees[t];
      tree.storageSlots = nullptr; // this rank stores its trees breadth-first, back to back
      Description.trees.push_back(tree);
    }
  }
  canopy::ForestDescription& description() { return Description; }

private:
  std::vector<std::vector<char>> Storage;
  canopy::ForestDescription Description;
};

/// Split mode: every rank describes every tree, masking what it does not own:
/// a level-1 child subtree belongs to rank (child index % ranks); an unrefined
/// root to rank (tree position % ranks).
class SplitForest
{
public:
  SplitForest(const canopy::ForestDescription& whole, int rank, int size) : Description(whole)
  {
    for (std::size_t t = 0; t < whole.trees.size(); ++t)
    {
      const auto& tree = whole.trees[t];
      std::vector<std::uint8_t> mask(tree.numberOfNodes, 0);
      if (tree.masked)
        mask.assign(tree.masked, tree.masked + tree.numberOfNodes);
      if (!tree.refinement[0])
      {
        if (static_cast<int>(t % static_cast<std::size_t>(size)) != rank)
          mask[0] = 1;
      }
      else
      {
        const int children = whole.dimension == 2
                                 ? whole.branchFactor * whole.branchFactor
                                 : whole.branchFactor * whole.branchFactor * whole.branchFactor;
        for (int c = 0; c < children; ++c)
          if (c % size != rank)
            mask[1 + static_cast<std::size_t>(c)] = 1;
      }
      Masks.push_back(std::move(mask));
    }
    for (std::size_t t = 0; t < Description.trees.size(); ++t)
      Description.trees[t].masked = Masks[t].data();
  }
  canopy::ForestDescription& description() { return Description; }

private:
  std::vector<std::vector<std::uint8_t>> Masks;
  canopy::ForestDescription Description;
};

/// Makes writes under the output fail for one step: writes the write-fault
/// shim's control file (tests/support/write_fault_shim.c, preloaded by the
/// checker) with `control` ("ENOSPC 8192 statvfs": a disk with 8192 bytes
/// free; "EIO 3000": writes fail after 3000 bytes); returns its path, to remove
/// after the step.
std::string startWriteFaults(const std::string& control)
{
  const char* path = std::getenv("CANOPY_WRITE_FAULT_CONTROL");
  if (path == nullptr || std::getenv("LD_PRELOAD") == nullptr)
    throw std::runtime_error("--fill-disk-step and --write-fault-step need the write-fault "
                             "shim preloaded (LD_PRELOAD) and CANOPY_WRITE_FAULT_CONTROL set");
  std::ofstream out(path);
  out << control << "\n";
  if (!out.flush())
    throw std::runtime_error(std::string("cannot write ") + path);
  return path;
}

/// Brute-force totals of the whole forest (rank 0 writes them for the checkers).
/// `owners`: the rank of each tree (by position in f.trees) when ranks own whole
/// trees, else empty; then rank_boundary_faces counts, besides the domain's
/// boundary, each leaf face against a tree of another rank: every rank's
/// full-resolution 3D surface draws the boundary of its own part.
std::string totalsJson(const canopy::ForestDescription& f, int step, double time,
                       const std::vector<int>& owners)
{
  std::int64_t leaves = 0;
  std::int64_t nodesTotal = 0;
  std::int64_t boundaryFaces = 0;
  std::map<int, std::int64_t> byLevel;
  std::int64_t rootCells[3] = {1, 1, 1};
  const std::size_t points[3] = {f.rootGrid.pointsX, f.rootGrid.pointsY, f.rootGrid.pointsZ};
  for (int a = 0; a < 3; ++a)
    rootCells[a] = points[a] > 1 ? static_cast<std::int64_t>(points[a]) - 1 : 1;
  std::map<std::int64_t, std::size_t> treeAt; // root index -> position in f.trees
  for (std::size_t t = 0; t < f.trees.size(); ++t)
    treeAt[f.trees[t].rootIndex] = t;
  std::int64_t facesBetweenRanks = 0;
  for (std::size_t t = 0; t < f.trees.size(); ++t)
  {
    const auto& tree = f.trees[t];
    const auto nodes = walkTree(f, tree, tree.masked);
    nodesTotal += static_cast<std::int64_t>(nodes.size());
    const std::int64_t root[3] = {tree.rootIndex % rootCells[0],
                                  (tree.rootIndex / rootCells[0]) % rootCells[1],
                                  tree.rootIndex / (rootCells[0] * rootCells[1])};
    for (std::size_t n = 0; n < nodes.size(); ++n)
    {
      if (tree.refinement[n] || !nodes[n].visible)
        continue;
      ++leaves;
      ++byLevel[nodes[n].level];
      if (f.dimension == 3)
      {
        const auto scale = static_cast<std::int64_t>(std::pow(f.branchFactor, nodes[n].level));
        for (int a = 0; a < 3; ++a)
        {
          const std::int64_t g = root[a] * scale + nodes[n].position[a];
          boundaryFaces += (g == 0) + (g == rootCells[a] * scale - 1);
          for (int side : {-1, 1})
          {
            const bool onTreeFace =
                side < 0 ? nodes[n].position[a] == 0 : nodes[n].position[a] == scale - 1;
            const std::int64_t across = root[a] + side;
            if (owners.empty() || !onTreeFace || across < 0 || across >= rootCells[a])
              continue;
            std::int64_t neighbour[3] = {root[0], root[1], root[2]};
            neighbour[a] = across;
            const auto found = treeAt.find(neighbour[0] + rootCells[0] * neighbour[1] +
                                           rootCells[0] * rootCells[1] * neighbour[2]);
            if (found == treeAt.end() || owners[found->second] != owners[t])
              ++facesBetweenRanks;
          }
        }
      }
    }
  }
  std::ostringstream json;
  json << "{\"step\": " << step << ", \"time\": " << time << ", \"leaves\": " << leaves
       << ", \"nodes\": " << nodesTotal << ", \"trees\": " << f.trees.size()
       << ", \"boundary_faces\": " << boundaryFaces;
  if (!owners.empty())
    json << ", \"rank_boundary_faces\": " << boundaryFaces + facesBetweenRanks;
  json << ", \"leaves_by_level\": {";
  bool first = true;
  for (const auto& [level, count] : byLevel)
  {
    json << (first ? "" : ", ") << "\"" << level << "\": " << count;
    first = false;
  }
  json << "}}";
  return json.str();
}

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  int rank = 0;
  int size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int status = 0;
  std::unique_ptr<canopy::InSitu> insitu;
  try
  {
    const Arguments args = parse(argc, argv);
    canopy::InSituOptions options;
    options.scripts = args.scripts;
    options.outputDirectory = args.output;
    options.stepSummary = args.summary;
    options.stepTimeLimitSeconds = args.timeLimit;
    options.queries = args.queries;
    options.fields = args.knownFields;
    insitu = std::make_unique<canopy::InSitu>(MPI_COMM_WORLD, options);

    std::ofstream expected;
    if (rank == 0)
      expected.open(args.expected);
    if (rank == 0)
      expected << "[\n";
    for (int step = 0; step < args.steps; ++step)
    {
      const double time = 0.1 * step;
      auto state = makeState(args.forestCase, step);
      const auto& whole = state->forest();
      if (rank == 0)
      {
        // Who owns each tree when ranks own whole trees (as below), for the
        // exact count of each rank's surface.
        std::vector<int> treeOwners;
        const int owning = args.emptyRank >= 0 && size > 1 ? size - 1 : size;
        for (std::size_t t = 0; args.distribute != "split" && t < whole.trees.size(); ++t)
        {
          const int me = static_cast<int>(t % static_cast<std::size_t>(owning));
          treeOwners.push_back(args.emptyRank >= 0 && me >= args.emptyRank ? me + 1 : me);
        }
        expected << (step ? ",\n" : "") << totalsJson(whole, step, time, treeOwners);
      }

      if (rank == 0 && args.forestJson)
      {
        // Who writes each tree: round robin over the ranks that own any (split: all).
        std::vector<int> owners(whole.trees.size(), -1);
        const int count = args.emptyRank >= 0 && size > 1 ? size - 1 : size;
        for (std::size_t t = 0; t < owners.size() && args.distribute != "split"; ++t)
        {
          const int owner = static_cast<int>(t % static_cast<std::size_t>(count));
          owners[t] =
              args.emptyRank >= 0 && size > 1 && owner >= args.emptyRank ? owner + 1 : owner;
        }
        std::ofstream(args.output + "/forest_" + std::to_string(step) + ".json")
            << canopy::testing::forestJson(whole, owners, step, time, size);
      }
      std::unique_ptr<RankForest> byTrees;
      std::unique_ptr<SplitForest> split;
      canopy::ForestDescription* local = nullptr;
      if (args.distribute == "split")
      {
        split = std::make_unique<SplitForest>(whole, rank, size);
        local = &split->description();
      }
      else
      {
        // Whole trees, round robin over the ranks that own any.
        std::vector<std::size_t> own;
        const int owners = args.emptyRank >= 0 && size > 1 ? size - 1 : size;
        const int me = args.emptyRank >= 0 && rank > args.emptyRank ? rank - 1 : rank;
        for (std::size_t t = 0; t < whole.trees.size(); ++t)
          if (rank != args.emptyRank &&
              static_cast<int>(t % static_cast<std::size_t>(owners)) == me)
            own.push_back(t);
        byTrees = std::make_unique<RankForest>(whole, own);
        local = &byTrees->description();
      }
      if (step == args.limitStep)
      {
        // A file-size limit (RLIMIT_FSIZE) makes writes past it fail with EFBIG, as a
        // full disk makes them fail with ENOSPC, without a filesystem to fill.
        std::error_code ignored;
        const auto size = std::filesystem::file_size(args.limitFile, ignored);
        std::signal(SIGXFSZ, SIG_IGN);
        const rlimit limit{static_cast<rlim_t>(size) + 16384, static_cast<rlim_t>(size) + 16384};
        setrlimit(RLIMIT_FSIZE, &limit);
      }
      for (auto& field : local->fields)
      {
        const auto renamed = args.renamedFields.find(field.name);
        if (renamed != args.renamedFields.end())
          field.name = renamed->second;
      }
      if (rank == args.corruptRank && step == args.corruptStep && !local->trees.empty())
      {
        // One byte short: the refinement does not describe a complete tree.
        local->trees[0].numberOfNodes -= 1;
      }
      std::string filler;
      const auto fault = args.writeFaults.find(step);
      if (fault != args.writeFaults.end())
      {
        if (rank == 0)
          filler = startWriteFaults(fault->second);
        MPI_Barrier(MPI_COMM_WORLD);
      }
      if (step == args.obstructStep)
      {
        if (rank == 0)
          mkdir((args.output + "/" + args.obstruct).c_str(), 0755);
        MPI_Barrier(MPI_COMM_WORLD);
      }
      std::string willText;
      if (args.willExecute)
      {
        const bool will = insitu->willExecute(step, time, *local);
        willText = "step " + std::to_string(step) + " will execute " + (will ? "1" : "0") + "\n";
      }
      const auto report = insitu->execute(step, time, *local);
      if (!filler.empty())
        std::remove(filler.c_str());
      if (fault != args.writeFaults.end())
        MPI_Barrier(MPI_COMM_WORLD); // the disk has space again on every rank's next step
      if (rank == 0)
      {
        // One write per report: the checker reads stdout and ParaView's stderr
        // from one pipe, and whole lines must not interleave.
        std::ostringstream text;
        text << willText;
        text.precision(17);
        for (const auto& [name, value] : report.expressions)
          text << "  query " << name << " = " << value << "\n";
        for (const auto& name : report.triggersFired)
          text << "  fired " << name << "\n";
        text << "step " << step << (report.executed ? " executed" : " idle") << " ran "
             << report.pipelinesRun.size() << " failures " << report.failures.size() << "\n";
        for (const auto& failure : report.failures)
          text << "  failure: " << failure << "\n";
        std::cout << text.str() << std::flush;
      }
    }
    if (rank == 0)
      expected << "\n]\n";
    if (args.close)
    {
      insitu->close();
      if (rank == 0)
        std::cout << "closed\n" << std::flush;
    }
  }
  catch (const std::exception& error)
  {
    std::cerr << "rank " << rank << ": " << error.what() << "\n";
    status = 2;
  }
  if (status == 0 && insitu && insitu->isOpen())
  {
    // --no-close: MPI_Finalize itself must close the driver (Catalyst first).
    MPI_Finalize();
    const bool closedByFinalize = !insitu->isOpen();
    if (rank == 0)
      std::cout << (closedByFinalize ? "MPI_Finalize closed the driver\n"
                                     : "the driver is still open after MPI_Finalize\n");
    insitu.reset();
    return closedByFinalize ? 0 : 1;
  }
  insitu.reset();
  MPI_Finalize();
  return status;
}
