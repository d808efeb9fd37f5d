// The one door between Canopy's in-situ driver and Python: the built-in module
// `_canopy`. Every call across the border is declared here, in both directions.
//
// Python -> driver: the functions of `_canopy` (pipelines/_canopy_driver.py and
// pipelines/canopy_catalyst.py call them; neither is importable outside the driver's
// process, so scripts run in pvbatch fall back to their documented defaults):
//
//   run_settings() -> RunSettings(output_directory, channel, plugin, live)
//       what InSituOptions say about the run ("" for live: none given)
//   script_arguments(path) -> [str]
//       the arguments the simulation gave the script at `path` ([] if none)
//   reduce(values, operation) -> [float]
//       `values` reduced element-wise over the ranks, `operation` "min", "max" or "sum";
//       collective, on a communicator of Canopy's that only these reductions use
//   agree_before_extracts(outcome, needed, free) -> (failed anywhere, needed by all, least free)
//       the ranks' agreement between a script's catalyst_execute and its extracts;
//       `outcome` "" where the script succeeded, else its failure; collective, on the
//       driver's agreement communicator
//   query_values() -> {str: float}
//       the step's query values (StepReport::queries' values and ::expressions) by their
//       text, the same on every rank; {} when no query ran at this step
//   interrupt_wanted() -> str or None
//       the step time limit's message when the running script call must stop
//   connect(side)
//       registers the Python side: the object the driver calls (below)
//   StepTimeLimitExceeded
//       the exception (a TimeoutError) the step time limit raises in a script
//
// driver -> Python: methods of the object registered with connect() (pipelines/
// _canopy_driver.py registers one when the driver imports it), called through
// PythonSide only:
//
//   take_failure() -> (summary, traceback) or None
//   take_measures(evaluate) -> {name: total over ranks}
//   discard_outputs(script_path)
//   install_interrupt(signal_number) -> bool
//   plot_history(csv_path, png_path) -> str   ("" when written, else why not)
//
// Why a module in sys.modules and not PyImport_AppendInittab: in a plain run Python
// starts here (ParaView's Catalyst start leaves it to the driver), but it may
// already be running when the driver opens (a simulation that embeds Python or
// uses VTK's; tests/bench/ImageStepBenchmark.cxx starts it first to time it);
// vtkPythonInterpreter::Initialize then leaves it as it is, and AppendInittab is
// only allowed before Py_Initialize (Python 3.12 aborts). One way for both cases:
// the module is created and put in sys.modules, where `import _canopy` finds it,
// the first time the driver opens in the process.
#pragma once

#include <canopy/InSitu.h>

#include <mpi.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace canopy
{

class CollectiveAgreement;
class OwnCommunicator;
class StepWatchdog;

/// What `_canopy.run_settings()` and `_canopy.script_arguments()` give Python.
struct PythonRunSettings
{
  std::string outputDirectory;
  std::string channel;
  std::string pluginPath;
  std::string liveUrl; ///< "" when the options name no Live address
  std::vector<PipelineScript> scripts;
};

/// What the last failed call into a script left: a one-line summary ("raised an
/// error: RuntimeError: ...", "called sys.exit(3)") and the traceback. Both empty
/// when no guarded call failed since the last take.
struct ScriptFailureText
{
  std::string summary;
  std::string traceback;
};

/// The driver's calls into Python: the methods of the registered side. Each
/// takes the GIL; without a side registered each does nothing (and says so).
class PythonSide
{
public:
  /// Whether a side is registered (the driver's helper module was imported).
  static bool connected();

  /// What the last failed call into a script left; forgets it.
  static ScriptFailureText takeFailure();

  /// What the script that just ran reported (canopy_catalyst.report), summed over
  /// ranks. Collective when `evaluate` (the script ran on every rank); otherwise
  /// forgets them and returns nothing. Names whose measure failed map to NaN.
  static std::map<std::string, double> takeMeasures(bool evaluate);

  /// Removes what the last run of the script wrote (its extracts failed on some rank).
  static void discardOutputs(const std::string& scriptPath);

  /// Handles `signalNumber` in Python on the main thread: a handler that raises
  /// StepTimeLimitExceeded in the script when interrupt_wanted() says so. False
  /// when not installed (the simulation handles that signal itself).
  static bool installInterrupt(int signalNumber);

  /// Plots the query history (QueryHistoryFile's CSV at `csvPath`) into `pngPath`: each
  /// query against time, the triggers' firings marked. Empty on success, else why not.
  static std::string plotHistory(const std::string& csvPath, const std::string& pngPath);
};

/// Asks Python to raise StepTimeLimitExceeded on the main thread, if the step
/// time limit still wants the call stopped then (Py_AddPendingCall: the fallback
/// when the signal's handler is not installed). Safe from any thread.
void interruptScriptByPendingCall();

/// `_canopy` connected to one run of the driver, from construction to destruction.
/// Starts Python if it is not running. The module stays in sys.modules for the
/// process; between runs its functions raise RuntimeError ("the in-situ driver is
/// closed"), but interrupt_wanted().
class CanopyModule
{
public:
  /// Python's reductions run on a duplicate of `communicator` (collective);
  /// agree_before_extracts on `agreement`, telling `watchdog` that this rank waits.
  CanopyModule(PythonRunSettings settings, MPI_Comm communicator,
               const CollectiveAgreement& agreement, StepWatchdog& watchdog);
  ~CanopyModule();
  CanopyModule(const CanopyModule&) = delete;
  CanopyModule& operator=(const CanopyModule&) = delete;

  /// Puts the helper modules on Python's path (`pipelinesDirectory` first, then
  /// the shipped pipelines) and imports them: canopy_catalyst, and _canopy_driver,
  /// which guards ParaView's calls into scripts and registers its side (connect).
  /// Empty on success, else what went wrong (Python's message printed above).
  std::string importHelperModules(const std::string& pipelinesDirectory);

  /// What `_canopy.query_values()` gives the scripts of this step (set before they run).
  static void setQueryValues(std::map<std::string, double> values);

private:
  std::unique_ptr<OwnCommunicator> Reductions;
};

} // namespace canopy
