#include "MiniAppForest.h"

#include "MiniAppOptions.h"
#include "Simulation.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace canopy::tools
{

MiniAppForest::MiniAppForest(const MiniAppForestOptions& options, MPI_Comm communicator)
    : Options(options)
{
  // Through the mini-app's own parser, so that every other setting (objects,
  // physics, regridding) is its default, as on its command line.
  std::vector<std::string> words{"canopy_miniamr",
                                 "--dimension",
                                 std::to_string(options.dimension),
                                 "--roots",
                                 std::to_string(options.roots),
                                 "--max-level",
                                 std::to_string(options.maxLevel),
                                 "--steps",
                                 std::to_string(options.steps),
                                 "--regrid-every",
                                 std::to_string(options.regridEvery),
                                 "--no-insitu",
                                 "--quiet"};
  std::vector<char*> argv;
  for (auto& word : words)
    argv.push_back(word.data());
  const miniamr::MiniAppOptions parsed =
      miniamr::parseOptions(static_cast<int>(argv.size()), argv.data());
  Simulation = std::make_unique<miniamr::Simulation>(parsed, communicator);
  for (int s = 0; s < options.steps; ++s)
    Simulation->advance();
}

MiniAppForest::~MiniAppForest() = default;

ForestDescription MiniAppForest::description() const
{
  return Simulation->describeForCanopy();
}

void MiniAppForest::advance()
{
  Simulation->advance();
}

int MiniAppForest::step() const
{
  return Simulation->step();
}

std::int64_t MiniAppForest::globalLeaves() const
{
  return Simulation->globalLeaves();
}

std::int64_t MiniAppForest::globalNodes() const
{
  return Simulation->globalNodes();
}

std::size_t MiniAppForest::localNodes() const
{
  std::size_t nodes = 0;
  for (const auto& tree : description().trees)
    nodes += tree.numberOfNodes;
  return nodes;
}

std::string MiniAppForest::label() const
{
  const std::string r = std::to_string(Options.roots);
  return "mini-app " + std::to_string(Options.dimension) + "D, " + r + "^" +
         std::to_string(Options.dimension) + " roots, " + std::to_string(Options.maxLevel) +
         " levels, step " + std::to_string(step()) +
         (Options.regridEvery > 1 ? ", regrid every " + std::to_string(Options.regridEvery) : "");
}

std::string MiniAppForest::commandLine() const
{
  return "canopy_miniamr --dimension " + std::to_string(Options.dimension) + " --roots " +
         std::to_string(Options.roots) + " --max-level " + std::to_string(Options.maxLevel) +
         " --steps " + std::to_string(step()) +
         (Options.regridEvery > 1 ? " --regrid-every " + std::to_string(Options.regridEvery) : "");
}

MiniAppForestOptions parseMiniAppForest(const std::string& text)
{
  std::vector<int> numbers;
  std::size_t start = 0;
  while (start <= text.size())
  {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    try
    {
      numbers.push_back(std::stoi(text.substr(start, comma - start)));
    }
    catch (const std::exception&)
    {
      numbers.clear();
      break;
    }
    start = comma + 1;
  }
  if ((numbers.size() != 4 && numbers.size() != 5) || (numbers[0] != 2 && numbers[0] != 3) ||
      numbers[1] < 1 || numbers[2] < 0 || numbers[3] < 0 || (numbers.size() == 5 && numbers[4] < 1))
    throw std::invalid_argument(
        "mini-app forest '" + text +
        "': expected DIMENSION,ROOTS,MAX_LEVEL,STEPS[,REGRID_EVERY], e.g. 2,32,9,20");
  MiniAppForestOptions o;
  o.dimension = numbers[0];
  o.roots = numbers[1];
  o.maxLevel = numbers[2];
  o.steps = numbers[3];
  o.regridEvery = numbers.size() == 5 ? numbers[4] : 1;
  return o;
}

bool initializeMpiIfNeeded(int* argc, char*** argv)
{
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (initialized)
    return false;
  MPI_Init(argc, argv);
  return true;
}

} // namespace canopy::tools
