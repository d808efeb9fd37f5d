// The image step, broken down and compared with ParaView's own route (issue 14).
//
// Runs the mini-app's image pipeline (pipelines/surface_image.py through
// canopy::InSitu: the adaptive surface colored by a field, edges on, 3-pixel
// threshold, 1024x1024, as canopy_miniamr runs it) and, in the same run on the
// same grids, ParaView's own routes (tests/bench/paraview_image.py: the grid
// shown directly with ParaView 5.11's hypertree-grid representation, the same
// camera, edges, image size and PNG extractor). Steps alternate between the
// routes (each script's trigger: frequency = number of routes, its own start).
//
// Each step's wall time (willExecute + execute, rank 0) is split into parts by
// ParaView's own scoped timings: vtkLogger scopes of the categories PIPELINE,
// EXECUTION, RENDERING and APPLICATION (PARAVIEW_LOG_<CATEGORY>_VERBOSITY=INFO),
// written to one log file per rank and parsed after each step; IceT's
// compositing time comes from the ICET_COMPOSITE_TIME line ParaView logs. The
// grid build is not in ParaView's log: the driver reports it (StepReport::
// buildSeconds; its GridBuilder keeps the trees of the unchanged forest the
// steps of one forest share), and a full build of the same description with the
// same field (what a step whose forest changed everywhere pays) is timed directly
// in the same run. What no scope
// covers is the Python/ParaView rest. The first step (script imports) is split
// further by tests/bench/image_step_probe.py (timing wrappers, installed after
// open).
//
// Usage: mpirun -np N canopy_bench_image_step [--output DIR] [--repetitions R]
//          [--image-size WxH] [--forests LIST] [--miniapp DIM,ROOTS,MAX_LEVEL,STEPS|none]...
//          [--routes LIST]
//        canopy_bench_image_step --first-step [--output DIR]
//   LIST of forests: synthetic-2d-1e5, synthetic-2d-1e6, synthetic-3d-1e6 (default: all
//   three, plus the mini-app's 2D forest 2,32,9,20); routes: canopy, paraview,
//   paraview-adaptive (default: all; the adaptive one is skipped on 3D forests,
//   which ParaView's adaptive representation does not handle).
//   CANOPY_PIPELINES_DIR=DIR runs the pipelines (scripts and helper modules) in DIR.
//   --first-step: the mini-app's own first step (its default forest at step 0
//   and its three default pipelines), broken down.
#include "ForestFingerprint.h"
#include "ForestSlice.h"
#include "MiniAppForest.h"
#include "SyntheticForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/InSitu.h>

#include <mpi.h>
#include <vtkHyperTreeGrid.h>
#include <vtkLogger.h>
#include <vtkPythonInterpreter.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace
{

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

double secondsSince(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> values)
{
  if (values.empty())
    return 0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

/// One step's time split by ParaView's log scopes (seconds, this rank).
struct Parts
{
  double surface = 0;  ///< Canopy's filters' executions (surface, slices, selections)
  double geometry = 0; ///< the representation's vtkPVGeometryFilter (HTG: vtkHyperTreeGridGeometry)
  double dataInfo = 0; ///< gathering data information (bounds, ranges) of grid and surface
  double render = 0;   ///< still renders, compositing excluded
  double composite = 0; ///< IceT's ICET_COMPOSITE_TIME
  /// CaptureWindow outside its update/render/gather scopes: reading the pixels
  /// back, which waits for Mesa llvmpipe to finish rasterizing (its threads work
  /// after Render() returned), so it is counted as rendering.
  double capture = 0;
  double png = 0;         ///< writing the PNG (vtkPNGWriter through ParaView's writer helper)
  double writers = 0;     ///< other extract writers (data extracts)
  double otherScopes = 0; ///< own time of other scopes (pipeline and view updates, delivery)
  double scoped() const
  {
    return surface + geometry + dataInfo + render + composite + capture + png + writers +
           otherScopes;
  }
};

/// Reads what ParaView logged since the last call and sorts scope times into Parts.
class LogReader
{
public:
  explicit LogReader(std::string path) : Path(std::move(path)) {}

  Parts read()
  {
    Parts parts;
    std::ifstream in(Path);
    if (!in)
      return parts;
    in.seekg(Offset);
    std::string line;
    std::vector<Frame> stack;
    while (std::getline(in, line))
    {
      if (in.eof())
        break; // a line still being written: read it next time
      Offset = in.tellg();
      const auto bar = line.find("INFO| ");
      if (bar == std::string::npos)
        continue;
      std::string message = line.substr(bar + 6);
      // Nested scopes are indented by ".   " per level.
      std::size_t start = 0;
      while (start < message.size() && (message[start] == '.' || message[start] == ' '))
        ++start;
      message = message.substr(start);
      double value = 0;
      if (message.rfind("{ ", 0) == 0)
      {
        Frame frame;
        frame.name = message.substr(2);
        frame.category = classify(frame.name);
        frame.inside = !stack.empty() && (stack.back().inside || stack.back().category >= Claimed);
        stack.push_back(frame);
      }
      else if (message.rfind("} ", 0) == 0 && std::sscanf(message.c_str(), "} %lf s:", &value) == 1)
      {
        const auto colon = message.find(" s: ");
        const std::string name = colon == std::string::npos ? "" : message.substr(colon + 4);
        // Close the matching scope (and any left open inside it).
        while (!stack.empty() && stack.back().name != name)
          stack.pop_back();
        if (stack.empty())
          continue;
        const Frame frame = stack.back();
        stack.pop_back();
        if (!stack.empty())
          stack.back().children += value;
        if (!frame.inside)
          add(parts, frame, value);
      }
      else if (std::sscanf(message.c_str(), "ICET_COMPOSITE_TIME: %lf", &value) == 1)
      {
        parts.composite += value;
        parts.render -= value; // it happened inside a still render
      }
    }
    return parts;
  }

private:
  enum Category
  {
    None,
    CaptureSelf, ///< only its own time (outside child scopes) counts
    Claimed,     ///< from here on: the whole scope counts, nested scopes do not
    Surface,
    Geometry,
    DataInfo,
    Render,
    Png,
    Writer
  };
  struct Frame
  {
    std::string name;
    Category category = None;
    bool inside = false; ///< inside a claimed scope
    double children = 0;
  };

  static bool contains(const std::string& text, const char* part)
  {
    return text.find(part) != std::string::npos;
  }

  static Category classify(const std::string& name)
  {
    const bool execute = name.size() > 9 && name.compare(name.size() - 9, 9, ": execute") == 0;
    if ((contains(name, "CanopyAdaptiveSurface") || contains(name, "CanopyAdaptiveSlice") ||
         contains(name, "CanopyExtractSelection")) &&
        execute && !contains(name, "("))
      return Surface; // Canopy's filters

    if (contains(name, "/SurfaceRepresentation: execute"))
      return Geometry;
    if (contains(name, "gather information vtkPVDataInformation"))
      return DataInfo;
    if (name.rfind("Render(", 0) == 0)
      return Render;
    if (name.rfind("Save captured image", 0) == 0)
      return Png;
    if (contains(name, "Writer") && execute)
      return Writer;
    if (name == "CaptureWindow")
      return CaptureSelf;
    return None;
  }

  static void add(Parts& parts, const Frame& frame, double seconds)
  {
    switch (frame.category)
    {
    case Surface:
      parts.surface += seconds;
      break;
    case Geometry:
      parts.geometry += seconds;
      break;
    case DataInfo:
      parts.dataInfo += seconds;
      break;
    case Render:
      parts.render += seconds;
      break;
    case Png:
      parts.png += seconds;
      break;
    case Writer:
      parts.writers += seconds;
      break;
    case CaptureSelf:
      parts.capture += seconds - frame.children;
      break;
    case None:
    case Claimed:
      // Unclassified scopes: their own time only (the scopes inside them were
      // counted when they closed), so that every scoped second counts once.
      parts.otherScopes += seconds - frame.children;
      break;
    }
  }

  std::string Path;
  std::streamoff Offset = 0;
};

struct Route
{
  std::string name;  ///< canopy, canopy-slices, paraview, paraview-adaptive
  std::string label; ///< for tables
  bool twoDOnly = false;
  bool threeDOnly = false;
};

struct BenchForest
{
  std::string name;
  std::string label;
  int dimension = 2;
  std::int64_t leaves = 0; ///< global
  std::unique_ptr<canopy::tools::SyntheticForest> synthetic;
  std::unique_ptr<canopy::tools::MiniAppForest> miniApp;
  canopy::ForestDescription local; ///< this rank's part, field "scalar" shown
};

/// The three synthetic forests of the issue: 2D near 1e5 and 1e6 leaves, 3D near
/// 1e6 (with the cut-away mask, so that the image shows the refined interior).
std::unique_ptr<BenchForest> syntheticForest(const std::string& name, int rank, int ranks)
{
  canopy::tools::SyntheticForestOptions o;
  o.depthFirstStorage = false; // breadth-first: the layout simulations are advised to use
  o.cutaway = false;
  if (name == "synthetic-2d-1e5")
  {
    o.dimension = 2;
    o.rootsPerAxis = 16;
    o.maxLevels = 7;
  }
  else if (name == "synthetic-2d-1e6")
  {
    o.dimension = 2;
    o.rootsPerAxis = 13;
    o.maxLevels = 9;
  }
  else if (name == "synthetic-3d-1e6")
  {
    o.dimension = 3;
    o.rootsPerAxis = 7;
    o.maxLevels = 6;
    o.cutaway = true;
  }
  else
  {
    throw std::invalid_argument("unknown forest '" + name + "'");
  }
  auto f = std::make_unique<BenchForest>();
  f->name = name;
  f->dimension = o.dimension;
  f->synthetic = std::make_unique<canopy::tools::SyntheticForest>(o);
  f->leaves = static_cast<std::int64_t>(f->synthetic->numberOfLeaves());
  f->label = "synthetic " + std::to_string(o.dimension) + "D, " + std::to_string(o.rootsPerAxis) +
             "^" + std::to_string(o.dimension) + " roots, " + std::to_string(o.maxLevels) +
             " levels" + (o.cutaway ? ", cut-away mask" : "");
  f->local = canopy::tools::rankSlice(f->synthetic->description(), rank, ranks);
  // Every forest shows a leaves-only field named "scalar" (the mini-app's name),
  // so that one set of script arguments serves all of them.
  for (auto& field : f->local.fields)
    if (field.name == "pressure")
      field.name = "scalar";
  if (rank == 0)
    std::cout << canopy::tools::describeInput(f->label + ", the whole forest",
                                              f->synthetic->description())
              << std::endl;
  return f;
}

std::unique_ptr<BenchForest> miniAppForest(const std::string& spec)
{
  auto f = std::make_unique<BenchForest>();
  const auto options = canopy::tools::parseMiniAppForest(spec);
  f->miniApp = std::make_unique<canopy::tools::MiniAppForest>(options);
  f->name = "miniapp-" + spec;
  f->label = f->miniApp->label();
  f->dimension = options.dimension;
  f->leaves = f->miniApp->globalLeaves();
  f->local = f->miniApp->description();
  f->local.missingTreesAreElsewhere = true;
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0)
    std::cout << canopy::tools::describeInput(f->label + ", rank 0's part", f->local) << std::endl;
  return f;
}

std::vector<std::string> split(const std::string& text)
{
  std::vector<std::string> items;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty())
      items.push_back(item);
  return items;
}

/// Median over repetitions of buildHyperTreeGrid on this rank's part.
double buildSeconds(const canopy::ForestDescription& forest, const canopy::FieldRequest& request,
                    int repetitions)
{
  std::vector<double> times;
  for (int r = 0; r < repetitions; ++r)
  {
    const auto start = Clock::now();
    auto grid = canopy::buildHyperTreeGrid(forest, request);
    times.push_back(secondsSince(start));
  }
  return median(times);
}

/// Probe records of rank 0: "<what>\t<seconds>" lines.
std::vector<std::pair<std::string, double>> readProbe(const fs::path& path)
{
  std::vector<std::pair<std::string, double>> records;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
  {
    const auto tab = line.find('\t');
    if (tab != std::string::npos)
      records.emplace_back(line.substr(0, tab), std::atof(line.c_str() + tab + 1));
  }
  return records;
}

struct StepRecord
{
  std::size_t forest = 0;
  std::size_t route = 0;
  int repetition = 0;
  double total = 0;
  Parts parts;
  double build = 0; ///< the step's own grid build (StepReport::buildSeconds, rank 0)
  std::size_t treesRebuilt = 0;
  std::size_t treesKept = 0;
};

std::string fixed(double value, int digits = 3)
{
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

/// The first step's breakdown (rank 0), printed as a table.
void printFirstStep(double pythonStart, double open, const StepRecord& step,
                    const std::vector<std::pair<std::string, double>>& probe,
                    const std::vector<std::string>& scriptModules, int ranks)
{
  double scriptImports = 0, simpleImport = 0, plugin = 0, views = 0, show = 0, extractors = 0;
  int plugins = 0, viewCount = 0;
  std::ostringstream perScript;
  for (const auto& [what, seconds] : probe)
  {
    for (const auto& module : scriptModules)
      if (what == "import module " + module)
      {
        scriptImports += seconds;
        perScript << (perScript.tellp() > 0 ? ", " : "") << module << " " << fixed(seconds, 2);
      }
    if (what == "import paraview.simple")
      simpleImport += seconds;
    else if (what == "plugin load")
      plugin += seconds, ++plugins;
    else if (what == "view creation")
      views += seconds, ++viewCount;
    else if (what == "show")
      show += seconds;
    else if (what == "extractor creation")
      extractors += seconds;
  }
  const double otherImport = scriptImports - simpleImport - plugin - views - show - extractors;
  const Parts& p = step.parts;
  const double rest = step.total - step.build - scriptImports - p.scoped();
  auto row = [](const std::string& part, double seconds, const std::string& how)
  { std::cout << "| " << part << " | " << fixed(seconds) << " | " << how << " |\n"; };
  std::cout << "\n## First step (" << ranks << " rank" << (ranks > 1 ? "s" : "")
            << "), rank 0\n\n| part | s | measured by |\n|---|---:|---|\n";
  row("Python start (vtkPythonInterpreter::Initialize)", pythonStart,
      "timed directly, before open");
  row("rest of canopy::InSitu open (Catalyst and ParaView start, helper modules)", open,
      "timed directly");
  row("**step 0 (willExecute + execute)**", step.total, "timed directly");
  row("- grid build (every field: the scripts' requests are not known before their import; " +
          std::to_string(step.treesRebuilt) + " trees)",
      step.build, "StepReport::buildSeconds");
  row("- script imports (" + perScript.str() + ")", scriptImports,
      "probe: importlib.import_module");
  row("  - import paraview.simple", simpleImport, "probe");
  row("  - plugin load (LoadPlugin x" + std::to_string(plugins) + ")", plugin, "probe");
  row("  - views (CreateView x" + std::to_string(viewCount) + ")", views, "probe");
  row("  - Show and extractor creation", show + extractors, "probe");
  row("  - other module-level code (proxies, settings)", otherImport, "imports minus the above");
  row("- Canopy's filters (surface, slices, selections)", p.surface, "ParaView log scope");
  row("- ParaView geometry filter (vtkPVGeometryFilter)", p.geometry, "ParaView log scope");
  row("- data information (bounds, ranges)", p.dataInfo, "ParaView log scopes");
  row("- first render (incl. read-back; compositing excluded)", p.render + p.capture,
      "ParaView log scopes");
  row("- compositing (IceT)", p.composite, "ICET_COMPOSITE_TIME");
  row("- PNG writing", p.png, "ParaView log scope");
  row("- data extract writers", p.writers, "ParaView log scopes");
  row("- other ParaView scopes (pipeline updates)", p.otherScopes, "ParaView log scopes");
  row("- Python/ParaView rest", rest, "step minus all of the above");
}

} // namespace

int main(int argc, char** argv)
{
  // Before anything asks ParaView's logger for its categories' verbosity.
  for (const char* category : {"PIPELINE", "EXECUTION", "RENDERING", "APPLICATION"})
    setenv(("PARAVIEW_LOG_" + std::string(category) + "_VERBOSITY").c_str(), "INFO", 1);
  MPI_Init(&argc, &argv);
  int rank = 0;
  int ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  int status = 0;
  try
  {
    fs::path output = "canopy-bench-image-step";
    int repetitions = 3;
    std::string imageSize = "1024x1024";
    std::vector<std::string> forestNames{"synthetic-2d-1e5", "synthetic-2d-1e6",
                                         "synthetic-3d-1e6"};
    std::vector<std::string> miniAppSpecs;
    std::vector<std::string> routeNames{"canopy", "canopy-slices", "canopy-slices-contour",
                                        "paraview", "paraview-adaptive"};
    bool firstStep = false;
    for (int i = 1; i < argc; ++i)
    {
      const std::string arg = argv[i];
      const bool value = i + 1 < argc;
      if (arg == "--output" && value)
        output = argv[++i];
      else if (arg == "--repetitions" && value)
        repetitions = std::max(1, std::atoi(argv[++i]));
      else if (arg == "--image-size" && value)
        imageSize = argv[++i];
      else if (arg == "--forests" && value)
        forestNames = split(argv[++i]);
      else if (arg == "--miniapp" && value)
        miniAppSpecs.push_back(argv[++i]);
      else if (arg == "--routes" && value)
        routeNames = split(argv[++i]);
      else if (arg == "--first-step")
        firstStep = true;
      else
        throw std::invalid_argument("unknown argument '" + arg + "'");
    }
    if (!firstStep && miniAppSpecs.empty())
      miniAppSpecs.push_back("2,32,9,20");
    miniAppSpecs.erase(std::remove(miniAppSpecs.begin(), miniAppSpecs.end(), "none"),
                       miniAppSpecs.end());
    if (firstStep)
    {
      // The mini-app's own first step: its default forest at step 0.
      forestNames.clear();
      miniAppSpecs = {"2,16,6,0"};
      routeNames = {"canopy"};
      repetitions = 1;
    }
    fs::create_directories(output / "logs");
    vtkLogger::LogToFile((output / "logs" / ("rank" + std::to_string(rank) + ".log")).c_str(),
                         vtkLogger::TRUNCATE, vtkLogger::VERBOSITY_INFO);
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_WARNING);
    LogReader log((output / "logs" / ("rank" + std::to_string(rank) + ".log")).string());

    std::vector<std::unique_ptr<BenchForest>> forests;
    for (const auto& name : forestNames)
      forests.push_back(syntheticForest(name, rank, ranks));
    for (const auto& spec : miniAppSpecs)
      forests.push_back(miniAppForest(spec));
    if (forests.empty())
      throw std::invalid_argument("no forest to run");

    std::vector<Route> routes;
    for (const auto& name : routeNames)
    {
      if (name == "canopy")
        routes.push_back({name, "Canopy (surface_image.py)", false});
      else if (name == "canopy-slices")
        routes.push_back(
            {name, "Canopy (slice_image.py: 3 slices + cut-away region)", false, true});
      else if (name == "canopy-slices-contour")
        routes.push_back({name, "Canopy (slice_image.py: 3 slices + cut-away region + isosurface)",
                          false, true});
      else if (name == "paraview")
        routes.push_back({name, "ParaView 'Surface' (vtkHyperTreeGridGeometry)", false});
      else if (name == "paraview-adaptive")
        routes.push_back({name, "ParaView 'HTG Surface' (adaptive decimation)", true});
      else
        throw std::invalid_argument("unknown route '" + name + "'");
    }

    // InSitu loads a script once: the two slices routes both run slice_image.py.
    if (std::count_if(routes.begin(), routes.end(),
                      [](const Route& r) { return r.name.rfind("canopy-slices", 0) == 0; }) > 1)
      throw std::invalid_argument(
          "canopy-slices and canopy-slices-contour both run slice_image.py: one per run");

    // A full build with the shown field (median; the slowest rank's, as a step waits
    // for it): what a step pays when every tree changed. The driver's GridBuilder keeps
    // the trees of an unchanged forest, so the steps below (the same forest each
    // time) pay only its check (StepReport::buildSeconds, in the tables).
    const auto shown = canopy::FieldRequest::only({"scalar"});
    std::vector<double> builds;
    for (const auto& forest : forests)
    {
      double local = buildSeconds(forest->local, shown, repetitions + 2);
      double slowest = 0;
      MPI_Allreduce(&local, &slowest, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
      builds.push_back(slowest);
    }

    // Scripts: the mini-app's image pipeline; ParaView's routes start one and two
    // steps later, every routes.size() steps.
    const std::string bench = CANOPY_BENCH_DIR;
    // CANOPY_PIPELINES_DIR (which the driver also reads for its helper modules)
    // runs another copy of the pipelines, e.g. an older one to compare with.
    const char* pipelinesDir = std::getenv("CANOPY_PIPELINES_DIR");
    const std::string pipelines = pipelinesDir ? pipelinesDir : CANOPY_PIPELINES_SOURCE_DIR;
    const std::string every = "--frequency=" + std::to_string(routes.size());
    canopy::InSituOptions options;
    options.outputDirectory = (output / "images").string();
    options.verbosity = vtkLogger::VERBOSITY_WARNING;
    std::vector<std::string> modules;
    if (firstStep)
    {
      // canopy_miniamr's default pipelines and arguments (miniapp/main.cxx).
      options.scripts = {{pipelines + "/surface_image.py",
                          {"--frequency=5", "--color-by=scalar", "--fields=scalar",
                           "--image-size=1024x1024", "--show-edges=1", "--pixel-threshold=3"}},
                         {pipelines + "/selection_extract.py",
                          {"--frequency=10", "--selection=range", "--value-field=scalar",
                           "--value-range=0.5,1e30"}},
                         {pipelines + "/data_extracts.py", {"--frequency=20"}}};
      modules = {"surface_image", "selection_extract", "data_extracts"};
    }
    else
    {
      for (std::size_t k = 0; k < routes.size(); ++k)
      {
        const std::vector<std::string> common{every, "--color-by=scalar", "--fields=scalar",
                                              "--image-size=" + imageSize, "--show-edges=1"};
        if (routes[k].name == "canopy")
        {
          auto arguments = common;
          arguments.push_back("--pixel-threshold=3");
          options.scripts.push_back({pipelines + "/surface_image.py", arguments});
          modules.push_back("surface_image");
          continue;
        }
        if (routes[k].name == "canopy-slices" || routes[k].name == "canopy-slices-contour")
        {
          // The 3D default of the mini-app's slices, with the region drawn in the
          // same image: scalar >= 3 (the front's shell) with an octant cut away;
          // and the same with the front's isosurface at scalar = 3 (following the
          // view, as the scripts' default).
          auto arguments = common;
          arguments.insert(arguments.end(),
                           {"--start=" + std::to_string(k), "--pixel-threshold=3",
                            "--select-field=scalar", "--select-range=3,1e30", "--cut-away=octant"});
          if (routes[k].name == "canopy-slices-contour")
          {
            arguments.insert(arguments.end(), {"--contour-field=scalar", "--contour-values=3",
                                               "--file-prefix=slices_contour"});
          }
          options.scripts.push_back({pipelines + "/slice_image.py", arguments});
          modules.push_back("slice_image");
          continue;
        }
        // InSitu runs a script once: the adaptive route is a copy under another name.
        const bool adaptive = routes[k].name == "paraview-adaptive";
        fs::path script = bench + "/paraview_image.py";
        if (adaptive)
        {
          fs::create_directories(output / "scripts");
          const fs::path copy = output / "scripts" / "paraview_adaptive_image.py";
          if (rank == 0)
            fs::copy_file(script, copy, fs::copy_options::overwrite_existing);
          MPI_Barrier(MPI_COMM_WORLD);
          script = fs::absolute(copy);
        }
        auto arguments = common;
        arguments.push_back("--start=" + std::to_string(k));
        arguments.push_back(adaptive ? "--representation=HTG Surface" : "--representation=Surface");
        arguments.push_back(adaptive ? "--file-prefix=paraview_adaptive"
                                     : "--file-prefix=paraview");
        options.scripts.push_back({script.string(), arguments});
        modules.push_back(script.stem().string());
      }
    }

    // Python first, timed alone (canopy::InSitu's own call is then a no-op; the
    // driver gives the scripts its settings through its Python module _canopy,
    // whenever Python started).
    auto start = Clock::now();
    vtkPythonInterpreter::Initialize();
    const double pythonStart = secondsSince(start);
    start = Clock::now();
    canopy::InSitu insitu(MPI_COMM_WORLD, options);
    const double open = secondsSince(start);
    if (!insitu.canRender())
      throw std::runtime_error("no X display: run under xvfb-run");
    const std::string probePath =
        (output / "logs" / ("probe" + std::to_string(rank) + ".txt")).string();
    vtkPythonInterpreter::RunSimpleString(
        ("import sys\nsys.path.insert(0, r'''" + bench +
         "''')\nimport image_step_probe\nimage_step_probe.install()\n")
            .c_str());
    log.read(); // what open logged

    // Schedule: per forest, a warm-up round then `repetitions` rounds of every route.
    std::vector<StepRecord> records;
    std::int64_t step = 0;
    bool first = true;
    StepRecord firstRecord;
    for (std::size_t f = 0; f < forests.size(); ++f)
    {
      for (int r = 0; r <= (firstStep ? 0 : repetitions); ++r)
      {
        for (std::size_t k = 0; k < routes.size(); ++k, ++step)
        {
          if (routes[k].twoDOnly && forests[f]->dimension == 3)
            continue; // ParaView's adaptive representation is for 2D grids only
          if (routes[k].threeDOnly && forests[f]->dimension != 3)
            continue; // slices are of 3D grids
          MPI_Barrier(MPI_COMM_WORLD);
          const auto t0 = Clock::now();
          canopy::StepReport report;
          if (insitu.willExecute(step, static_cast<double>(step)))
          {
            report = insitu.execute(step, static_cast<double>(step), forests[f]->local);
            if (!report.failures.empty())
              throw std::runtime_error("step " + std::to_string(step) +
                                       " failed: " + report.failures.front());
          }
          StepRecord record{f,
                            k,
                            r,
                            secondsSince(t0),
                            log.read(),
                            report.buildSeconds,
                            report.treesRebuilt,
                            report.treesKept};
          if (first)
          {
            first = false;
            firstRecord = record;
            vtkPythonInterpreter::RunSimpleString(
                ("image_step_probe.dump(r'''" + probePath + "''')\n").c_str());
          }
          else if (r > 0)
          {
            records.push_back(record);
          }
          if (rank == 0)
            std::cerr << "bench: step " << step << " " << forests[f]->name << " " << routes[k].name
                      << (r == 0 ? " (warm-up)" : "") << ": " << fixed(record.total) << " s\n";
        }
      }
      if (firstStep)
      {
        // The next image step of the mini-app (steady state), to set the first against.
        step = 5;
        MPI_Barrier(MPI_COMM_WORLD);
        const auto t0 = Clock::now();
        if (insitu.willExecute(step, 0.0012))
          insitu.execute(step, 0.0012, forests[f]->local);
        StepRecord record{f, 0, 1, secondsSince(t0), log.read()};
        records.push_back(record);
      }
    }
    insitu.close();

    if (rank == 0)
    {
      std::cout << "# The image step, broken down (" << ranks << " rank" << (ranks > 1 ? "s" : "")
                << ", rank 0's times; " << imageSize << ")\n";
      printFirstStep(pythonStart, open, firstRecord, readProbe(probePath), modules, ranks);
      if (firstStep)
      {
        const Parts& p = records.back().parts;
        std::cout << "\nThe next image step (5) of the same run: " << fixed(records.back().total)
                  << " s (render " << fixed(p.render) << " s, PNG " << fixed(p.png) << " s)\n";
      }
      else
      {
        std::cout << "\n## Image step: median over " << repetitions
                  << " steps per forest and route (the step with the median total; parts in s)\n\n"
                  << "| forest | leaves | route | step s | build in step (trees rebuilt / kept) | "
                     "full build | surface filter | ParaView geometry filter | data information | "
                     "render | compositing | PNG | other ParaView scopes | Python/ParaView rest |\n"
                  << "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        std::map<std::pair<std::size_t, std::size_t>, StepRecord> medians;
        for (std::size_t f = 0; f < forests.size(); ++f)
          for (std::size_t k = 0; k < routes.size(); ++k)
          {
            std::vector<StepRecord> these;
            for (const auto& record : records)
              if (record.forest == f && record.route == k)
                these.push_back(record);
            if (these.empty())
              continue;
            std::sort(these.begin(), these.end(),
                      [](const StepRecord& a, const StepRecord& b) { return a.total < b.total; });
            const StepRecord& m = these[these.size() / 2];
            medians[{f, k}] = m;
            const Parts& p = m.parts;
            const double rest = m.total - m.build - p.scoped();
            std::cout << "| " << forests[f]->label << " | " << forests[f]->leaves << " | "
                      << routes[k].label << " | " << fixed(m.total) << " | " << fixed(m.build)
                      << " (" << m.treesRebuilt << " / " << m.treesKept << ") | "
                      << fixed(builds[f]) << " | " << fixed(p.surface) << " | " << fixed(p.geometry)
                      << " | " << fixed(p.dataInfo) << " | " << fixed(p.render + p.capture) << " | "
                      << fixed(p.composite) << " | " << fixed(p.png) << " | "
                      << fixed(p.otherScopes) << " | " << fixed(rest) << " |\n";
          }
        std::cout << "\n## Canopy against ParaView's routes\n\n"
                  << "| forest | leaves | Canopy step s | ParaView 'Surface' s | speedup | "
                     "ParaView 'HTG Surface' s | speedup | Canopy's own share (full build + "
                     "surface filter) of a step that rebuilds every tree |\n"
                     "|---|---:|---:|---:|---:|---:|---:|---:|\n";
        auto find = [&](std::size_t f, const std::string& name) -> const StepRecord*
        {
          for (std::size_t k = 0; k < routes.size(); ++k)
            if (routes[k].name == name && medians.count({f, k}))
              return &medians[{f, k}];
          return nullptr;
        };
        for (std::size_t f = 0; f < forests.size(); ++f)
        {
          const StepRecord* c = find(f, "canopy");
          const StepRecord* g = find(f, "paraview");
          const StepRecord* a = find(f, "paraview-adaptive");
          if (!c)
            continue;
          auto versus = [&](const StepRecord* other)
          {
            return other ? fixed(other->total) + " | " + fixed(other->total / c->total, 1) + "x"
                         : std::string("- | -");
          };
          // The share of a step whose forest changed everywhere: the full build in
          // place of the kept trees' check.
          const double own = builds[f] + c->parts.surface;
          const double rebuilding = c->total - c->build + builds[f];
          std::cout << "| " << forests[f]->label << " | " << forests[f]->leaves << " | "
                    << fixed(c->total) << " | " << versus(g) << " | " << versus(a) << " | "
                    << fixed(100 * own / rebuilding, 1) << "% (" << fixed(own) << " of "
                    << fixed(rebuilding) << " s) |\n";
        }
      }
      std::cout << std::flush;
    }
  }
  catch (const std::exception& error)
  {
    std::cerr << "canopy_bench_image_step (rank " << rank << "): " << error.what() << "\n";
    status = 1;
    if (ranks > 1)
      MPI_Abort(MPI_COMM_WORLD, 1);
  }
  MPI_Finalize();
  return status;
}
