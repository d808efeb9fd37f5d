#include "canopy/InSitu.h"

#include "CatalystScript.h"
#include "CollectiveAgreement.h"
#include "DisplayProbe.h"
#include "DriverPython.h"
#include "FinalizeGuard.h"
#include "JobOutput.h"
#include "RuntimePaths.h"
#include "ScriptInspection.h"
#include "StepWatchdog.h"

#include "canopy/HtgBuilder.h"

#include <vtkCPProcessor.h>
#include <vtkHyperTreeGrid.h>
#include <vtkLogger.h>
#include <vtkMPI.h>
#include <vtkSmartPointer.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

namespace canopy
{
namespace
{

std::string joined(const std::vector<std::string>& items, const char* separator)
{
  std::string text;
  for (const auto& item : items)
  {
    text += (text.empty() ? "" : separator) + item;
  }
  return text;
}

/// Empty when `directory` exists (or can be created) and is writable.
std::string outputDirectoryProblem(const std::string& directory)
{
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  if (!std::filesystem::is_directory(directory, error))
  {
    return "the output directory '" + directory + "' does not exist and cannot be created";
  }
  if (access(directory.c_str(), W_OK | X_OK) != 0)
  {
    return "the output directory '" + directory + "' is not writable";
  }
  return {};
}

/// Only one driver may be open per process: ParaView's Catalyst state is global.
bool driverOpen = false;
/// ParaView 5.11's Catalyst cannot be initialized again once finalized (the
/// second vtkCPProcessor::Initialize aborts the process).
bool catalystStarted = false;

} // namespace

class InSitu::Driver
{
public:
  Driver(MPI_Comm communicator, InSituOptions options);
  ~Driver() { this->close(); }

  bool willExecute(std::int64_t step, double time);
  StepReport execute(std::int64_t step, double time, const ForestDescription& forest);
  void close();
  bool isOpen() const { return this->Open; }
  bool canRender() const { return this->CanRender; }

private:
  struct Requests
  {
    std::int64_t step = 0;
    double time = 0.0;
    std::vector<bool> due;
    std::vector<std::string> failures;
    bool valid = false;
  };
  const Requests& requestAll(std::int64_t step, double time);
  void logFailures(const std::vector<std::string>& failures) const;
  /// After calls into scripts: every rank's failure, gathered; rank 0 logs them
  /// with the Python tracebacks of the other ranks (ParaView silences their
  /// stderr). `localTraceback` goes with this rank's failure: "step 4: Python
  /// traceback of the script '...':\n...".
  std::vector<std::string> gatherScriptFailures(const std::string& localFailure,
                                                const std::string& localTraceback,
                                                const RankAgreement::After* after) const;
  FieldRequest fieldsFor(const std::vector<bool>& due, const ForestDescription& forest) const;

  // Canopy's agreements and ParaView's collectives on separate communicators:
  // a rank waiting in one can never be matched with a rank in the other.
  MPI_Comm Communicator = MPI_COMM_NULL;
  MPI_Comm ParaViewCommunicator = MPI_COMM_NULL;
  int Rank = 0;
  InSituOptions Options;
  std::unique_ptr<JobOutput> Output;
  std::unique_ptr<RankAgreement> Agreement;
  std::unique_ptr<StepWatchdog> Watchdog;
  vtkSmartPointer<vtkCPProcessor> Processor;
  std::vector<std::unique_ptr<CatalystScript>> Scripts;
  bool CanRender = false;
  bool Open = false;
  Requests LastRequests;
  std::unique_ptr<XDisplayConnection> Display;
  std::unique_ptr<FinalizeGuard> Guard;
};

InSitu::Driver::Driver(MPI_Comm communicator, InSituOptions options) : Options(std::move(options))
{
  int initialized = 0;
  MPI_Initialized(&initialized);
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!initialized || finalized)
  {
    throw InSituError("canopy::InSitu: MPI must be initialized (and not finalized) before open");
  }
  if (communicator == MPI_COMM_NULL)
  {
    throw InSituError("canopy::InSitu: the communicator is MPI_COMM_NULL");
  }
  MPI_Comm_dup(communicator, &this->Communicator);
  MPI_Comm_rank(this->Communicator, &this->Rank);
  this->Output = std::make_unique<JobOutput>();
  auto fail = [this](const std::string& message)
  {
    this->Watchdog.reset();
    MPI_Comm_free(&this->Communicator);
    if (this->ParaViewCommunicator != MPI_COMM_NULL)
    {
      MPI_Comm_free(&this->ParaViewCommunicator);
    }
    throw InSituError("canopy::InSitu: " + message);
  };

  // Every rank checks its options; all ranks throw together, naming each rank's problem.
  std::vector<std::string> problems;
  if (driverOpen)
  {
    problems.push_back("another canopy::InSitu is open in this process");
  }
  else if (catalystStarted)
  {
    problems.push_back("Catalyst was already started and finalized in this process; ParaView "
                       "5.11 cannot start it again (open one canopy::InSitu per run)");
  }
  if (this->Options.scripts.empty())
  {
    problems.push_back("no pipeline script given");
  }
  if (this->Options.channel.empty())
  {
    problems.push_back("the channel name is empty");
  }
  if (this->Options.outputDirectory.empty())
  {
    problems.push_back("the output directory is empty");
  }
  if (!std::isfinite(this->Options.stepTimeLimitSeconds) ||
      this->Options.stepTimeLimitSeconds < 0.0)
  {
    problems.push_back("the step time limit must be a finite number of seconds >= 0 (0: none)");
  }
  // Absolute paths: ParaView imports scripts lazily, and the simulation may
  // change its working directory after open.
  std::error_code ignoredError;
  for (auto& script : this->Options.scripts)
  {
    script.path = std::filesystem::absolute(script.path, ignoredError).lexically_normal().string();
  }
  this->Options.outputDirectory =
      std::filesystem::absolute(this->Options.outputDirectory, ignoredError).string();
  std::set<std::string> seen;
  for (const auto& script : this->Options.scripts)
  {
    std::string why;
    if (!scriptReadable(script.path, why))
    {
      problems.push_back("pipeline script '" + script.path + "': " + why);
    }
    if (!seen.insert(script.path).second)
    {
      problems.push_back("pipeline script '" + script.path +
                         "' is given twice (copy it to run it with other arguments)");
    }
  }
  const auto optionFailures = RankAgreement(this->Communicator, *this->Output, 0.0, 0.0)
                                  .gatherFailures(joined(problems, "; "));
  if (!optionFailures.empty())
  {
    fail(joined(optionFailures, "\n"));
  }
  this->Watchdog = std::make_unique<StepWatchdog>(this->Options.stepTimeLimitSeconds, this->Rank,
                                                  this->Communicator, *this->Output);
  this->Agreement = std::make_unique<RankAgreement>(this->Communicator, *this->Output,
                                                    this->Options.stepTimeLimitSeconds,
                                                    this->Watchdog->graceSeconds());

  if (this->Options.verbosity >= vtkLogger::VERBOSITY_TRACE - 18)
  {
    vtkLogger::SetStderrVerbosity(static_cast<vtkLogger::Verbosity>(this->Options.verbosity));
  }

  // Images need an X display on every rank (IceT composites across all of them).
  this->Display = std::make_unique<XDisplayConnection>();
  const std::string noDisplay = this->Display->why();
  int localDisplay = this->Display->connected() ? 1 : 0;
  int everyDisplay = 0;
  MPI_Allreduce(&localDisplay, &everyDisplay, 1, MPI_INT, MPI_MIN, this->Communicator);
  this->CanRender = everyDisplay == 1;
  // Rank 0 decides which scripts render, so that every rank keeps the same list.
  std::vector<int> renders(this->Options.scripts.size(), 0);
  if (this->Rank == 0)
  {
    for (std::size_t i = 0; i < renders.size(); ++i)
    {
      renders[i] = scriptRenders(this->Options.scripts[i].path) ? 1 : 0;
    }
  }
  MPI_Bcast(renders.data(), static_cast<int>(renders.size()), MPI_INT, 0, this->Communicator);
  std::vector<PipelineScript> kept;
  std::vector<std::string> skipped;
  for (std::size_t i = 0; i < renders.size(); ++i)
  {
    const auto& script = this->Options.scripts[i];
    if (!this->CanRender && renders[i])
    {
      skipped.push_back(script.path);
    }
    else
    {
      kept.push_back(script);
    }
  }
  if (!skipped.empty() && this->Rank == 0)
  {
    vtkLogF(WARNING,
            "canopy: no X display (%s on at least one rank): rendering pipeline(s) %s will not "
            "run at any step; data extracts still run. Run under 'xvfb-run -a' to get images.",
            noDisplay.empty() ? "another rank has none" : noDisplay.c_str(),
            joined(skipped, ", ").c_str());
  }

  // Scripts find their settings, the plugin and the helper module through these.
  setenv("CANOPY_OUTPUT_DIRECTORY", this->Options.outputDirectory.c_str(), 1);
  setenv("CANOPY_CHANNEL", this->Options.channel.c_str(), 1);
  setenv("CANOPY_PLUGIN", pluginPath().c_str(), 0);
  std::error_code ignored;
  std::filesystem::create_directories(this->Options.outputDirectory, ignored);

  catalystStarted = true;
  this->Processor = vtkSmartPointer<vtkCPProcessor>::New();
  MPI_Comm_dup(this->Communicator, &this->ParaViewCommunicator);
  vtkMPICommunicatorOpaqueComm opaque(&this->ParaViewCommunicator);
  int started = this->Processor->Initialize(opaque);
  int everyStarted = 0;
  MPI_Allreduce(&started, &everyStarted, 1, MPI_INT, MPI_MIN, this->Communicator);
  if (!everyStarted)
  {
    this->Processor->Finalize();
    this->Processor = nullptr;
    fail("ParaView Catalyst failed to initialize");
  }

  std::string localProblem = startDriverPython(pipelinesDirectory(), kept);
  if (localProblem.empty())
  {
    this->Watchdog->connectPython();
    connectAgreement(this->Agreement.get(), this->Watchdog.get());
    try
    {
      for (const auto& script : kept)
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
  const auto startFailures = this->Agreement->gatherFailures(localProblem);
  if (!startFailures.empty())
  {
    this->Scripts.clear();
    this->Processor->Finalize();
    this->Processor = nullptr;
    fail(joined(startFailures, "\n"));
  }

  this->Open = true;
  driverOpen = true;
  this->Guard = std::make_unique<FinalizeGuard>([this] { this->close(); });
  vtkVLogF(vtkLogger::VERBOSITY_TRACE, "canopy: open with %zu pipeline(s), output in '%s'",
           this->Scripts.size(), this->Options.outputDirectory.c_str());
}

const InSitu::Driver::Requests& InSitu::Driver::requestAll(std::int64_t step, double time)
{
  Requests& requests = this->LastRequests;
  if (requests.valid && requests.step == step && requests.time == time)
  {
    return requests;
  }
  requests = Requests{step, time, std::vector<bool>(this->Scripts.size(), false), {}, true};
  std::vector<ScriptState> states(this->Scripts.size(), ScriptState::NotDue);
  std::string localErrors;
  std::string tracebacks;
  const auto since = std::chrono::steady_clock::now();
  double extraSeconds = 0.0;
  for (std::size_t i = 0; i < this->Scripts.size(); ++i)
  {
    std::string error;
    extraSeconds = std::max(extraSeconds, this->Scripts[i]->extraSeconds());
    states[i] = this->Scripts[i]->request(step, time, error);
    if (states[i] == ScriptState::Failed)
    {
      localErrors += (localErrors.empty() ? "" : "; ") + error;
      if (!this->Scripts[i]->lastTraceback().empty())
      {
        tracebacks += "step " + std::to_string(step) + ": Python traceback of the script '" +
                      this->Scripts[i]->path() + "':\n" + this->Scripts[i]->lastTraceback();
      }
    }
  }
  const auto waited = RankAgreement::After{
      "RequestDataDescription of the scripts at step " + std::to_string(step), since, extraSeconds};
  const auto agreed = this->Agreement->agree(states, &waited);
  bool anyProblem = false;
  for (std::size_t i = 0; i < this->Scripts.size(); ++i)
  {
    anyProblem = anyProblem || agreed.maximum[i] == ScriptState::Failed ||
                 agreed.minimum[i] != agreed.maximum[i];
    requests.due[i] = agreed.minimum[i] == ScriptState::Due;
  }
  if (anyProblem)
  {
    std::string local =
        localErrors.empty() ? std::string() : "step " + std::to_string(step) + ": " + localErrors;
    requests.failures = this->Agreement->gatherFailures(local);
    const auto everyTraceback = this->Agreement->gatherOnRoot(tracebacks);
    for (std::size_t rank = 1; rank < everyTraceback.size(); ++rank)
    {
      if (!everyTraceback[rank].empty())
      {
        vtkLogF(ERROR, "canopy: rank %zu, %s", rank, everyTraceback[rank].c_str());
      }
    }
    for (std::size_t i = 0; i < this->Scripts.size(); ++i)
    {
      if (agreed.maximum[i] != ScriptState::Failed && agreed.minimum[i] != agreed.maximum[i])
      {
        requests.failures.push_back("step " + std::to_string(step) + ": ranks disagree whether '" +
                                    this->Scripts[i]->path() + "' runs; skipped");
      }
    }
  }
  return requests;
}

bool InSitu::Driver::willExecute(std::int64_t step, double time)
{
  if (!this->Open)
  {
    return false;
  }
  const auto& requests = this->requestAll(step, time);
  return !requests.failures.empty() ||
         std::any_of(requests.due.begin(), requests.due.end(), [](bool due) { return due; });
}

FieldRequest InSitu::Driver::fieldsFor(const std::vector<bool>& due,
                                       const ForestDescription& forest) const
{
  std::vector<std::string> present;
  for (std::size_t i = 0; i < this->Scripts.size(); ++i)
  {
    if (!due[i])
    {
      continue;
    }
    const auto& script = *this->Scripts[i];
    if (script.needsAllFields())
    {
      return FieldRequest::all();
    }
    unsigned int found = 0;
    for (const auto& field : forest.fields)
    {
      if (script.needsField(field.name))
      {
        ++found;
        if (std::find(present.begin(), present.end(), field.name) == present.end())
        {
          present.push_back(field.name);
        }
      }
    }
    if (found < script.numberOfNeededFields())
    {
      vtkVLogF(vtkLogger::VERBOSITY_TRACE,
               "canopy: '%s' asks for %u field(s) the forest does not have", script.path().c_str(),
               script.numberOfNeededFields() - found);
    }
  }
  return FieldRequest::only(present);
}

void InSitu::Driver::logFailures(const std::vector<std::string>& failures) const
{
  // Ranks above 0 have their stderr silenced by ParaView; every rank's
  // failures are gathered, so rank 0 reports them all.
  if (this->Rank != 0)
  {
    return;
  }
  for (const auto& failure : failures)
  {
    vtkLogF(ERROR, "canopy: %s", failure.c_str());
  }
}

std::vector<std::string>
InSitu::Driver::gatherScriptFailures(const std::string& localFailure,
                                     const std::string& localTraceback,
                                     const RankAgreement::After* after) const
{
  const std::string traceback = localFailure.empty() ? std::string() : localTraceback;
  auto failures = this->Agreement->gatherFailures(localFailure, after, traceback);
  if (failures.empty())
  {
    return failures;
  }
  // Everyone knows that some rank failed: the tracebacks can be gathered too.
  const auto tracebacks = this->Agreement->gatherOnRoot(traceback);
  this->logFailures(failures);
  for (std::size_t rank = 1; rank < tracebacks.size(); ++rank)
  {
    if (!tracebacks[rank].empty())
    {
      vtkLogF(ERROR, "canopy: rank %zu, %s", rank, tracebacks[rank].c_str());
    }
  }
  return failures;
}

StepReport InSitu::Driver::execute(std::int64_t step, double time, const ForestDescription& forest)
{
  const auto start = std::chrono::steady_clock::now();
  StepReport report;
  auto finish = [&]() -> StepReport
  {
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (this->Options.stepSummary && report.executed && this->Rank == 0)
    {
      vtkLogF(INFO,
              "canopy: step %lld time %g: ran [%s], %zu failure(s), %lld cells on rank 0, %.3f s",
              static_cast<long long>(step), time, joined(report.pipelinesRun, ", ").c_str(),
              report.failures.size(), static_cast<long long>(report.localCells), report.seconds);
    }
    return report;
  };
  if (!this->Open)
  {
    report.failures.push_back("rank " + std::to_string(this->Rank) + ", step " +
                              std::to_string(step) + ": execute() after close()");
    return finish();
  }

  const Requests requests = this->requestAll(step, time);
  this->LastRequests.valid = false; // each execute() asks anew next time
  report.failures = requests.failures;
  this->logFailures(requests.failures);
  if (std::none_of(requests.due.begin(), requests.due.end(), [](bool due) { return due; }))
  {
    report.executed = !requests.failures.empty();
    return finish();
  }
  report.executed = true;

  // Build only now, and only with the fields some due pipeline asked for.
  vtkSmartPointer<vtkHyperTreeGrid> grid;
  std::string localProblem = outputDirectoryProblem(this->Options.outputDirectory);
  if (localProblem.empty())
  {
    try
    {
      grid = buildHyperTreeGrid(forest, this->fieldsFor(requests.due, forest));
      report.localCells = grid->GetNumberOfCells();
    }
    catch (const InvalidForest& error)
    {
      // One line per failure in the report: the problems, separated by ';'.
      std::string problems;
      for (const auto& problem : error.problems())
      {
        problems += (problems.empty() ? "" : "; ") + problem;
      }
      localProblem = "invalid forest: " + problems;
    }
    catch (const std::exception& error)
    {
      localProblem = std::string("cannot build the grid: ") + error.what();
    }
  }
  const std::string stepText = "step " + std::to_string(step) + ": ";
  const auto buildFailures =
      this->Agreement->gatherFailures(localProblem.empty() ? "" : stepText + localProblem);
  if (!buildFailures.empty())
  {
    this->logFailures(buildFailures);
    report.failures.insert(report.failures.end(), buildFailures.begin(), buildFailures.end());
    return finish();
  }

  // Each phase that can fail on some ranks only (import, the script's own
  // request, the run) ends in an agreement, so no rank enters a script's
  // collectives alone.
  auto agree = [&](const CatalystScript& script, const std::string& localError,
                   const RankAgreement::After* waited = nullptr)
  {
    const std::string traceback = script.lastTraceback().empty()
                                      ? std::string()
                                      : stepText + "Python traceback of the script '" +
                                            script.path() + "':\n" + script.lastTraceback();
    auto failures = this->gatherScriptFailures(localError.empty() ? "" : stepText + localError,
                                               traceback, waited);
    report.failures.insert(report.failures.end(), failures.begin(), failures.end());
    return failures.empty();
  };
  for (std::size_t i = 0; i < this->Scripts.size(); ++i)
  {
    if (!requests.due[i])
    {
      continue;
    }
    auto& script = *this->Scripts[i];
    const std::string scriptText = "the script '" + script.path() + "'";
    const std::string atStep = " at step " + std::to_string(step);
    std::string error;
    if (!script.imported())
    {
      auto since = std::chrono::steady_clock::now();
      const bool imported = script.import(grid, error);
      const auto importing = RankAgreement::After{scriptText + " (import)" + atStep, since,
                                                  StepWatchdog::firstStepExtraSeconds};
      if (!agree(script, imported ? "" : error + "; the script is disabled", &importing))
      {
        script.disable(); // on every rank, also where the import worked
        continue;
      }
      since = std::chrono::steady_clock::now();
      const auto state = script.requestAfterImport(error);
      const auto requesting = RankAgreement::After{
          scriptText + " (RequestDataDescription)" + atStep, since, script.extraSeconds()};
      const auto agreed = this->Agreement->agree({state}, &requesting);
      if (agreed.maximum[0] == ScriptState::Failed)
      {
        agree(script, state == ScriptState::Failed ? error : "");
        continue;
      }
      if (agreed.minimum[0] != agreed.maximum[0])
      {
        agree(script, this->Rank == 0
                          ? "ranks disagree whether '" + script.path() + "' runs; skipped"
                          : "");
        continue;
      }
      if (agreed.maximum[0] == ScriptState::NotDue)
      {
        continue; // imported, and not due at this step
      }
    }
    const auto since = std::chrono::steady_clock::now();
    const double extraSeconds = script.extraSeconds();
    const bool ran = script.run(grid, error);
    const auto running =
        RankAgreement::After{scriptText + " (catalyst_execute)" + atStep, since, extraSeconds};
    if (agree(script, ran ? "" : error, &running))
    {
      report.pipelinesRun.push_back(script.path());
    }
    else
    {
      script.discardOutputs(); // nothing half-written may look like a result
    }
  }
  return finish();
}

void InSitu::Driver::close()
{
  if (!this->Open)
  {
    return;
  }
  this->Open = false;
  driverOpen = false;
  if (this->Guard)
  {
    this->Guard->disarm();
  }
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
  const auto finalizing = RankAgreement::After{"catalyst_finalize of the scripts at close", since};
  this->gatherScriptFailures(localErrors.empty() ? "" : "close: " + localErrors, tracebacks,
                             &finalizing);
  this->Scripts.clear();
  connectAgreement(nullptr, nullptr);
  this->Processor->Finalize();
  this->Processor = nullptr;
  this->Watchdog.reset();
  this->Display.reset();
  MPI_Comm_free(&this->ParaViewCommunicator);
  MPI_Comm_free(&this->Communicator);
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
