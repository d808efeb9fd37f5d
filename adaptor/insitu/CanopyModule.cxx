#include "vtkPython.h" // first, as Python requires

#include "CanopyModule.h"

#include "CollectiveAgreement.h"
#include "OwnCommunicator.h"
#include "RuntimePaths.h"
#include "StepWatchdog.h"

#include <vtkPythonInterpreter.h>
#include <vtkSmartPyObject.h>

#include <cstdarg>
#include <filesystem>
#include <stdexcept>

namespace canopy
{
namespace
{

/// One run of the driver, as the module's functions see it.
struct Run
{
  PythonRunSettings settings;
  MPI_Comm reductions;
  const CollectiveAgreement* agreement;
  StepWatchdog* watchdog;
  std::map<std::string, double> queryValues; ///< the step's (setQueryValues)
};

// Python's objects live as long as the process's interpreter: created once,
// never freed (the module stays in sys.modules).
std::unique_ptr<Run> openRun;
PyObject* module = nullptr;
PyObject* side = nullptr; ///< the registered Python side (a new reference)
PyObject* stepTimeLimitExceeded = nullptr;
PyTypeObject* runSettingsType = nullptr;

/// The methods connect() requires of a side: what PythonSide calls.
const char* const sideMethods[] = {"take_failure", "take_measures", "discard_outputs",
                                   "install_interrupt", "plot_history"};

/// Text for Python, as os.environ decodes it: UTF-8, undecodable bytes kept as
/// surrogates (paths and arguments arrive intact whatever their bytes).
PyObject* toPython(const std::string& text)
{
  return PyUnicode_DecodeUTF8(text.data(), static_cast<Py_ssize_t>(text.size()), "surrogateescape");
}

/// The reverse of toPython ("" for anything but a str); what even that cannot
/// encode (a lone surrogate of Python's own) as a backslash escape, never lost.
std::string fromPython(PyObject* object)
{
  if (object == nullptr || !PyUnicode_Check(object))
  {
    return {};
  }
  vtkSmartPyObject bytes(PyUnicode_AsEncodedString(object, "utf-8", "surrogateescape"));
  if (!bytes)
  {
    PyErr_Clear();
    bytes.TakeReference(PyUnicode_AsEncodedString(object, "utf-8", "backslashreplace"));
  }
  if (!bytes)
  {
    PyErr_Clear();
    return {};
  }
  return std::string(PyBytes_AS_STRING(bytes.GetPointer()),
                     static_cast<std::size_t>(PyBytes_GET_SIZE(bytes.GetPointer())));
}

/// A script's path as the registry keys it: absolute and normal, as Python's
/// os.path.abspath makes it (the driver and ParaView may spell it differently).
std::string normalPath(const std::string& path)
{
  std::error_code error;
  auto normal = std::filesystem::absolute(path, error).lexically_normal();
  if (error)
  {
    return path;
  }
  if (!normal.has_filename() && normal.has_parent_path())
  {
    normal = normal.parent_path(); // "package/" names the same script as "package"
  }
  return normal.string();
}

Run* requireRun()
{
  if (openRun == nullptr)
  {
    PyErr_SetString(PyExc_RuntimeError, "the in-situ driver is closed");
  }
  return openRun.get();
}

PyObject* runSettings(PyObject*, PyObject*)
{
  const Run* run = requireRun();
  if (run == nullptr)
  {
    return nullptr;
  }
  const PythonRunSettings& settings = run->settings;
  vtkSmartPyObject result(PyStructSequence_New(runSettingsType));
  if (!result)
  {
    return nullptr;
  }
  const std::string* fields[] = {&settings.outputDirectory, &settings.channel, &settings.pluginPath,
                                 &settings.liveUrl};
  for (Py_ssize_t i = 0; i < 4; ++i)
  {
    PyObject* text = toPython(*fields[i]);
    if (text == nullptr)
    {
      return nullptr;
    }
    PyStructSequence_SetItem(result, i, text); // steals the reference
  }
  return result.ReleaseReference();
}

PyObject* scriptArguments(PyObject*, PyObject* arguments)
{
  PyObject* pathObject = nullptr;
  if (!PyArg_ParseTuple(arguments, "U:script_arguments", &pathObject))
  {
    return nullptr;
  }
  const Run* run = requireRun();
  if (run == nullptr)
  {
    return nullptr;
  }
  const std::string path = normalPath(fromPython(pathObject));
  vtkSmartPyObject list(PyList_New(0));
  for (const auto& script : run->settings.scripts)
  {
    if (normalPath(script.path) != path)
    {
      continue;
    }
    for (const auto& argument : script.arguments)
    {
      vtkSmartPyObject text(toPython(argument));
      if (!text || PyList_Append(list, text) != 0)
      {
        return nullptr;
      }
    }
    break;
  }
  return list.ReleaseReference();
}

PyObject* queryValues(PyObject*, PyObject*)
{
  const Run* run = requireRun();
  if (run == nullptr)
  {
    return nullptr;
  }
  vtkSmartPyObject values(PyDict_New());
  for (const auto& [text, value] : run->queryValues)
  {
    vtkSmartPyObject key(toPython(text));
    vtkSmartPyObject number(PyFloat_FromDouble(value));
    if (!key || !number || PyDict_SetItem(values, key, number) != 0)
    {
      return nullptr;
    }
  }
  return values.ReleaseReference();
}

PyObject* reduceOverRanks(PyObject*, PyObject* arguments)
{
  PyObject* values = nullptr;
  const char* operationName = "";
  if (!PyArg_ParseTuple(arguments, "Os:reduce", &values, &operationName))
  {
    return nullptr;
  }
  const std::string name = operationName;
  const MPI_Op operation = name == "min"   ? MPI_MIN
                           : name == "max" ? MPI_MAX
                           : name == "sum" ? MPI_SUM
                                           : MPI_OP_NULL;
  if (operation == MPI_OP_NULL)
  {
    PyErr_Format(PyExc_ValueError, "reduce: operation %R: expected 'min', 'max' or 'sum'",
                 PyTuple_GET_ITEM(arguments, 1));
    return nullptr;
  }
  const Run* run = requireRun();
  if (run == nullptr)
  {
    return nullptr;
  }
  vtkSmartPyObject sequence(PySequence_Fast(values, "reduce: values must be a sequence"));
  if (!sequence)
  {
    return nullptr;
  }
  const Py_ssize_t count = PySequence_Fast_GET_SIZE(sequence.GetPointer());
  std::vector<double> local(static_cast<std::size_t>(count));
  for (Py_ssize_t i = 0; i < count; ++i)
  {
    local[i] = PyFloat_AsDouble(PySequence_Fast_GET_ITEM(sequence.GetPointer(), i));
    if (local[i] == -1.0 && PyErr_Occurred())
    {
      return nullptr;
    }
  }
  std::vector<double> total(local.size());
  MPI_Allreduce(local.data(), total.data(), static_cast<int>(count), MPI_DOUBLE, operation,
                run->reductions);
  vtkSmartPyObject list(PyList_New(count));
  for (Py_ssize_t i = 0; list && i < count; ++i)
  {
    PyList_SET_ITEM(list.GetPointer(), i, PyFloat_FromDouble(total[i]));
  }
  return list.ReleaseReference();
}

PyObject* agreeBeforeExtracts(PyObject*, PyObject* arguments)
{
  PyObject* outcomeObject = nullptr;
  double needed = 0.0;
  double available = 0.0;
  if (!PyArg_ParseTuple(arguments, "Udd:agree_before_extracts", &outcomeObject, &needed,
                        &available))
  {
    return nullptr;
  }
  const Run* run = requireRun();
  if (run == nullptr)
  {
    return nullptr;
  }
  // Any text (a failure's message may hold what UTF-8 cannot encode): a rank
  // that raised here instead would leave the others waiting in the agreement.
  const std::string outcome = fromPython(outcomeObject);
  const bool failed = !outcome.empty();
  run->watchdog->noteWaiting(failed ? outcome : "succeeded");
  const auto most = run->agreement->reduce({failed ? 1.0 : 0.0, -available}, MPI_MAX);
  const auto sum = run->agreement->reduce({needed}, MPI_SUM);
  return Py_BuildValue("(Odd)", most[0] != 0.0 ? Py_True : Py_False, sum[0], -most[1]);
}

PyObject* interruptWanted(PyObject*, PyObject*)
{
  const std::string message = StepWatchdog::takeInterrupt();
  if (message.empty())
  {
    Py_RETURN_NONE;
  }
  return toPython(message);
}

PyObject* connectSide(PyObject*, PyObject* arguments)
{
  PyObject* candidate = nullptr;
  if (!PyArg_ParseTuple(arguments, "O:connect", &candidate))
  {
    return nullptr;
  }
  for (const char* method : sideMethods)
  {
    vtkSmartPyObject attribute(PyObject_GetAttrString(candidate, method));
    if (!attribute || !PyCallable_Check(attribute))
    {
      PyErr_Clear();
      PyErr_Format(PyExc_TypeError, "connect: the side has no method %s()", method);
      return nullptr;
    }
  }
  Py_INCREF(candidate);
  Py_XSETREF(side, candidate);
  Py_RETURN_NONE;
}

PyMethodDef methods[] = {
    {"run_settings", &runSettings, METH_NOARGS,
     "run_settings() -> RunSettings(output_directory, channel, plugin, live): the run's "
     "InSituOptions ('' for live: none given)."},
    {"script_arguments", &scriptArguments, METH_VARARGS,
     "script_arguments(path) -> [str]: the arguments the simulation gave the script at path "
     "([] if none)."},
    {"query_values", &queryValues, METH_NOARGS,
     "query_values() -> {str: float}: the step's queries and InSituOptions::queries by their "
     "text (docs/queries.md), the same on every rank; {} when none ran this step."},
    {"reduce", &reduceOverRanks, METH_VARARGS,
     "reduce(values, operation) -> [float]: values reduced element-wise over the ranks with "
     "'min', 'max' or 'sum'. Collective: every rank calls it, with as many values."},
    {"agree_before_extracts", &agreeBeforeExtracts, METH_VARARGS,
     "agree_before_extracts(outcome, needed, free) -> (failed on any rank, needed summed over "
     "ranks, least free): outcome '' where the script succeeded, else its failure. Collective."},
    {"interrupt_wanted", &interruptWanted, METH_NOARGS,
     "interrupt_wanted() -> str or None: the step time limit's message when the running script "
     "call must stop."},
    {"connect", &connectSide, METH_VARARGS,
     "connect(side): registers the object the driver calls: take_failure(), "
     "take_measures(evaluate), discard_outputs(script_path), install_interrupt(signal_number), "
     "plot_history(csv_path, png_path)."},
    {nullptr, nullptr, 0, nullptr}};

PyModuleDef definition = {PyModuleDef_HEAD_INIT,
                          "_canopy",
                          "Canopy's in-situ driver as Python sees it (adaptor/insitu/"
                          "CanopyModule.h): the run's settings, the scripts' arguments, "
                          "reductions over ranks, the agreement before extracts, and the "
                          "object the driver calls (connect).",
                          -1,
                          methods,
                          nullptr,
                          nullptr,
                          nullptr,
                          nullptr};

PyStructSequence_Field runSettingsFields[] = {
    {"output_directory", "where the pipelines write (InSituOptions::outputDirectory)"},
    {"channel", "the channel the grid is published on (InSituOptions::channel)"},
    {"plugin", "the Canopy ParaView plugin to load (CANOPY_PLUGIN, else next to the library)"},
    {"live", "host:port of a Catalyst Live viewer (InSituOptions::liveUrl), '' for none"},
    {nullptr, nullptr}};

PyStructSequence_Desc runSettingsDescription = {
    "_canopy.RunSettings", "The in-situ driver's settings for its scripts.", runSettingsFields, 4};

/// Creates _canopy the first time, and (again) puts it in sys.modules. GIL held.
void install()
{
  if (module == nullptr)
  {
    vtkSmartPyObject created(PyModule_Create(&definition));
    runSettingsType = created ? PyStructSequence_NewType(&runSettingsDescription) : nullptr;
    stepTimeLimitExceeded =
        runSettingsType
            ? PyErr_NewExceptionWithDoc(
                  "_canopy.StepTimeLimitExceeded",
                  "Raised by the driver's watchdog where a script is when the step time limit "
                  "passes (InSituOptions::stepTimeLimitSeconds).",
                  PyExc_TimeoutError, nullptr)
            : nullptr;
    if (!stepTimeLimitExceeded ||
        PyModule_AddObjectRef(created, "RunSettings",
                              reinterpret_cast<PyObject*>(runSettingsType)) != 0 ||
        PyModule_AddObjectRef(created, "StepTimeLimitExceeded", stepTimeLimitExceeded) != 0)
    {
      PyErr_Print();
      throw std::runtime_error("cannot create Python's _canopy module");
    }
    module = created.ReleaseReference();
  }
  if (PyDict_SetItemString(PyImport_GetModuleDict(), "_canopy", module) != 0)
  {
    PyErr_Print();
    throw std::runtime_error("cannot put the _canopy module in sys.modules");
  }
}

/// A method of the registered side called with `arguments` (a format as
/// Py_BuildValue's), or null (and nothing raised) when it fails or no side is
/// registered; `print` shows why first. GIL held.
PyObject* callSide(const char* method, bool print, const char* format, ...)
{
  if (side == nullptr)
  {
    return nullptr;
  }
  vtkSmartPyObject function(PyObject_GetAttrString(side, method));
  va_list values;
  va_start(values, format);
  vtkSmartPyObject arguments(Py_VaBuildValue(format, values));
  va_end(values);
  PyObject* result = function && arguments ? PyObject_CallObject(function, arguments) : nullptr;
  if (result == nullptr && print)
  {
    PyErr_Print();
  }
  PyErr_Clear();
  return result;
}

int raisePendingInterrupt(void*)
{
  const std::string message = StepWatchdog::takeInterrupt();
  if (message.empty())
  {
    return 0;
  }
  PyErr_SetString(stepTimeLimitExceeded ? stepTimeLimitExceeded : PyExc_TimeoutError,
                  message.c_str());
  return -1; // raises the exception where the script is
}

} // namespace

bool PythonSide::connected()
{
  return side != nullptr;
}

ScriptFailureText PythonSide::takeFailure()
{
  vtkPythonScopeGilEnsurer gil;
  ScriptFailureText failure;
  vtkSmartPyObject taken(callSide("take_failure", false, "()"));
  if (taken && PyTuple_Check(taken) && PyTuple_Size(taken) == 2)
  {
    failure.summary = fromPython(PyTuple_GetItem(taken, 0));
    failure.traceback = fromPython(PyTuple_GetItem(taken, 1));
  }
  return failure;
}

std::map<std::string, double> PythonSide::takeMeasures(bool evaluate)
{
  vtkPythonScopeGilEnsurer gil;
  std::map<std::string, double> measures;
  vtkSmartPyObject taken(callSide("take_measures", false, "(O)", evaluate ? Py_True : Py_False));
  if (!taken || !PyDict_Check(taken))
  {
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
    measures[fromPython(name)] = number;
  }
  return measures;
}

void PythonSide::discardOutputs(const std::string& scriptPath)
{
  vtkPythonScopeGilEnsurer gil;
  vtkSmartPyObject path(toPython(scriptPath));
  // Printed: the step is reported failed anyway, this says why its files stay.
  vtkSmartPyObject done(callSide("discard_outputs", true, "(O)", path.GetPointer()));
}

bool PythonSide::installInterrupt(int signalNumber)
{
  vtkPythonScopeGilEnsurer gil;
  vtkSmartPyObject installed(callSide("install_interrupt", false, "(i)", signalNumber));
  return installed.GetPointer() == Py_True;
}

std::string PythonSide::plotHistory(const std::string& csvPath, const std::string& pngPath)
{
  vtkPythonScopeGilEnsurer gil;
  if (side == nullptr)
  {
    return "no Python side to plot the query history with";
  }
  vtkSmartPyObject csv(toPython(csvPath));
  vtkSmartPyObject png(toPython(pngPath));
  vtkSmartPyObject problem(
      callSide("plot_history", false, "(OO)", csv.GetPointer(), png.GetPointer()));
  if (!problem)
  {
    return "plotting the query history raised an error";
  }
  return fromPython(problem);
}

void interruptScriptByPendingCall()
{
  Py_AddPendingCall(&raisePendingInterrupt, nullptr);
}

CanopyModule::CanopyModule(PythonRunSettings settings, MPI_Comm communicator,
                           const CollectiveAgreement& agreement, StepWatchdog& watchdog)
{
  if (openRun != nullptr)
  {
    throw std::logic_error("_canopy is already connected to an open in-situ driver");
  }
  // Not the agreement's communicator: a rank whose script failed goes to an
  // agreement while the others may still be in the script's reductions, and
  // mismatched collectives on one communicator end the job (MPI_ERR_TRUNCATE)
  // instead of a wait the time limit bounds and explains
  // (insitu.fault.time_limit.error_on_one_rank_without_decorator).
  this->Reductions = std::make_unique<OwnCommunicator>(communicator);
  vtkPythonInterpreter::Initialize();
  {
    vtkPythonScopeGilEnsurer gil;
    install();
  }
  openRun = std::make_unique<Run>(
      Run{std::move(settings), this->Reductions->get(), &agreement, &watchdog, {}});
}

CanopyModule::~CanopyModule()
{
  openRun.reset();
}

void CanopyModule::setQueryValues(std::map<std::string, double> values)
{
  if (openRun != nullptr)
  {
    openRun->queryValues = std::move(values);
  }
}

std::string CanopyModule::importHelperModules(const std::string& pipelinesDirectory)
{
  // Canopy's helper modules ship with it; a CANOPY_PIPELINES_DIR folder of the
  // user's scripts comes first on the path (its own helper copies would win),
  // but needs none.
  const std::string shipped = shippedPipelinesDirectory();
  vtkPythonInterpreter::PrependPythonPath(shipped.c_str());
  if (pipelinesDirectory != shipped)
  {
    vtkPythonInterpreter::PrependPythonPath(pipelinesDirectory.c_str());
  }
  vtkPythonScopeGilEnsurer gil;
  for (const char* name : {"canopy_catalyst", "_canopy_driver"})
  {
    vtkSmartPyObject imported(PyImport_ImportModule(name));
    if (!imported)
    {
      PyErr_Print();
      return "cannot import Canopy's helper modules from '" + pipelinesDirectory +
             "' (set CANOPY_PIPELINES_DIR)";
    }
  }
  if (side == nullptr)
  {
    return "the helper module _canopy_driver from '" + pipelinesDirectory +
           "' did not connect to _canopy (a copy older than this Canopy?)";
  }
  return {};
}

} // namespace canopy
