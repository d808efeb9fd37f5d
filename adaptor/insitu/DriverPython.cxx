#include "vtkPython.h" // first, as Python requires

#include "DriverPython.h"

#include "CollectiveAgreement.h"
#include "RuntimePaths.h"
#include "StepWatchdog.h"

#include <vtkPythonInterpreter.h>
#include <vtkSmartPyObject.h>

#include <cstdlib>
#include <sstream>

namespace canopy
{
namespace
{

/// A Python expression for any text (paths, arguments): a bytes literal decoded
/// as UTF-8, so non-ASCII text arrives intact.
std::string pythonLiteral(const std::string& text)
{
  std::ostringstream out;
  out << "b\"";
  for (unsigned char c : text)
  {
    if (c == '\\' || c == '"')
    {
      out << '\\' << c;
    }
    else if (c < 0x20 || c >= 0x7f)
    {
      static const char* hex = "0123456789abcdef";
      out << "\\x" << hex[c >> 4] << hex[c & 15];
    }
    else
    {
      out << c;
    }
  }
  out << "\".decode(\"utf-8\", \"surrogateescape\")";
  return out.str();
}

const CollectiveAgreement* connectedAgreement = nullptr;
StepWatchdog* connectedWatchdog = nullptr;

/// agree_before_extracts(outcome, needed, free) -> (any failed, needed in all, least free);
/// outcome: "" when the script succeeded on this rank, else its failure.
PyObject* agreeBeforeExtracts(PyObject*, PyObject* arguments)
{
  const char* outcome = "";
  double needed = 0.0;
  double available = 0.0;
  if (!PyArg_ParseTuple(arguments, "sdd", &outcome, &needed, &available))
  {
    return nullptr;
  }
  if (connectedAgreement == nullptr || connectedWatchdog == nullptr)
  {
    PyErr_SetString(PyExc_RuntimeError, "the in-situ driver is closed");
    return nullptr;
  }
  const bool failed = *outcome != '\0';
  connectedWatchdog->noteWaiting(failed ? outcome : "succeeded");
  const auto most = connectedAgreement->reduce({failed ? 1.0 : 0.0, -available}, MPI_MAX);
  const auto sum = connectedAgreement->reduce({needed}, MPI_SUM);
  return Py_BuildValue("(Odd)", most[0] != 0.0 ? Py_True : Py_False, sum[0], -most[1]);
}

PyMethodDef agreeBeforeExtractsMethod = {
    "agree_before_extracts", &agreeBeforeExtracts, METH_VARARGS,
    "(outcome, needed, free) -> (any rank failed, needed by all ranks, least free)"};

std::string textOf(PyObject* object)
{
  if (object == nullptr || !PyUnicode_Check(object))
  {
    return {};
  }
  Py_ssize_t size = 0;
  const char* text = PyUnicode_AsUTF8AndSize(object, &size);
  if (text == nullptr)
  {
    PyErr_Clear();
    return {};
  }
  return std::string(text, static_cast<std::size_t>(size));
}

} // namespace

void exportScriptEnvironment(const std::string& outputDirectory, const std::string& channel,
                             const std::string& liveUrl)
{
  if (!liveUrl.empty())
  {
    setenv("CANOPY_LIVE", liveUrl.c_str(), 1);
  }
  setenv("CANOPY_OUTPUT_DIRECTORY", outputDirectory.c_str(), 1);
  setenv("CANOPY_CHANNEL", channel.c_str(), 1);
  setenv("CANOPY_PLUGIN", pluginPath().c_str(), 0);
}

std::string startDriverPython(const std::string& pipelinesDirectory,
                              const std::vector<PipelineScript>& scripts)
{
  vtkPythonInterpreter::Initialize();
  // Canopy's helper modules ship with it; a CANOPY_PIPELINES_DIR folder of the
  // user's scripts comes first on the path (its own helper copies would win),
  // but needs none.
  const std::string shipped = shippedPipelinesDirectory();
  vtkPythonInterpreter::PrependPythonPath(shipped.c_str());
  if (pipelinesDirectory != shipped)
  {
    vtkPythonInterpreter::PrependPythonPath(pipelinesDirectory.c_str());
  }
  std::ostringstream code;
  code << "import canopy_catalyst\n"
       << "import _canopy_driver\n"
       << "_canopy_driver.guard_catalyst_calls()\n";
  for (const auto& script : scripts)
  {
    code << "canopy_catalyst._register_arguments(" << pythonLiteral(script.path) << ", [";
    for (const auto& argument : script.arguments)
    {
      code << pythonLiteral(argument) << ", ";
    }
    code << "])\n";
  }
  if (vtkPythonInterpreter::RunSimpleString(code.str().c_str()) != 0)
  {
    return "cannot import Canopy's helper modules from '" + pipelinesDirectory +
           "' (set CANOPY_PIPELINES_DIR)";
  }
  return {};
}

ScriptFailureText takeScriptFailure()
{
  vtkPythonScopeGilEnsurer gil;
  ScriptFailureText failure;
  vtkSmartPyObject module(PyImport_ImportModule("_canopy_driver"));
  vtkSmartPyObject taken(module ? PyObject_CallMethod(module, "take_failure", nullptr) : nullptr);
  if (!taken)
  {
    PyErr_Clear();
    return failure;
  }
  if (PyTuple_Check(taken) && PyTuple_Size(taken) == 2)
  {
    failure.summary = textOf(PyTuple_GetItem(taken, 0));
    failure.traceback = textOf(PyTuple_GetItem(taken, 1));
  }
  return failure;
}

std::map<std::string, double> takeScriptMeasures(bool evaluate)
{
  vtkPythonScopeGilEnsurer gil;
  std::map<std::string, double> measures;
  vtkSmartPyObject module(PyImport_ImportModule("_canopy_driver"));
  vtkSmartPyObject taken(
      module ? PyObject_CallMethod(module, "take_measures", "O", evaluate ? Py_True : Py_False)
             : nullptr);
  if (!taken || !PyDict_Check(taken))
  {
    PyErr_Clear();
    return measures;
  }
  PyObject* name = nullptr;
  PyObject* value = nullptr;
  Py_ssize_t position = 0;
  while (PyDict_Next(taken, &position, &name, &value))
  {
    const double number = PyFloat_AsDouble(value);
    if (PyErr_Occurred())
    {
      PyErr_Clear();
      continue;
    }
    measures[textOf(name)] = number;
  }
  return measures;
}

void connectAgreement(const CollectiveAgreement* agreement, StepWatchdog* watchdog)
{
  connectedAgreement = agreement;
  connectedWatchdog = watchdog;
  if (agreement == nullptr)
  {
    return;
  }
  vtkPythonScopeGilEnsurer gil;
  vtkSmartPyObject module(PyImport_ImportModule("_canopy_driver"));
  vtkSmartPyObject function(PyCFunction_New(&agreeBeforeExtractsMethod, nullptr));
  if (!module || !function ||
      PyObject_SetAttrString(module, "agree_before_extracts", function) != 0)
  {
    PyErr_Print();
  }
}

void discardStepOutputs(const std::string& scriptPath)
{
  vtkPythonScopeGilEnsurer gil;
  vtkSmartPyObject module(PyImport_ImportModule("_canopy_driver"));
  vtkSmartPyObject done(
      module ? PyObject_CallMethod(module, "discard_outputs", "s", scriptPath.c_str()) : nullptr);
  if (!done)
  {
    PyErr_Print(); // shows why; the step is reported failed anyway
  }
}

} // namespace canopy
