// StepRequests (adaptor/insitu/StepRequests.h), through its own header, on
// real MPI ranks with ParaView Catalyst started and real pipeline scripts
// (ParaView 5.9+ format) whose own RequestDataDescription decides, per rank and
// step, from a table this test writes into them: a script runs at a step only
// where it is due on every rank; a script due on some ranks only is skipped
// with a message naming the step and the script, in the returned failures on
// every rank and in rank 0's log; a script failing on one rank is skipped
// everywhere and the failure names the rank; before a script's first run it is
// due with every field. The fields the due scripts need against the tables.
#include "StepRequests.h"
#include "CapturedStderr.h"
#include "ChangingForest.h"
#include "CollectiveAgreement.h"
#include "FailureLog.h"
#include "JobOutput.h"
#include "StepWatchdog.h"

#include <canopy/HtgBuilder.h>

#include <gtest/gtest.h>
#include <mpi.h>
#include <vtkHyperTreeGrid.h>
#include <vtkSmartPointer.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace canopy::testing
{
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

constexpr std::int64_t lastStep = 8;

/// A pipeline script for the test: at each step, on each rank, whether it is
/// due (with `fields`, or every field when empty), or raises in its
/// RequestDataDescription.
struct ScriptTable
{
  std::string name;
  std::function<bool(int rank, std::int64_t step)> due;
  std::function<bool(int rank, std::int64_t step)> raises;
  std::vector<std::string> fields;
};

/// The script's text: its tables for every rank and step, written out.
std::string scriptText(const ScriptTable& table)
{
  auto steps = [&](const std::function<bool(int, std::int64_t)>& when)
  {
    std::string text = "{";
    for (int r = 0; r < ranks(); ++r)
    {
      text += std::to_string(r) + ": [";
      for (std::int64_t s = 0; s <= lastStep; ++s)
      {
        text += when(r, s) ? std::to_string(s) + ", " : "";
      }
      text += "], ";
    }
    return text + "}";
  };
  std::string fields = "[";
  for (const std::string& f : table.fields)
  {
    fields += "'" + f + "', ";
  }
  fields += "]";
  return "# script-version: 2\n"
         "from paraview import catalyst\n"
         "from paraview.modules.vtkRemotingCore import vtkProcessModule\n"
         "options = catalyst.Options()\n"
         "rank = vtkProcessModule.GetProcessModule().GetPartitionId()\n"
         "DUE = " +
         steps(table.due) + "\nRAISES = " + steps(table.raises) + "\nFIELDS = " + fields +
         "\n"
         "def RequestDataDescription(description):\n"
         "    step = description.GetTimeStep()\n"
         "    if step in RAISES[rank]:\n"
         "        raise RuntimeError('failing on purpose at step %d' % step)\n"
         "    if step in DUE[rank]:\n"
         "        channel = description.GetInputDescription(0)\n"
         "        channel.GenerateMeshOn()\n"
         "        if FIELDS:\n"
         "            for name in FIELDS:\n"
         "                channel.AddField(name, 1)\n" // vtkDataObject.CELL
         "        else:\n"
         "            channel.AllFieldsOn()\n"
         "def catalyst_execute(info):\n"
         "    pass\n";
}

bool never(int, std::int64_t)
{
  return false;
}

/// The driver's pieces a request needs (no time limit), the scripts written
/// by rank 0 into a folder of the build tree, and a grid to import them with.
class StepRequestsTest : public ::testing::Test
{
protected:
  void SetUp() override
  {
    Tables = {
        // Due on every rank at every step.
        {"always", [](int, std::int64_t) { return true; }, never, {"value"}},
        // Due on rank 0 at every step, elsewhere only at even steps.
        {"rank_zero_more",
         [](int r, std::int64_t s) { return r == 0 || s % 2 == 0; },
         never,
         {"leafValue", "nowhere"}},
        // Due at steps 3 and 6 everywhere; raises at step 5 on the last rank.
        {"failing",
         [](int, std::int64_t s) { return s == 3 || s == 6; },
         [](int r, std::int64_t s) { return r == ranks() - 1 && s == 5; },
         {}},
    };
    const std::filesystem::path folder =
        std::filesystem::path(CANOPY_TEST_SCRATCH) / "step_requests";
    if (rank() == 0)
    {
      std::filesystem::create_directories(folder);
      for (const ScriptTable& table : Tables)
      {
        std::ofstream(folder / (table.name + ".py")) << scriptText(table);
      }
    }
    MPI_Barrier(MPI_COMM_WORLD);
    for (const ScriptTable& table : Tables)
    {
      Scripts.push_back(std::make_unique<CatalystScript>((folder / (table.name + ".py")).string(),
                                                         "grid", Watchdog));
    }
    Forest = std::make_unique<ChangingForest>(2, 4, false, 5);
    Grid = buildHyperTreeGrid(Forest->describe(0));
  }

  /// What the step's requests must be: due where due on every rank and no rank
  /// raises; the failures (every rank's, in rank order) and disagreements.
  void expectRequests(const StepRequests& requests, std::int64_t step)
  {
    ASSERT_EQ(requests.due.size(), Tables.size());
    std::vector<std::string> failures;
    for (int r = 0; r < ranks(); ++r)
    {
      for (std::size_t i = 0; i < Tables.size(); ++i)
      {
        if (Tables[i].raises(r, step))
        {
          failures.push_back("rank " + std::to_string(r) + ", step " + std::to_string(step) +
                             ": the script '" + Scripts[i]->path() +
                             "' failed in RequestDataDescription: raised an error (Python "
                             "message above)");
        }
      }
    }
    for (std::size_t i = 0; i < Tables.size(); ++i)
    {
      bool anywhere = false;
      bool everywhere = true;
      bool raises = false;
      for (int r = 0; r < ranks(); ++r)
      {
        anywhere = anywhere || Tables[i].due(r, step);
        everywhere = everywhere && Tables[i].due(r, step);
        raises = raises || Tables[i].raises(r, step);
      }
      EXPECT_EQ(requests.due[i], everywhere && !raises)
          << "step " << step << ", script " << Tables[i].name;
      if (anywhere && !everywhere && !raises)
      {
        failures.push_back("step " + std::to_string(step) + ": ranks disagree whether '" +
                           Scripts[i]->path() + "' runs; skipped");
      }
    }
    EXPECT_EQ(requests.failures, failures) << "step " << step;
    EXPECT_EQ(requests.anyDue(),
              std::find(requests.due.begin(), requests.due.end(), true) != requests.due.end());
    EXPECT_EQ(requests.step, step);
  }

  /// Imports every script (as the driver does at a script's first run).
  void importAll()
  {
    for (auto& script : Scripts)
    {
      std::string error;
      ASSERT_TRUE(script->import(Grid, error)) << error;
    }
  }

  std::vector<ScriptTable> Tables;
  JobOutput Output;
  StepWatchdog Watchdog{0.0, rank(), MPI_COMM_WORLD, Output};
  CollectiveAgreement Agreement{MPI_COMM_WORLD, Output, 0.0, 0.0};
  FailureLog Log{Agreement};
  ScriptList Scripts;
  std::unique_ptr<ChangingForest> Forest;
  vtkSmartPointer<vtkHyperTreeGrid> Grid;
};

TEST_F(StepRequestsTest, BeforeTheirFirstRunScriptsAreDueWithEveryField)
{
  const StepRequests requests = requestScripts(Scripts, Agreement, Log, 0, 0.0);
  EXPECT_EQ(requests.due, std::vector<bool>(Tables.size(), true));
  EXPECT_TRUE(requests.failures.empty());
  EXPECT_TRUE(fieldsNeeded(Scripts, requests.due, Forest->describe(0)).includesAll());
}

TEST_F(StepRequestsTest, AScriptRunsOnlyWhereItIsDueOnEveryRank)
{
  ASSERT_GE(ranks(), 2) << "the disagreements need two ranks";
  requestScripts(Scripts, Agreement, Log, 0, 0.0);
  importAll();
  for (std::int64_t step = 1; step <= lastStep; ++step)
  {
    CapturedStderr log;
    const StepRequests requests =
        requestScripts(Scripts, Agreement, Log, step, 0.5 * static_cast<double>(step));
    log.restore();
    expectRequests(requests, step);
    EXPECT_EQ(requests.time, 0.5 * static_cast<double>(step));
    // Logged once, by rank 0: every failure and disagreement of the step.
    const std::string logged = log.text();
    for (const std::string& failure : requests.failures)
    {
      EXPECT_EQ(logged.find(failure) != std::string::npos, rank() == 0)
          << "step " << step << ": '" << failure << "' in the log:\n"
          << logged;
    }
  }
}

TEST_F(StepRequestsTest, TheFieldsOfTheDueScripts)
{
  requestScripts(Scripts, Agreement, Log, 0, 0.0);
  importAll();
  const ForestDescription forest = Forest->describe(1);
  // Step 2: "always" (value) and "rank_zero_more" (leafValue and a field the
  // forest lacks) due everywhere: the forest's fields they name, in its order.
  StepRequests requests = requestScripts(Scripts, Agreement, Log, 2, 1.0);
  ASSERT_EQ(requests.due, (std::vector<bool>{true, true, false}));
  FieldRequest fields = fieldsNeeded(Scripts, requests.due, forest);
  EXPECT_FALSE(fields.includesAll());
  EXPECT_EQ(fields.names(), (std::vector<std::string>{"value", "leafValue"}));
  // Step 3: "failing" is due too and asks for every field.
  requests = requestScripts(Scripts, Agreement, Log, 3, 1.5);
  ASSERT_EQ(requests.due, (std::vector<bool>{true, false, true}));
  EXPECT_TRUE(fieldsNeeded(Scripts, requests.due, forest).includesAll());
  // Only "always" due: its field only; none due: no field.
  fields = fieldsNeeded(Scripts, {true, false, false}, forest);
  EXPECT_EQ(fields.names(), std::vector<std::string>{"value"});
  fields = fieldsNeeded(Scripts, {false, false, false}, forest);
  EXPECT_FALSE(fields.includesAll());
  EXPECT_TRUE(fields.names().empty());
}

TEST_F(StepRequestsTest, ADisabledScriptIsNeverDue)
{
  requestScripts(Scripts, Agreement, Log, 0, 0.0);
  importAll();
  Scripts[0]->disable();
  const StepRequests requests = requestScripts(Scripts, Agreement, Log, 2, 1.0);
  EXPECT_EQ(requests.due, (std::vector<bool>{false, true, false}));
  EXPECT_TRUE(requests.failures.empty());
}

} // namespace
} // namespace canopy::testing
