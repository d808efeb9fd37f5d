// Canopy's in-situ driver: the calls a simulation makes to run ParaView
// Catalyst pipelines (Python scripts, ParaView 5.9+ format) on its forest.
//
//   canopy::InSitu insitu(MPI_COMM_WORLD, options);     // open
//   if (insitu.willExecute(step, time)) ...             // optional, cheap
//   insitu.execute(step, time, forest);                 // every step
//   insitu.close();                                     // or let it go out of scope
//
// Every call is collective over the communicator: all ranks make it, with the
// same step and time. A failing pipeline never throws out of execute() and never
// leaves a rank waiting for the others; see docs/insitu.md.
#pragma once

#include <canopy/ForestDescription.h>
#include <canopy/Queries.h>

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace canopy
{

/// A Catalyst pipeline script and the arguments it reads through
/// canopy_catalyst.settings() (e.g. "--frequency=5", "--fields=density").
/// Two arguments are also the driver's (docs/queries.md): "--trigger=<condition>"
/// (e.g. "--trigger=max(scalar) > 0.9": the script runs only at the steps its
/// frequency names where the condition's trigger fires) and
/// "--trigger-mode=while|rising|every:N" (default while).
struct PipelineScript
{
  std::string path;
  std::vector<std::string> arguments;
};

struct InSituOptions
{
  /// Catalyst scripts (ParaView 5.9+ format: a .py file, a directory or a .zip).
  std::vector<PipelineScript> scripts;
  /// Where pipelines write images and extracts; created if missing.
  std::string outputDirectory = "canopy-output";
  /// Name of the Catalyst channel: a script reads it as
  /// TrivialProducer(registrationName=<channel>).
  std::string channel = "grid";
  /// vtkLogger verbosity for stderr (process-wide), e.g. vtkLogger::VERBOSITY_INFO (0) or
  /// VERBOSITY_TRACE (9) for Canopy's per-step details; below -9 (default): leave it unchanged.
  int verbosity = -10;
  /// Log one line per executed step (rank 0): pipelines run, cells, times.
  bool stepSummary = false;
  /// Numbers computed at every step and reported (StepReport::expressions, the
  /// history file): expressions of the query language, e.g. "max(scalar)",
  /// "volume(scalar, 0.5, 1) - prev(volume(scalar, 0.5, 1))" (docs/queries.md).
  std::vector<std::string> queries;
  /// The fields the simulation describes, for checking triggers and queries at
  /// open (an unknown field is refused then); empty: checked when they first run.
  std::vector<std::string> fields;
  /// The history of queries (one row per evaluated step) in the output directory,
  /// written by rank 0 when there are triggers or queries; empty: none.
  std::string queryHistoryFile = "canopy_queries.csv";
  /// The longest any call into a script may take (its import, its
  /// RequestDataDescription, its catalyst_execute with its extracts, its
  /// catalyst_finalize), in seconds; 0: no limit. A script still running then is
  /// interrupted (a Python exception where it is), reported with rank, script
  /// and step, and the step skipped on every rank. A rank that cannot be
  /// interrupted (in C code, or waiting in an MPI collective inside ParaView)
  /// is named on stderr and the job is ended with MPI_Abort (exit code 124)
  /// rather than hanging. See docs/insitu.md.
  double stepTimeLimitSeconds = 0.0;
  /// Catalyst Live (docs/insitu.md): "host:port" where a viewer (ParaView's
  /// Catalyst > Connect, or pvpython's paraview.live) listens; every shipped
  /// script then offers its sources to it (its setting `live`). Empty: only scripts
  /// whose options enable Live (options.EnableCatalystLive) do.
  std::string liveUrl;
  /// The longest a viewer's pause holds the simulation, in seconds (<= 0: until
  /// it resumes); then the simulation goes on and ignores that pause.
  double livePauseLimitSeconds = 300.0;
  /// A viewer that does not answer for this long during an exchange is
  /// disconnected (it can connect again), in seconds.
  double liveStallSeconds = 20.0;
};

/// Thrown by the InSitu constructor when the options are unusable (no script,
/// unreadable script, Catalyst cannot start). Nothing is left running.
class InSituError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// What one execute() call did. Identical on every rank but for localCells and seconds.
struct StepReport
{
  bool executed = false;                 ///< some pipeline ran (successfully or not)
  std::vector<std::string> pipelinesRun; ///< scripts that completed this step
  std::vector<std::string> failures;     ///< "rank R, step S: message", every rank's
  std::int64_t localCells = 0;           ///< cells of this rank's grid (0 when not built)
  double seconds = 0.0;                  ///< wall time of the call on this rank
  double buildSeconds = 0.0;             ///< of which building the grid (this rank)
  /// This rank's trees built anew and kept from the previous executed step: the
  /// grid is rebuilt only where the forest's topology changed (canopy::GridBuilder).
  std::size_t treesRebuilt = 0;
  std::size_t treesKept = 0;
  /// What the scripts that ran measured this step (canopy_catalyst.report in a
  /// script), each summed over ranks, by name: e.g. surface_image.py's
  /// "surface quads", the quads its image drew. The same on every rank.
  std::map<std::string, double> measures;
  /// What went wrong with a Catalyst Live viewer this step, on this rank (also
  /// logged as warnings): a viewer never fails a step.
  std::vector<std::string> liveWarnings;
  /// Wall time of the step's Catalyst Live exchange on this rank (0 without Live).
  double liveSeconds = 0.0;
  /// Whether this step's queries ran (there are triggers or queries, and the step
  /// was evaluated by willExecute(step, time, forest) or execute()).
  bool queriesEvaluated = false;
  /// The step's queries (those of the triggers and of InSituOptions::queries), by
  /// their text (Query::text()), the same on every rank.
  std::map<std::string, QueryResult> queries;
  /// InSituOptions::queries' values, by the text given, the same on every rank.
  std::map<std::string, double> expressions;
  /// Scripts whose trigger fired at this step (whether their frequency made them due or not).
  std::vector<std::string> triggersFired;
  /// Wall time of the step's queries and triggers on this rank.
  double querySeconds = 0.0;
};

class InSitu
{
public:
  /// Open: starts Catalyst on `communicator` (duplicated; the caller keeps its own)
  /// and prepares every script (paths made absolute; a script may appear once).
  /// Collective. Once per process: ParaView 5.11's Catalyst cannot be restarted
  /// after close, so a second InSitu throws InSituError.
  InSitu(MPI_Comm communicator, InSituOptions options);
  /// Closes if still open.
  ~InSitu();
  InSitu(const InSitu&) = delete;
  InSitu& operator=(const InSitu&) = delete;

  /// Whether any pipeline runs at this step (or a script's RequestDataDescription
  /// failed, which execute() then reports); when false, execute() for the same
  /// step and time returns at once, and the simulation may skip preparing its
  /// forest. Collective, cheap (no grid is built).
  bool willExecute(std::int64_t step, double time);

  /// The same, with the step's forest: also runs the step's queries (one
  /// collective for all of them, no grid built) and evaluates the triggers, so
  /// the answer is exact for scripts with a trigger; execute() then reuses them.
  /// Without the forest, a script with a trigger counts as due whenever its
  /// frequency says so. `forest` is only read during the call.
  bool willExecute(std::int64_t step, double time, const ForestDescription& forest);

  /// Runs the pipelines due at this step on the rank's part of the forest
  /// (only its own trees). Builds the grid only when some pipeline runs, and wraps
  /// only the fields a pipeline asks for. Never throws for a pipeline or forest
  /// problem: it is reported (rank and step), the step skipped on all ranks.
  StepReport execute(std::int64_t step, double time, const ForestDescription& forest);

  /// Finalizes the pipelines and Catalyst. Collective. Also done by the destructor
  /// and, if the simulation forgets both, when MPI_Finalize is called.
  void close();

  bool isOpen() const;

  /// Whether rendering scripts can run (an X display was reachable on every rank at open).
  bool canRender() const;

private:
  class Driver;
  std::unique_ptr<Driver> Impl;
};

} // namespace canopy
