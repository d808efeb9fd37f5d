#include <canopy/InSitu.h>

#include "CanopyModule.h"
#include "CatalystScript.h"
#include "CatalystSession.h"
#include "CollectiveAgreement.h"
#include "DriverChecks.h"
#include "FailureLog.h"
#include "FinalizeGuard.h"
#include "JobOutput.h"
#include "LiveConnection.h"
#include "OwnCommunicator.h"
#include "RenderDecision.h"
#include "RuntimePaths.h"
#include "StepRequests.h"
#include "StepTriggers.h"
#include "StepWatchdog.h"
#include "XDisplayConnection.h"

#include <canopy/GridBuilder.h>
#include <canopy/HtgBuilder.h>

#include <vtkHyperTreeGrid.h>
#include <vtkLogger.h>
#include <vtkSmartPointer.h>
#include <vtk_loguru.h>

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <optional>

namespace canopy
{
namespace
{

/// ", surface quads 1234, ..." for the step summary; empty without measures.
std::string measuresText(const std::map<std::string, double>& measures)
{
  std::string text;
  for (const auto& [name, value] : measures)
  {
    char number[32];
    std::snprintf(number, sizeof number, " %.15g", value);
    text += ", " + name + number;
  }
  return text;
}

} // namespace

class InSitu::Driver
{
public:
  Driver(MPI_Comm communicator, InSituOptions options);
  ~Driver() { this->close(); }

  bool willExecute(std::int64_t step, double time);
  bool willExecute(std::int64_t step, double time, const ForestDescription& forest);
  StepReport execute(std::int64_t step, double time, const ForestDescription& forest);
  void close();
  bool isOpen() const { return this->Open; }
  bool canRender() const { return this->CanRender; }

private:
  void startScripts(const std::vector<PipelineScript>& scripts);
  /// The requests willExecute made for this step, or new ones.
  StepRequests takeRequests(std::int64_t step, double time);
  /// The step's queries and triggers (evaluated once per step; collective).
  TriggerOutcome takeTriggers(std::int64_t step, double time, const ForestDescription& forest);
  /// The grid with the fields the due scripts need; null (and the failures in
  /// `report`) if some rank cannot build it or write its output.
  vtkSmartPointer<vtkHyperTreeGrid> buildGrid(const ForestDescription& forest,
                                              const StepRequests& requests, StepReport& report);
  /// A due script at this step: its import on its first step (then its own
  /// request), then its run. Each phase ends in an agreement.
  void runScript(CatalystScript& script, vtkHyperTreeGrid* grid, std::int64_t step,
                 StepReport& report);
  void finalizeScripts();
  /// Rank 0: the query history as a PNG beside its CSV (each query against time,
  /// the triggers' firings marked), through Python; a failure is only logged.
  void plotHistory();
  /// The step's Catalyst Live exchange, when some script (or the options) asked
  /// for Live and some script ran (the same on every rank).
  void runLive(std::int64_t step, double time, StepReport& report);
  StepReport& finish(StepReport& report, std::int64_t step, double time,
                     std::chrono::steady_clock::time_point start) const;

  // Destroyed in reverse: scripts before Catalyst, Catalyst before the X
  // connection, the watchdog's thread before what it reports with.
  InSituOptions Options;
  std::unique_ptr<OwnCommunicator> Communicator; ///< Canopy's agreements only
  int Rank = 0;
  std::unique_ptr<JobOutput> Output;
  std::unique_ptr<StepWatchdog> Watchdog;
  std::unique_ptr<CollectiveAgreement> Agreement;
  std::unique_ptr<FailureLog> Failures;
  /// Held while scripts may render: xvfb-run's server resets when its last client leaves.
  std::unique_ptr<XDisplayConnection> Display;
  std::unique_ptr<CatalystSession> Session;
  /// The door between the driver and Python; before the scripts, which use it.
  std::unique_ptr<CanopyModule> Python;
  ScriptList Scripts;
  /// Before the scripts go: it refers to their proxies.
  std::unique_ptr<LiveConnection> Live;
  /// Keeps the grid from step to step, rebuilding only what changed.
  GridBuilder Builder;
  std::optional<StepRequests> Requested;
  /// Triggers and queries of the scripts and options; what willExecute evaluated.
  std::unique_ptr<StepTriggers> Triggers;
  std::optional<TriggerOutcome> Evaluated;
  bool CanRender = false;
  bool Open = false;
  std::unique_ptr<FinalizeGuard> Guard;
};

InSitu::Driver::Driver(MPI_Comm communicator, InSituOptions options) : Options(std::move(options))
{
  requireUsableMpi(communicator);
  this->Communicator = std::make_unique<OwnCommunicator>(communicator);
  const MPI_Comm comm = this->Communicator->get();
  MPI_Comm_rank(comm, &this->Rank);
  this->Output = std::make_unique<JobOutput>();

  // Every rank checks its options; all ranks throw together, naming each rank's problem.
  const auto problems = CollectiveAgreement(comm, *this->Output, 0.0, 0.0)
                            .gatherFailures(joined(normalizeAndCheckOptions(this->Options), "; "));
  if (!problems.empty())
  {
    throw InSituError("canopy::InSitu: " + joined(problems, "\n"));
  }
  const double limit = this->Options.stepTimeLimitSeconds;
  this->Watchdog = std::make_unique<StepWatchdog>(limit, this->Rank, comm, *this->Output);
  this->Agreement = std::make_unique<CollectiveAgreement>(comm, *this->Output, limit,
                                                          this->Watchdog->graceSeconds());
  this->Failures = std::make_unique<FailureLog>(*this->Agreement);
  if (this->Options.verbosity >= vtkLogger::VERBOSITY_TRACE - 18)
  {
    vtkLogger::SetStderrVerbosity(static_cast<vtkLogger::Verbosity>(this->Options.verbosity));
  }
  // VTK's log colours its lines whenever the terminal type could show colours,
  // also into a job's log file: colour only on a terminal.
  if (!isatty(STDERR_FILENO))
  {
    vtkloguru::g_colorlogtostderr = false;
  }

  this->Display = std::make_unique<XDisplayConnection>();
  const RenderPlan plan = planRendering(comm, this->Options.scripts, *this->Display);
  this->CanRender = plan.canRender;

  prepareOutputDirectory(this->Options.outputDirectory); // created now; reported at each step
  // Triggers and queries are parsed and checked before Catalyst starts (the same
  // options on every rank: every rank refuses alike).
  const std::string history =
      this->Options.queryHistoryFile.empty()
          ? std::string()
          : this->Options.outputDirectory + "/" + this->Options.queryHistoryFile;
  this->Triggers = std::make_unique<StepTriggers>(plan.scripts, this->Options, history, this->Rank);
  this->Session = std::make_unique<CatalystSession>(comm);
  if (!this->Agreement->allOf(this->Session->started()))
  {
    throw InSituError("canopy::InSitu: ParaView Catalyst failed to initialize");
  }
  this->startScripts(plan.scripts);
  this->Open = true;
  this->Guard = std::make_unique<FinalizeGuard>([this] { this->close(); });
  vtkVLogF(vtkLogger::VERBOSITY_TRACE, "canopy: open with %zu pipeline(s), output in '%s'",
           this->Scripts.size(), this->Options.outputDirectory.c_str());
}

void InSitu::Driver::startScripts(const std::vector<PipelineScript>& scripts)
{
  // Everything scripts learn from the driver, they learn through _canopy.
  PythonRunSettings settings{this->Options.outputDirectory, this->Options.channel, pluginPath(),
                             this->Options.liveUrl, scripts};
  this->Python = std::make_unique<CanopyModule>(std::move(settings), this->Communicator->get(),
                                                *this->Agreement, *this->Watchdog);
  std::string localProblem = this->Python->importHelperModules(pipelinesDirectory());
  if (localProblem.empty())
  {
    if (this->Watchdog->limitSeconds() > 0.0)
    {
      this->Watchdog->useSignal(PythonSide::installInterrupt(StepWatchdog::interruptSignal));
    }
    try
    {
      for (const auto& script : scripts)
      {
        this->Scripts.push_back(
            std::make_unique<CatalystScript>(script.path, this->Options.channel, *this->Watchdog));
      }
    }
    catch (const std::exception& error)
    {
      localProblem = error.what();
    }
  }
  const auto failures = this->Agreement->gatherFailures(localProblem);
  if (!failures.empty())
  {
    throw InSituError("canopy::InSitu: " + joined(failures, "\n"));
  }
}

StepRequests InSitu::Driver::takeRequests(std::int64_t step, double time)
{
  std::optional<StepRequests> requested;
  requested.swap(this->Requested); // each execute() asks anew next time
  if (requested && requested->step == step && requested->time == time)
  {
    return std::move(*requested);
  }
  return requestScripts(this->Scripts, *this->Agreement, *this->Failures, step, time);
}

bool InSitu::Driver::willExecute(std::int64_t step, double time)
{
  if (!this->Open)
  {
    return false;
  }
  this->Requested = this->takeRequests(step, time);
  return !this->Requested->failures.empty() || this->Requested->anyDue();
}

bool InSitu::Driver::willExecute(std::int64_t step, double time, const ForestDescription& forest)
{
  if (!this->Open)
  {
    return false;
  }
  this->Requested = this->takeRequests(step, time);
  if (!this->Triggers->active())
  {
    return !this->Requested->failures.empty() || this->Requested->anyDue();
  }
  this->Evaluated = this->takeTriggers(step, time, forest);
  bool any = !this->Requested->failures.empty() || !this->Evaluated->failure.empty();
  for (std::size_t i = 0; i < this->Requested->due.size(); ++i)
  {
    any = any || (this->Requested->due[i] && this->Evaluated->allowed[i]);
  }
  return any;
}

TriggerOutcome InSitu::Driver::takeTriggers(std::int64_t step, double time,
                                            const ForestDescription& forest)
{
  std::optional<TriggerOutcome> evaluated;
  evaluated.swap(this->Evaluated);
  if (evaluated && evaluated->step == step && evaluated->time == time)
  {
    return std::move(*evaluated);
  }
  TriggerOutcome outcome = this->Triggers->evaluate(this->Communicator->get(), step, time, forest);
  if (!outcome.warning.empty())
  {
    vtkLogF(WARNING, "canopy: rank %d, step %lld: %s", this->Rank, static_cast<long long>(step),
            outcome.warning.c_str());
  }
  return outcome;
}

StepReport& InSitu::Driver::finish(StepReport& report, std::int64_t step, double time,
                                   std::chrono::steady_clock::time_point start) const
{
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (this->Options.stepSummary && report.executed && this->Rank == 0)
  {
    vtkLogF(INFO,
            "canopy: step %lld time %g: ran [%s], %zu failure(s), %lld cells on rank 0, %.3f s "
            "(grid %.3f s, %zu of %zu trees rebuilt)%s",
            static_cast<long long>(step), time, joined(report.pipelinesRun, ", ").c_str(),
            report.failures.size(), static_cast<long long>(report.localCells), report.seconds,
            report.buildSeconds, report.treesRebuilt, report.treesRebuilt + report.treesKept,
            (measuresText(report.measures) + measuresText(report.expressions)).c_str());
  }
  return report;
}

StepReport InSitu::Driver::execute(std::int64_t step, double time, const ForestDescription& forest)
{
  const auto start = std::chrono::steady_clock::now();
  StepReport report;
  if (!this->Open)
  {
    report.failures.push_back("rank " + std::to_string(this->Rank) + ", step " +
                              std::to_string(step) + ": execute() after close()");
    return this->finish(report, step, time, start);
  }
  StepRequests requests = this->takeRequests(step, time);
  report.failures = requests.failures;
  if (this->Triggers->active())
  {
    TriggerOutcome outcome = this->takeTriggers(step, time, forest);
    report.queriesEvaluated = true;
    report.queries = std::move(outcome.queries);
    report.expressions = std::move(outcome.expressions);
    report.triggersFired = std::move(outcome.fired);
    report.querySeconds = outcome.seconds;
    if (!outcome.failure.empty())
    {
      report.failures.push_back(outcome.failure);
    }
    for (std::size_t i = 0; i < requests.due.size(); ++i)
    {
      requests.due[i] = requests.due[i] && outcome.allowed[i];
    }
  }
  // What the scripts of this step read with canopy_catalyst.query_values().
  std::map<std::string, double> values = report.expressions;
  for (const auto& [text, result] : report.queries)
  {
    values[text] = result.value;
  }
  CanopyModule::setQueryValues(std::move(values));
  report.executed = requests.anyDue() || !report.failures.empty();
  if (!requests.anyDue())
  {
    return this->finish(report, step, time, start);
  }
  const auto grid = this->buildGrid(forest, requests, report);
  for (std::size_t i = 0; grid && i < this->Scripts.size(); ++i)
  {
    if (requests.due[i])
    {
      this->runScript(*this->Scripts[i], grid, step, report);
    }
  }
  if (grid && !report.pipelinesRun.empty())
  {
    this->runLive(step, time, report);
  }
  return this->finish(report, step, time, start);
}

vtkSmartPointer<vtkHyperTreeGrid> InSitu::Driver::buildGrid(const ForestDescription& forest,
                                                            const StepRequests& requests,
                                                            StepReport& report)
{
  // Built only now, and only with the fields some due pipeline asked for.
  vtkSmartPointer<vtkHyperTreeGrid> grid;
  std::string localProblem = prepareOutputDirectory(this->Options.outputDirectory);
  if (localProblem.empty())
  {
    try
    {
      const auto start = std::chrono::steady_clock::now();
      grid = this->Builder.build(forest, fieldsNeeded(this->Scripts, requests.due, forest));
      report.buildSeconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      report.localCells = grid->GetNumberOfCells();
      report.treesRebuilt = this->Builder.lastBuild().treesRebuilt;
      report.treesKept = this->Builder.lastBuild().treesKept;
    }
    catch (const InvalidForest& error)
    {
      localProblem = "invalid forest: " + joined(error.problems(), "; "); // one line per rank
    }
    catch (const std::exception& error)
    {
      localProblem = std::string("cannot build the grid: ") + error.what();
    }
  }
  const std::string stepText = "step " + std::to_string(requests.step) + ": ";
  const auto failures = this->Failures->gather(localProblem.empty() ? "" : stepText + localProblem);
  report.failures.insert(report.failures.end(), failures.begin(), failures.end());
  return failures.empty() ? grid : nullptr;
}

void InSitu::Driver::runScript(CatalystScript& script, vtkHyperTreeGrid* grid, std::int64_t step,
                               StepReport& report)
{
  // Each phase that can fail on some ranks only (import, the script's own
  // request, the run) ends in an agreement, so no rank enters a script's
  // collectives alone; the agreement after a script call is bounded by the
  // step time limit.
  const std::string stepText = "step " + std::to_string(step) + ": ";
  const std::string phaseText =
      "the script '" + script.path() + "' (%) at step " + std::to_string(step);
  auto after = [&](const char* phase, std::chrono::steady_clock::time_point since, double extra)
  {
    std::string what = phaseText;
    what.replace(what.find('%'), 1, phase);
    return CollectiveAgreement::After{what, since, extra};
  };
  auto agree =
      [&](const std::string& localError, const CollectiveAgreement::After* waited = nullptr)
  {
    const std::string traceback = script.lastTraceback().empty()
                                      ? std::string()
                                      : stepText + "Python traceback of the script '" +
                                            script.path() + "':\n" + script.lastTraceback();
    const auto failures =
        this->Failures->gather(localError.empty() ? "" : stepText + localError, traceback, waited);
    report.failures.insert(report.failures.end(), failures.begin(), failures.end());
    return failures.empty();
  };
  std::string error;
  if (!script.imported())
  {
    auto since = std::chrono::steady_clock::now();
    const bool imported = script.import(grid, error);
    const auto importing = after("import", since, StepWatchdog::firstStepExtraSeconds);
    if (!agree(imported ? "" : error + "; the script is disabled", &importing))
    {
      script.disable(); // on every rank, also where the import worked
      return;
    }
    since = std::chrono::steady_clock::now();
    const ScriptState state = script.requestAfterImport(error);
    const auto asking = after("RequestDataDescription", since, script.extraSeconds());
    const auto agreed = this->Agreement->agree({state}, &asking);
    if (agreed.maximum[0] == ScriptState::Failed)
    {
      agree(state == ScriptState::Failed ? error : "");
      return;
    }
    if (agreed.minimum[0] != agreed.maximum[0])
    {
      agree(this->Rank == 0 ? "ranks disagree whether '" + script.path() + "' runs; skipped" : "");
      return;
    }
    if (agreed.maximum[0] == ScriptState::NotDue)
    {
      return; // imported, and not due at this step
    }
  }
  const auto since = std::chrono::steady_clock::now();
  const double extraSeconds = script.extraSeconds();
  const bool ran = script.run(grid, error);
  const auto running = after("catalyst_execute", since, extraSeconds);
  const bool ranEverywhere = agree(ran ? "" : error, &running);
  // Collective only when the script ran on every rank (then every rank is here).
  for (const auto& [name, value] : PythonSide::takeMeasures(ranEverywhere))
  {
    report.measures[name] = value;
  }
  if (ranEverywhere)
  {
    report.pipelinesRun.push_back(script.path());
  }
  else
  {
    script.discardOutputs(); // nothing half-written may look like a result
  }
}

void InSitu::Driver::runLive(std::int64_t step, double time, StepReport& report)
{
  if (!this->Live)
  {
    std::string url = this->Options.liveUrl;
    for (const auto& script : this->Scripts)
    {
      url = url.empty() ? script->liveUrl() : url;
    }
    if (url.empty())
    {
      return;
    }
    LiveConnection::Settings settings;
    settings.pauseLimitSeconds = this->Options.livePauseLimitSeconds;
    settings.stallSeconds = this->Options.liveStallSeconds;
    std::string error;
    if (!LiveConnection::parseUrl(url, settings, error))
    {
      // Only a script's own CatalystLiveURL gets here unchecked (the options' is
      // checked at start): the same on every rank, so no rank starts Live.
      report.liveWarnings.push_back(error + "; Catalyst Live is off");
      vtkLogF(WARNING, "canopy: rank %d, step %lld: %s", this->Rank, static_cast<long long>(step),
              report.liveWarnings.back().c_str());
      return;
    }
    this->Live = std::make_unique<LiveConnection>(settings);
  }
  const auto start = std::chrono::steady_clock::now();
  report.liveWarnings = this->Live->update(time, step);
  report.liveSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const auto& warning : report.liveWarnings)
  {
    vtkLogF(WARNING, "canopy: rank %d, step %lld: Catalyst Live: %s", this->Rank,
            static_cast<long long>(step), warning.c_str());
  }
}

void InSitu::Driver::finalizeScripts()
{
  // Every rank finalizes its scripts; failures are gathered and logged by rank 0.
  std::string localErrors;
  std::string tracebacks;
  const auto since = std::chrono::steady_clock::now();
  for (auto& script : this->Scripts)
  {
    std::string error;
    if (!script->finalize(error))
    {
      localErrors += (localErrors.empty() ? "" : "; ") + error;
      if (!script->lastTraceback().empty())
      {
        tracebacks += "close: Python traceback of the script '" + script->path() + "':\n" +
                      script->lastTraceback();
      }
    }
  }
  const CollectiveAgreement::After finalizing{"catalyst_finalize of the scripts at close", since};
  this->Failures->gather(localErrors.empty() ? "" : "close: " + localErrors, tracebacks,
                         &finalizing);
}

void InSitu::Driver::plotHistory()
{
  const std::string csv = this->Triggers ? this->Triggers->writtenHistory() : std::string();
  if (csv.empty() || !this->Python)
  {
    return;
  }
  this->Triggers.reset(); // the file closed, every row in it
  const std::string png =
      (csv.size() > 4 && csv.compare(csv.size() - 4, 4, ".csv") == 0 ? csv.substr(0, csv.size() - 4)
                                                                     : csv) +
      ".png";
  const std::string problem = PythonSide::plotHistory(csv, png);
  if (!problem.empty())
  {
    vtkLogF(WARNING, "canopy: close: %s", problem.c_str());
  }
}

void InSitu::Driver::close()
{
  if (!this->Open)
  {
    return;
  }
  this->Open = false;
  this->Guard->disarm();
  this->finalizeScripts();
  this->plotHistory();
  this->Python.reset(); // _canopy's functions raise from now on
  this->Live.reset();
  this->Scripts.clear();
  this->Triggers.reset(); // closes the history file
  this->Session.reset();
  this->Display.reset();
  this->Failures.reset();
  this->Agreement.reset();
  this->Watchdog.reset();
  this->Communicator.reset();
}

InSitu::InSitu(MPI_Comm communicator, InSituOptions options)
    : Impl(std::make_unique<Driver>(communicator, std::move(options)))
{
}

InSitu::~InSitu() = default;

bool InSitu::willExecute(std::int64_t step, double time)
{
  return this->Impl->willExecute(step, time);
}

bool InSitu::willExecute(std::int64_t step, double time, const ForestDescription& forest)
{
  return this->Impl->willExecute(step, time, forest);
}

StepReport InSitu::execute(std::int64_t step, double time, const ForestDescription& forest)
{
  return this->Impl->execute(step, time, forest);
}

void InSitu::close()
{
  this->Impl->close();
}

bool InSitu::isOpen() const
{
  return this->Impl->isOpen();
}

bool InSitu::canRender() const
{
  return this->Impl->canRender();
}

} // namespace canopy
