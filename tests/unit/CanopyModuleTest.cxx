// _canopy, the door between the in-situ driver and Python (adaptor/insitu/
// CanopyModule.h): each of its functions called from Python as the helper
// modules call it, each of the driver's calls into Python reaching the side
// registered with connect(), and the shipped helper modules connecting their
// side. Runs on any number of MPI ranks (ctest: 2), every rank through every
// test: the reductions and the agreement are checked against sums over ranks.
#include "vtkPython.h" // first, as Python requires

#include "CanopyModule.h"
#include "CollectiveAgreement.h"
#include "JobOutput.h"
#include "RuntimePaths.h"
#include "StepWatchdog.h"

#include <gtest/gtest.h>
#include <vtkPythonInterpreter.h>
#include <vtkSmartPyObject.h>

#include <unistd.h>

#include <cstdlib>
#include <memory>
#include <string>

namespace
{

int rank()
{
  int value = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &value);
  return value;
}

int ranks()
{
  int value = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &value);
  return value;
}

std::string number(double value)
{
  vtkPythonScopeGilEnsurer gil;
  vtkSmartPyObject text(PyObject_Repr(vtkSmartPyObject(PyFloat_FromDouble(value))));
  return PyUnicode_AsUTF8(text);
}

/// "<ExceptionType>: <message>" for the Python exception being raised; clears it.
std::string takeException()
{
  PyObject* type = nullptr;
  PyObject* value = nullptr;
  PyObject* traceback = nullptr;
  PyErr_Fetch(&type, &value, &traceback);
  PyErr_NormalizeException(&type, &value, &traceback);
  vtkSmartPyObject message(value ? PyObject_Str(value) : nullptr);
  std::string text = std::string(reinterpret_cast<PyTypeObject*>(type)->tp_name) + ": " +
                     (message ? PyUnicode_AsUTF8(message) : "");
  Py_XDECREF(type);
  Py_XDECREF(value);
  Py_XDECREF(traceback);
  return text;
}

/// repr() of a Python expression's value in __main__, or what it raised.
std::string evaluate(const std::string& expression)
{
  vtkPythonScopeGilEnsurer gil;
  PyObject* globals = PyModule_GetDict(PyImport_AddModule("__main__")); // borrowed
  vtkSmartPyObject result(PyRun_String(expression.c_str(), Py_eval_input, globals, globals));
  if (!result)
  {
    return takeException();
  }
  vtkSmartPyObject text(PyObject_Repr(result));
  return PyUnicode_AsUTF8(text);
}

/// Runs Python statements in __main__; "" or what they raised.
std::string run(const std::string& code)
{
  vtkPythonScopeGilEnsurer gil;
  PyObject* globals = PyModule_GetDict(PyImport_AddModule("__main__")); // borrowed
  vtkSmartPyObject result(PyRun_String(code.c_str(), Py_file_input, globals, globals));
  return result ? std::string() : takeException();
}

bool pythonErrorSet()
{
  vtkPythonScopeGilEnsurer gil;
  return PyErr_Occurred() != nullptr;
}

/// The driver's side of the door as InSitu sets it up: an agreement, a watchdog
/// (no limit), and _canopy connected to a run with these settings.
class CanopyModuleTest : public ::testing::Test
{
protected:
  void SetUp() override
  {
    canopy::PythonRunSettings settings;
    settings.outputDirectory = "/tmp/out dir/\xc3\xa9t\xc3\xa9"; // "été": UTF-8 kept
    settings.channel = "mesh";
    settings.pluginPath = "/opt/canopy/CanopyPlugin.so";
    settings.liveUrl = LiveUrl;
    settings.scripts = {{"/pipelines/surface_image.py", {"--frequency=5", "--color-by=density"}},
                        {"relative/own.py", {"--name=\xff"}}, // not UTF-8: kept as a surrogate
                        {"/pipelines/package/", {"--start=2"}},
                        {"/pipelines/no_arguments.py", {}}};
    Agreement = std::make_unique<canopy::CollectiveAgreement>(MPI_COMM_WORLD, Output, 0.0, 0.0);
    Watchdog = std::make_unique<canopy::StepWatchdog>(0.0, rank(), MPI_COMM_WORLD, Output);
    Module = std::make_unique<canopy::CanopyModule>(std::move(settings), MPI_COMM_WORLD, *Agreement,
                                                    *Watchdog);
    ASSERT_EQ(run("import _canopy"), "");
  }
  void TearDown() override
  {
    Module.reset();
    Watchdog.reset();
    Agreement.reset();
  }

  std::string LiveUrl;
  canopy::JobOutput Output;
  std::unique_ptr<canopy::CollectiveAgreement> Agreement;
  std::unique_ptr<canopy::StepWatchdog> Watchdog;
  std::unique_ptr<canopy::CanopyModule> Module;
};

TEST_F(CanopyModuleTest, RunSettingsAreTheOptions)
{
  EXPECT_EQ(evaluate("tuple(_canopy.run_settings())"),
            "('/tmp/out dir/été', 'mesh', '/opt/canopy/CanopyPlugin.so', '')");
  EXPECT_EQ(evaluate("_canopy.run_settings().output_directory"), "'/tmp/out dir/été'");
  EXPECT_EQ(evaluate("_canopy.run_settings().channel"), "'mesh'");
  EXPECT_EQ(evaluate("_canopy.run_settings().plugin"), "'/opt/canopy/CanopyPlugin.so'");
  EXPECT_EQ(evaluate("type(_canopy.run_settings()) is _canopy.RunSettings"), "True");
}

class CanopyModuleLiveTest : public CanopyModuleTest
{
protected:
  void SetUp() override
  {
    LiveUrl = "localhost:22222";
    CanopyModuleTest::SetUp();
  }
};

TEST_F(CanopyModuleLiveTest, LiveAddressGiven)
{
  EXPECT_EQ(evaluate("_canopy.run_settings().live"), "'localhost:22222'");
}

TEST_F(CanopyModuleTest, ScriptArgumentsByPath)
{
  EXPECT_EQ(evaluate("_canopy.script_arguments('/pipelines/surface_image.py')"),
            "['--frequency=5', '--color-by=density']");
  // The same file spelled otherwise (ParaView and the driver need not agree).
  EXPECT_EQ(evaluate("_canopy.script_arguments('/pipelines/./x/../surface_image.py')"),
            "['--frequency=5', '--color-by=density']");
  EXPECT_EQ(evaluate("_canopy.script_arguments('//pipelines//surface_image.py')"),
            "['--frequency=5', '--color-by=density']");
  // A relative path counts from the working directory, on both sides.
  EXPECT_EQ(evaluate("_canopy.script_arguments('relative/own.py') == ['--name=\\udcff']"), "True");
  EXPECT_EQ(evaluate("_canopy.script_arguments(__import__('os').path.abspath('relative/own.py'))"
                     " == ['--name=\\udcff']"),
            "True");
  // A package directory, with or without its trailing slash.
  EXPECT_EQ(evaluate("_canopy.script_arguments('/pipelines/package')"), "['--start=2']");
  EXPECT_EQ(evaluate("_canopy.script_arguments('/pipelines/package/')"), "['--start=2']");
  EXPECT_EQ(evaluate("_canopy.script_arguments('/pipelines/no_arguments.py')"), "[]");
  EXPECT_EQ(evaluate("_canopy.script_arguments('/elsewhere/surface_image.py')"), "[]");
  EXPECT_EQ(evaluate("_canopy.script_arguments(3)"),
            "TypeError: script_arguments() argument 1 must be str, not int");
}

TEST_F(CanopyModuleTest, ReduceOverEveryRank)
{
  const int r = rank();
  const int n = ranks();
  const std::string values = "[" + std::to_string(r) + ", 1.5, " + std::to_string(-r) + "]";
  const double sum = n * (n - 1) / 2.0;
  EXPECT_EQ(evaluate("_canopy.reduce(" + values + ", 'sum')"),
            "[" + number(sum) + ", " + number(1.5 * n) + ", " + number(0.0 - sum) + "]");
  EXPECT_EQ(evaluate("_canopy.reduce(" + values + ", 'min')"), "[0.0, 1.5, " + number(1 - n) + "]");
  EXPECT_EQ(evaluate("_canopy.reduce(" + values + ", 'max')"), "[" + number(n - 1) + ", 1.5, 0.0]");
  EXPECT_EQ(evaluate("_canopy.reduce((2, True), 'sum')"),
            "[" + number(2.0 * n) + ", " + number(n) + "]");
  EXPECT_EQ(evaluate("_canopy.reduce([], 'sum')"), "[]");
  // Refused before any rank waits: the same mistake on every rank.
  EXPECT_EQ(evaluate("_canopy.reduce([1.0], 'MAX_OP')"),
            "ValueError: reduce: operation 'MAX_OP': expected 'min', 'max' or 'sum'");
  EXPECT_EQ(evaluate("_canopy.reduce(['a'], 'sum')"), "TypeError: must be real number, not str");
  EXPECT_EQ(evaluate("_canopy.reduce(1.0, 'sum')"), "TypeError: reduce: values must be a sequence");
}

TEST_F(CanopyModuleTest, AgreementBeforeExtracts)
{
  const int r = rank();
  const int n = ranks();
  const std::string needed = std::to_string(r + 1);
  const std::string available = std::to_string(100 - r);
  EXPECT_EQ(evaluate("_canopy.agree_before_extracts('', " + needed + ", " + available + ")"),
            "(False, " + number(n * (n + 1) / 2.0) + ", " + number(101 - n) + ")");
  // The last rank's script failed (its message not even valid UTF-8): every rank learns it.
  const std::string outcome = r == n - 1 ? "'raised an error: ValueError: \\udcff\\ud800'" : "''";
  EXPECT_EQ(evaluate("_canopy.agree_before_extracts(" + outcome + ", 0.0, 5.0)"),
            "(True, 0.0, 5.0)");
}

TEST_F(CanopyModuleTest, ClosedDriverRaises)
{
  Module.reset();
  EXPECT_EQ(evaluate("_canopy.run_settings()"), "RuntimeError: the in-situ driver is closed");
  EXPECT_EQ(evaluate("_canopy.script_arguments('/pipelines/surface_image.py')"),
            "RuntimeError: the in-situ driver is closed");
  EXPECT_EQ(evaluate("_canopy.reduce([1.0], 'sum')"), "RuntimeError: the in-situ driver is closed");
  EXPECT_EQ(evaluate("_canopy.agree_before_extracts('', 0.0, 0.0)"),
            "RuntimeError: the in-situ driver is closed");
  // Nothing to interrupt: no watched call.
  EXPECT_EQ(evaluate("_canopy.interrupt_wanted()"), "None");
  EXPECT_EQ(evaluate("issubclass(_canopy.StepTimeLimitExceeded, TimeoutError)"), "True");
}

TEST_F(CanopyModuleTest, OneRunAtATime)
{
  canopy::PythonRunSettings settings;
  EXPECT_THROW(canopy::CanopyModule(settings, MPI_COMM_WORLD, *Agreement, *Watchdog),
               std::logic_error);
}

// The side tests run in this order: nothing registered, then a fake side, then
// the shipped _canopy_driver's (a side stays registered for the process).
TEST_F(CanopyModuleTest, WithoutSideTheDriverCallsNothing)
{
  ASSERT_FALSE(canopy::PythonSide::connected());
  const auto failure = canopy::PythonSide::takeFailure();
  EXPECT_EQ(failure.summary, "");
  EXPECT_EQ(failure.traceback, "");
  EXPECT_TRUE(canopy::PythonSide::takeMeasures(true).empty());
  EXPECT_FALSE(canopy::PythonSide::installInterrupt(SIGURG));
  EXPECT_FALSE(pythonErrorSet());
}

TEST_F(CanopyModuleTest, ConnectRefusesAnIncompleteSide)
{
  ASSERT_EQ(run("class Incomplete:\n"
                "    def take_failure(self): return None\n"
                "    def take_measures(self, evaluate): return {}\n"
                "    discard_outputs = None\n"
                "    def install_interrupt(self, number): return False\n"
                "    def plot_history(self, csv, png): return ''\n"),
            "");
  EXPECT_EQ(run("_canopy.connect(Incomplete())"),
            "TypeError: connect: the side has no method discard_outputs()");
  EXPECT_FALSE(canopy::PythonSide::connected());
}

TEST_F(CanopyModuleTest, DriverCallsReachTheRegisteredSide)
{
  ASSERT_EQ(run("class FakeSide:\n"
                "    def __init__(self): self.calls = []\n"
                "    def take_failure(self):\n"
                "        self.calls.append('take_failure')\n"
                "        return ('raised an error: ValueError: \\u00e9', 'Traceback (...)\\n')\n"
                "    def take_measures(self, evaluate):\n"
                "        self.calls.append(('take_measures', evaluate))\n"
                "        return {'quads': 12.5, 'cells': 3, 'broken': 'x'} if evaluate else {}\n"
                "    def discard_outputs(self, path):\n"
                "        self.calls.append(('discard_outputs', path))\n"
                "    def install_interrupt(self, number):\n"
                "        self.calls.append(('install_interrupt', number))\n"
                "        return number == 23\n"
                "    def plot_history(self, csv, png):\n"
                "        self.calls.append(('plot_history', csv, png))\n"
                "        return 'no rows'\n"
                "side = FakeSide()\n"
                "_canopy.connect(side)\n"),
            "");
  ASSERT_TRUE(canopy::PythonSide::connected());

  const auto failure = canopy::PythonSide::takeFailure();
  EXPECT_EQ(failure.summary, "raised an error: ValueError: \xc3\xa9");
  EXPECT_EQ(failure.traceback, "Traceback (...)\n");
  const auto measures = canopy::PythonSide::takeMeasures(true);
  EXPECT_EQ(measures, (std::map<std::string, double>{{"quads", 12.5}, {"cells", 3.0}}));
  EXPECT_TRUE(canopy::PythonSide::takeMeasures(false).empty());
  canopy::PythonSide::discardOutputs("/out/\xc3\xa9/script.py");
  EXPECT_TRUE(canopy::PythonSide::installInterrupt(23));
  EXPECT_FALSE(canopy::PythonSide::installInterrupt(24));
  EXPECT_EQ(canopy::PythonSide::plotHistory("/out/q.csv", "/out/q.png"), "no rows");
  EXPECT_EQ(evaluate("side.calls"),
            "['take_failure', ('take_measures', True), ('take_measures', False), "
            "('discard_outputs', '/out/é/script.py'), ('install_interrupt', 23), "
            "('install_interrupt', 24), ('plot_history', '/out/q.csv', '/out/q.png')]");

  // A side that raises: nothing taken, nothing left raised for the driver's caller.
  ASSERT_EQ(run("def broken(*arguments): raise RuntimeError('broken')\n"
                "side.take_failure = side.take_measures = broken\n"),
            "");
  EXPECT_EQ(canopy::PythonSide::takeFailure().summary, "");
  EXPECT_TRUE(canopy::PythonSide::takeMeasures(true).empty());
  EXPECT_FALSE(pythonErrorSet());
}

TEST_F(CanopyModuleTest, ShippedHelperModulesConnectTheirSide)
{
  // As the driver imports them (ParaView's Python modules load in this process).
  ASSERT_EQ(Module->importHelperModules(canopy::shippedPipelinesDirectory()), "");
  ASSERT_EQ(run("import _canopy_driver, canopy_catalyst"), "");
  // The side registered is _canopy_driver's: its measures go through the door.
  ASSERT_EQ(run("_canopy_driver.report_measure('ones', lambda: 1.0)"), "");
  EXPECT_EQ(canopy::PythonSide::takeMeasures(true),
            (std::map<std::string, double>{{"ones", static_cast<double>(ranks())}}));
  EXPECT_EQ(evaluate("_canopy_driver.StepTimeLimitExceeded is _canopy.StepTimeLimitExceeded"),
            "True");

  // canopy_catalyst: the driver's settings over the user's environment, under the
  // script's arguments (none here: no script is running); its reductions go
  // through the door.
  ASSERT_EQ(run("import os\n"
                "os.environ['CANOPY_OUTPUT_DIRECTORY'] = '/the/user/s'\n"
                "os.environ['CANOPY_FREQUENCY'] = '7'\n"
                "values = canopy_catalyst.settings(extra=1.5)\n"),
            "");
  EXPECT_EQ(evaluate("(values.output_directory, values.channel, values.frequency, values.live, "
                     "values.extra)"),
            "('/tmp/out dir/été', 'mesh', 7, '', 1.5)");
  EXPECT_EQ(evaluate("canopy_catalyst.plugin_path()"), "'/opt/canopy/CanopyPlugin.so'");
  EXPECT_EQ(evaluate("canopy_catalyst._reduce([1.0], 'SUM_OP')"), "[" + number(ranks()) + "]");
  EXPECT_EQ(
      evaluate("canopy_catalyst._any_rank(" + std::string(rank() == 0 ? "True" : "False") + ")"),
      "True");
  EXPECT_EQ(run("del os.environ['CANOPY_OUTPUT_DIRECTORY'], os.environ['CANOPY_FREQUENCY']"), "");
}

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  // Python running before the driver opens, as in a simulation that embeds it
  // (in-situ runs start it in the door: both ways are tested).
  vtkPythonInterpreter::Initialize();
  ::testing::InitGoogleTest(&argc, argv);
  if (rank() != 0)
  {
    // One report: rank 0's (every rank checks; a failure anywhere fails the run).
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int failed = RUN_ALL_TESTS();
  int anyFailed = failed;
  MPI_Allreduce(&failed, &anyFailed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return anyFailed;
}
