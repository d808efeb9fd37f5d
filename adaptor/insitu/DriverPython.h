// The in-situ driver's side of Python: the helper modules on the path, each
// script's arguments registered, ParaView's script calls guarded
// (pipelines/_canopy_driver.py), and what a failed call left behind.
#pragma once

#include "canopy/InSitu.h"

#include <map>
#include <string>
#include <vector>

namespace canopy
{

/// What scripts read from the environment: CANOPY_OUTPUT_DIRECTORY and
/// CANOPY_CHANNEL (their settings' defaults), CANOPY_PLUGIN (the plugin they
/// load; an existing value wins), CANOPY_LIVE (Catalyst Live's address, when set).
void exportScriptEnvironment(const std::string& outputDirectory, const std::string& channel,
                             const std::string& liveUrl);

/// Puts `pipelinesDirectory` on Python's path, imports the helper modules,
/// registers each script's arguments and guards ParaView's calls into scripts
/// (sys.exit() becomes an error). Empty on success, else what went wrong.
std::string startDriverPython(const std::string& pipelinesDirectory,
                              const std::vector<PipelineScript>& scripts);

/// What the last failed call into a script left: a one-line summary ("raised an
/// error: RuntimeError: ...", "called sys.exit(3)") and the traceback. Both are
/// empty when no guarded call failed since the last take. Forgets it.
struct ScriptFailureText
{
  std::string summary;
  std::string traceback;
};
ScriptFailureText takeScriptFailure();

/// What the script that just ran reported (canopy_catalyst.report), summed over
/// ranks. Collective when `evaluate` (the script ran on every rank); otherwise
/// forgets them and returns nothing. Names whose measure failed map to NaN.
std::map<std::string, double> takeScriptMeasures(bool evaluate);

class CollectiveAgreement;
class StepWatchdog;

/// Gives the Python side the ranks' agreement before a script's extracts are
/// written (_canopy_driver.agree_before_extracts), on Canopy's communicator:
/// ParaView's may still be busy on a rank whose script is stuck in a collective.
/// The watchdog learns that this rank waits there. nullptr disconnects it.
void connectAgreement(const CollectiveAgreement* agreement, StepWatchdog* watchdog);

/// Removes what the last run of the script wrote (pipelines/_canopy_driver.py).
void discardStepOutputs(const std::string& scriptPath);

} // namespace canopy
