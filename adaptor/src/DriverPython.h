// The in-situ driver's side of Python: the helper modules on the path, each
// script's arguments registered, ParaView's script calls guarded
// (pipelines/_canopy_driver.py), and what a failed call left behind.
#pragma once

#include "canopy/InSitu.h"

#include <string>
#include <vector>

namespace canopy
{

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

} // namespace canopy
