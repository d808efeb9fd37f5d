// One Catalyst pipeline script (ParaView 5.9+ format) driven through ParaView
// 5.11's vtkCPPythonScriptV2Helper. Canopy drives the helper itself instead of
// through vtkCPPythonScriptV2Pipeline so that it can tell "not due at this step"
// from "failed", and ask each script separately which fields it needs. Every
// call into the script's Python is watched by the step time limit.
#pragma once

#include "CollectiveAgreement.h"

#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include <cstdint>
#include <string>
#include <vector>

class vtkCPDataDescription;
class vtkCPPythonScriptV2Helper;
class vtkDataObject;
class vtkSMProxy;

namespace canopy
{

class StepWatchdog;

class CatalystScript
{
public:
  /// Registers the script with Python (no script code runs yet). Throws
  /// std::runtime_error when Catalyst cannot load it.
  CatalystScript(std::string path, const std::string& channel, StepWatchdog& watchdog);
  ~CatalystScript();
  CatalystScript(const CatalystScript&) = delete;
  CatalystScript& operator=(const CatalystScript&) = delete;

  /// Whether the script runs at this step. Before its first run the script has
  /// not been imported (ParaView imports V2 scripts with data present), so it is
  /// due, with every field. A disabled script is never due. On Failed, `error`
  /// says why.
  ScriptState request(std::int64_t step, double time, std::string& error);

  /// Fields the script asked for at the last request: all, or the ones named.
  bool needsAllFields() const;
  bool needsField(const std::string& name) const;
  /// How many fields the script named (with needsField, tells whether it named
  /// some the forest does not have).
  unsigned int numberOfNeededFields() const;

  bool imported() const { return Imported; }
  /// Seconds the next call may take beyond the step time limit: the step that
  /// imports the script (ParaView loads its modules and creates render windows
  /// on the first import and run).
  double extraSeconds() const;
  /// Imports the script with `grid` present and runs its catalyst_initialize.
  bool import(vtkDataObject* grid, std::string& error);
  /// Right after import: asks the script itself whether it is due at this step.
  ScriptState requestAfterImport(std::string& error);
  /// Runs the script on `grid` (catalyst_execute, then its extractors). Fails
  /// also when VTK or ParaView log an error or warning meanwhile (writers say
  /// nothing else), and when the extracts would not fit on the disk (checked,
  /// over all ranks, before any is written).
  bool run(vtkDataObject* grid, std::string& error);
  /// After a run that failed on some rank: removes the files that run wrote
  /// (the step's extracts of this script), on every rank.
  void discardOutputs();

  /// Never runs again, nor is finalized (used when its import failed on some rank).
  void disable() { Disabled = true; }
  bool disabled() const { return Disabled; }

  /// Runs the script's catalyst_finalize (if it was imported and is not disabled);
  /// false, with `error` set, when it failed.
  bool finalize(std::string& error);

  /// After import: the Catalyst Live address the script's options ask for
  /// (options.EnableCatalystLive, CatalystLiveURL), "" for none. Canopy runs Live
  /// itself (LiveConnection.h), so ParaView's own Live is turned off in the script;
  /// the script is still due at the steps of its options.CatalystLiveTrigger, as
  /// in ParaView (without an extractor, those are the only steps it runs at).
  const std::string& liveUrl() const { return LiveUrl; }

  /// The Python traceback of the last failure (empty if it left none).
  const std::string& lastTraceback() const { return LastTraceback; }

  const std::string& path() const { return Path; }

private:
  /// Runs `body` (a call into the script's Python) under the step time limit:
  /// false when it failed or ran past the limit (`exceeded`).
  template <typename Call>
  bool watched(const char* call, bool& exceeded, Call&& body);
  /// "step 4": for messages and the watchdog.
  std::string when() const;
  /// Why the call failed: the Python failure's summary (its traceback is kept),
  /// or that it ran past the time limit (also when it caught the interruption).
  std::string failure(bool exceeded);
  /// Reads the script's Live settings into LiveUrl and LiveTrigger and turns
  /// ParaView's Live off.
  void takeOverLive();
  /// Whether the script asked for Live and its Live trigger fires at the step of
  /// the last request.
  bool liveTriggered() const;

  std::string Path;
  std::string Channel;
  StepWatchdog& Watchdog;
  std::string LastTraceback;
  vtkNew<vtkCPPythonScriptV2Helper> Helper;
  vtkNew<vtkCPDataDescription> Description;
  std::string LiveUrl;
  vtkSmartPointer<vtkSMProxy> LiveTrigger; ///< options.CatalystLiveTrigger, with Live on
  bool Imported = false;
  bool FirstRun = false; ///< imported at this step, not run yet
  bool Disabled = false;
};

} // namespace canopy
