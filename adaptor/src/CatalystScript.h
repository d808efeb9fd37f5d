// One Catalyst pipeline script (ParaView 5.9+ format) driven through ParaView
// 5.11's vtkCPPythonScriptV2Helper. Canopy drives the helper itself instead of
// through vtkCPPythonScriptV2Pipeline so that it can tell "not due at this step"
// from "failed", and ask each script separately which fields it needs.
#pragma once

#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include <cstdint>
#include <string>
#include <vector>

class vtkCPDataDescription;
class vtkCPPythonScriptV2Helper;
class vtkDataObject;

namespace canopy
{

class CatalystScript
{
public:
  /// Registers the script with Python (no script code runs yet). Throws
  /// std::runtime_error when Catalyst cannot load it.
  CatalystScript(std::string path, const std::string& channel);
  ~CatalystScript();
  CatalystScript(const CatalystScript&) = delete;
  CatalystScript& operator=(const CatalystScript&) = delete;

  enum class Request
  {
    NotDue,
    Due,
    Failed
  };

  /// Whether the script runs at this step. Before the first run the script has
  /// not been imported (ParaView imports V2 scripts with data present), so it is
  /// due, with every field. On Failed, `error` says why.
  Request request(std::int64_t step, double time, std::string& error);

  /// Fields the script asked for at the last request(): `all` or the listed names.
  bool needsAllFields() const;
  std::vector<std::string> neededFields() const;

  enum class Outcome
  {
    Ran,
    NotDue, ///< only on the first run: imported, then found not due at this step
    Failed
  };

  /// Imports the script if needed and runs it on `grid`. Never throws.
  Outcome execute(vtkDataObject* grid, std::string& error);

  /// Runs the script's catalyst_finalize (if it was imported).
  void finalize();

  const std::string& path() const { return Path; }

private:
  std::string Path;
  std::string Channel;
  vtkNew<vtkCPPythonScriptV2Helper> Helper;
  vtkNew<vtkCPDataDescription> Description;
  bool Imported = false;
  bool ImportFailed = false;
};

} // namespace canopy
