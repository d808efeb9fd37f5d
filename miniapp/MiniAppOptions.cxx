#include "MiniAppOptions.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>

namespace miniamr
{
namespace
{

std::vector<double> numbers(const std::string& text, const std::string& option)
{
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ','))
  {
    try
    {
      std::size_t used = 0;
      values.push_back(std::stod(item, &used));
      if (used != item.size() || !std::isfinite(values.back()))
        throw std::invalid_argument(item);
    }
    catch (const std::exception&)
    {
      throw std::invalid_argument(option + ": '" + item + "' is not a finite number");
    }
  }
  return values;
}

/// Exactly one finite number.
double single(const std::string& text, const std::string& option)
{
  const auto values = numbers(text, option);
  if (values.size() != 1 || !std::isfinite(values[0]))
    throw std::invalid_argument(option + " needs one finite number, not '" + text + "'");
  return values[0];
}

/// Exactly one integer that fits an int.
int integer(const std::string& text, const std::string& option)
{
  const double value = single(text, option);
  if (value != std::floor(value) || std::abs(value) > 1e9)
    throw std::invalid_argument(option + " needs an integer, not '" + text + "'");
  return static_cast<int>(value);
}

MovingObject parseObject(const std::string& text, int dimension)
{
  const auto colon = text.find(':');
  const std::string kind = text.substr(0, colon);
  const auto v = numbers(colon == std::string::npos ? "" : text.substr(colon + 1), "--object");
  const std::size_t d = static_cast<std::size_t>(dimension);
  MovingObject object;
  if (kind == "sphere")
  {
    if (v.size() != 2 * d + 1)
      throw std::invalid_argument(
          "--object sphere:" + std::string(d == 2 ? "cx,cy,r,vx,vy" : "cx,cy,cz,r,vx,vy,vz") +
          " (got '" + text + "')");
    object.kind = MovingObject::Kind::Sphere;
    for (std::size_t a = 0; a < d; ++a)
    {
      object.center[a] = v[a];
      object.velocity[a] = v[d + 1 + a];
    }
    object.radius = v[d];
    if (object.radius <= 0)
      throw std::invalid_argument("--object sphere: the radius must be positive");
  }
  else if (kind == "plane")
  {
    if (v.size() != d + 2)
      throw std::invalid_argument("--object plane:" + std::string(d == 2 ? "nx,ny" : "nx,ny,nz") +
                                  ",offset,speed (got '" + text + "')");
    object.kind = MovingObject::Kind::Plane;
    double length = 0;
    for (std::size_t a = 0; a < d; ++a)
    {
      object.normal[a] = v[a];
      length += v[a] * v[a];
    }
    if (length == 0)
      throw std::invalid_argument("--object plane: the normal is zero");
    for (auto& n : object.normal)
      n /= std::sqrt(length);
    object.offset = v[d];
    object.speed = v[d + 1];
  }
  else
  {
    throw std::invalid_argument("--object: '" + kind + "' is not sphere or plane");
  }
  return object;
}

/// The options that only store one integer or one number: where each goes.
const std::map<std::string, int MiniAppOptions::*> integerOptions = {
    {"--dimension", &MiniAppOptions::dimension},
    {"--branch-factor", &MiniAppOptions::branchFactor},
    {"--max-level", &MiniAppOptions::maxLevel},
    {"--blocks", &MiniAppOptions::blocks},
    {"--regrid-every", &MiniAppOptions::regridEvery},
    {"--image-every", &MiniAppOptions::imageEvery},
    {"--selection-every", &MiniAppOptions::selectionEvery},
    {"--extract-every", &MiniAppOptions::extractEvery}};
const std::map<std::string, double MiniAppOptions::*> numberOptions = {
    {"--cfl", &MiniAppOptions::cfl},
    {"--diffusion", &MiniAppOptions::diffusion},
    {"--refine-gradient", &MiniAppOptions::refineGradient},
    {"--coarsen-gradient", &MiniAppOptions::coarsenGradient},
    {"--repartition-imbalance", &MiniAppOptions::repartitionImbalance},
    {"--live-pause-limit", &MiniAppOptions::livePauseLimit},
    {"--live-stall-limit", &MiniAppOptions::liveStallLimit}};

} // namespace

MiniAppOptions parseOptions(int argc, char** argv)
{
  MiniAppOptions o;
  std::vector<std::string> objectTexts;
  bool velocityGiven = false;
  bool stepsGiven = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string key = argv[i];
    auto value = [&]() -> std::string
    {
      if (i + 1 >= argc)
        throw std::invalid_argument(key + " needs a value");
      return argv[++i];
    };
    const auto integerOption = integerOptions.find(key);
    const auto numberOption = numberOptions.find(key);
    if (key == "--help" || key == "-h")
      throw std::invalid_argument("");
    else if (integerOption != integerOptions.end())
      o.*(integerOption->second) = integer(value(), key);
    else if (numberOption != numberOptions.end())
      o.*(numberOption->second) = single(value(), key);
    else if (key == "--roots")
    {
      const auto v = numbers(value(), key);
      if (v.empty() || v.size() > 3)
        throw std::invalid_argument("--roots N or NX,NY[,NZ]");
      for (double n : v)
        if (n != std::floor(n) || n < 1 || n > 65536)
          throw std::invalid_argument("--roots: each count must be an integer in 1..65536");
      if (v.size() == 1)
        o.roots = {{static_cast<int>(v[0]), static_cast<int>(v[0]), static_cast<int>(v[0])}};
      else
        o.roots = {{static_cast<int>(v[0]), static_cast<int>(v[1]),
                    static_cast<int>(v.size() == 3 ? v[2] : 1)}};
    }
    else if (key == "--live")
      o.live = value();
    else if (key == "--steps")
    {
      o.steps = integer(value(), key);
      stepsGiven = true;
    }
    else if (key == "--end-time")
    {
      o.endTime = single(value(), key);
      if (!(o.endTime > 0))
        throw std::invalid_argument("--end-time must be > 0");
    }
    else if (key == "--velocity")
    {
      o.velocity = value();
      velocityGiven = true;
      if (o.velocity.rfind("uniform:", 0) == 0)
      {
        const auto v = numbers(o.velocity.substr(8), key);
        for (std::size_t a = 0; a < 3; ++a)
          o.uniformVelocity[a] = a < v.size() ? v[a] : 0.0;
        o.velocity = "uniform";
      }
      else if (o.velocity != "swirl")
        throw std::invalid_argument("--velocity swirl or uniform:vx,vy[,vz]");
    }
    else if (key == "--exact-solution")
    {
      o.exactSolution = value();
      if (o.exactSolution != "gaussian")
        throw std::invalid_argument("--exact-solution: '" + o.exactSolution + "' is not gaussian");
    }
    else if (key == "--object")
      objectTexts.push_back(value());
    else if (key == "--pipeline")
    {
      o.pipelines.push_back(value());
      o.pipelineArguments.emplace_back();
    }
    else if (key == "--pipeline-arg")
    {
      if (o.pipelines.empty())
        throw std::invalid_argument("--pipeline-arg before any --pipeline");
      o.pipelineArguments.back().push_back(value());
    }
    else if (key == "--query")
      o.queries.push_back(value());
    else if (key == "--extract-trigger")
      o.extractTrigger = value();
    else if (key == "--extract-trigger-mode")
      o.extractTriggerMode = value();
    else if (key == "--no-insitu")
      o.noInSitu = true;
    else if (key == "--output")
      o.output = value();
    else if (key == "--quiet")
      o.quiet = true;
    else if (key == "--verify-untouched")
      o.verifyUntouched = true;
    else if (key == "--dump")
      o.dump = value();
    else if (key == "--resource-log")
      o.resourceLog = value();
    else if (key == "--plant-leak")
      o.plantLeak = std::stoll(value());
    else
      throw std::invalid_argument("unknown option '" + key + "'");
  }
  if (o.blocks > 0 && (!o.queries.empty() || !o.extractTrigger.empty()))
    throw std::invalid_argument("--query and --extract-trigger need --blocks 0 (queries do not "
                                "read block forests yet)");
  if (o.dimension != 2 && o.dimension != 3)
    throw std::invalid_argument("--dimension must be 2 or 3");
  if (o.branchFactor != 2 && o.branchFactor != 3)
    throw std::invalid_argument("--branch-factor must be 2 or 3");
  for (int a = 0; a < o.dimension; ++a)
    if (o.roots[a] < 1)
      throw std::invalid_argument("--roots must be at least 1 per axis");
  if (!(o.repartitionImbalance >= 1))
    throw std::invalid_argument("--repartition-imbalance must be >= 1");
  if (o.maxLevel < 0 || o.steps < 0 || o.regridEvery < 1 || o.imageEvery < 1 ||
      o.selectionEvery < 1 || o.extractEvery < 1)
    throw std::invalid_argument("--max-level/--steps must be >= 0, the *-every options >= 1");
  // Every rank holds the whole forest's topology, about 1 KiB per root cell once
  // the grid is built (measured: 512 x 512 roots, 1 GB): refuse a root grid that
  // cannot fit in this machine's memory before allocating anything.
  double rootCells = 1;
  for (int a = 0; a < o.dimension; ++a)
    rootCells *= o.roots[a];
  const double memory =
      static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
  constexpr double bytesPerRoot = 1024;
  if (rootCells * bytesPerRoot > memory)
  {
    std::ostringstream why;
    why << "--roots: " << static_cast<long long>(rootCells) << " root cells need about "
        << rootCells * bytesPerRoot / 1073741824.0 << " GiB on every rank (each holds the whole "
        << "forest, about 1 KiB per root cell), more than this machine's " << memory / 1073741824.0
        << " GiB";
    throw std::invalid_argument(why.str());
  }
  if (o.blocks != 0)
  {
    // A block's cells become uniform levels of the grid below its leaf: one cell
    // splits into branchFactor per axis at each, so n must be a power of it.
    int n = 1;
    while (n < o.blocks && n <= 1024)
      n *= o.branchFactor;
    if (o.blocks < 0 || n != o.blocks || o.blocks == 1 || o.blocks > 64)
      throw std::invalid_argument("--blocks: 0 (off) or a power of the branch factor " +
                                  std::to_string(o.branchFactor) + " from " +
                                  std::to_string(o.branchFactor) + " to 64 (" +
                                  (o.branchFactor == 2 ? "2, 4, 8, 16, 32, 64" : "3, 9, 27") +
                                  "), not " + std::to_string(o.blocks));
  }
  // Every rank holds the whole forest's topology: keep the finest level's cells
  // per axis at most 2^20 (a fully refined forest would not fit anyway); blocks
  // divide the finest leaves further.
  double finest = std::max(1, o.blocks);
  for (int l = 0; l < o.maxLevel && finest <= 1e12; ++l)
    finest *= o.branchFactor;
  for (int a = 0; a < o.dimension; ++a)
    if (finest * o.roots[a] > 1048576.0)
      throw std::invalid_argument("--max-level: at most 2^20 finest cells per axis "
                                  "(roots x branch factor^max level, x --blocks)");
  if (!(o.cfl > 0 && o.cfl <= 1))
    throw std::invalid_argument("--cfl must be in (0, 1]");
  if (!(o.diffusion >= 0))
    throw std::invalid_argument("--diffusion must be >= 0");
  if (stepsGiven && o.endTime > 0)
    throw std::invalid_argument("--steps or --end-time, not both");
  if (!o.exactSolution.empty())
  {
    // The exact solution is a pure translation on a fixed mesh: anything that
    // would change the equation or the mesh is a contradiction, not a default.
    if (!objectTexts.empty())
      throw std::invalid_argument("--exact-solution runs on a fixed mesh: no --object");
    if (o.diffusion != 0)
      throw std::invalid_argument("--exact-solution translates without diffusion: no --diffusion");
    if (velocityGiven && o.velocity != "uniform")
      throw std::invalid_argument("--exact-solution needs --velocity uniform:vx,vy[,vz]");
    if (!velocityGiven)
      o.uniformVelocity = {{1.0, 1.0, 1.0}}; // the diagonal
    o.velocity = "uniform";
  }
  for (const auto& text : objectTexts)
    o.objects.push_back(parseObject(text, o.dimension));
  if (objectTexts.empty() && o.exactSolution.empty())
  {
    // miniAMR's default spirit: two objects crossing the domain.
    MovingObject a;
    a.center = {{0.25, 0.3, 0.5}};
    a.radius = 0.12;
    a.velocity = {{0.6, 0.35, 0.2}};
    MovingObject b;
    b.kind = MovingObject::Kind::Plane;
    b.normal = {{1.0, 0.0, 0.0}};
    b.offset = 0.8;
    b.speed = -0.4;
    o.objects = {a, b};
  }
  if (o.pipelines.size() == 1 && o.pipelines[0] == "none")
  {
    o.pipelines.clear();
    o.pipelineArguments.clear();
    o.noInSitu = true;
  }
  return o;
}

std::string usage()
{
  return R"(canopy_miniamr: an AMR mini-app (miniAMR-style) running Canopy in situ.

Mesh:     --dimension 2|3 (2)  --branch-factor 2|3 (2)  --roots N|NX,NY[,NZ] (16)
          --max-level L (6)    --regrid-every K (1)
          --refine-gradient G (0.05)  --coarsen-gradient G (0.01)
          --blocks N (0): show every leaf to Canopy as a block of N^d cells (a block
          forest; N a power of the branch factor, e.g. 8): the leaf's fields at the
          cells' centres (scalar: with limited slopes); 0: one cell per leaf
Objects:  --object sphere:cx,cy[,cz],r,vx,vy[,vz]   --object plane:nx,ny[,nz],offset,speed
          (repeatable; default: a sphere and a plane crossing the domain; velocities
          in domain lengths per 100 steps; spheres bounce off the walls)
Physics:  --steps S (40)  --end-time T (instead of --steps; dt shortened to land on T)
          --cfl C (0.5)  --velocity swirl|uniform:vx,vy[,vz] (swirl)  --diffusion D (0)
Accuracy: --exact-solution gaussian: a Gaussian (sigma 0.15) translated by a uniform
          velocity (default the diagonal, 1,1[,1]) on the periodic domain, on a fixed
          uniform mesh at --max-level (no objects, no adaptation); prints at the end
          "exact: gaussian level L leaves N h H time T L1 E1 max EMAX" (cell averages
          against the exact ones, L1 volume-weighted over all ranks)
MPI:      --repartition-imbalance R (1.1): repartition when max/mean leaves per rank > R
In situ:  --output DIR (canopy-output)  --no-insitu
          --pipeline SCRIPT [--pipeline-arg ARG]...   (replaces the default pipelines)
          --image-every N (5)  --selection-every N (10)  --extract-every N (20)
          --query EXPR: print EXPR's value every step, e.g. 'max(scalar)' or
          'volume(scalar, 0.5, 2)'; repeatable (docs/queries.md); the values also go
          to OUTPUT/canopy_queries.csv
          --extract-trigger EXPR: the data extracts also need EXPR to hold, e.g.
          'max(scalar) < 0.9'; --extract-trigger-mode while|rising|every:N (while)
          --live HOST:PORT: offer every pipeline's sources to a Catalyst Live viewer
          listening there (ParaView: Catalyst > Connect; docs/insitu.md)
          --live-pause-limit S (300): a viewer's pause holds the run at most S seconds
          --live-stall-limit S (20): a viewer silent that long is disconnected
Output:   --quiet  --verify-untouched  --dump FILE
          --resource-log PREFIX: each rank writes PREFIX.<rank>.csv, a line per step:
          step, the rank's leaves, resident KiB, heap KiB in use, open file
          descriptors (soak tests)
          --plant-leak BYTES: allocate BYTES per step and never free them (to check
          that a soak test sees a leak)
)";
}

} // namespace miniamr
