// The driver's triggers and queries: each script's --trigger= and --trigger-mode=
// arguments and InSituOptions::queries, parsed and checked at open; at each
// evaluated step, one runQueries call (one collective) for all of their queries,
// the triggers decided, the history file written (QueryHistoryFile).
#pragma once

#include "QueryHistory.h"
#include "QueryHistoryFile.h"
#include "Trigger.h"

#include <canopy/InSitu.h>

#include <mpi.h>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace canopy
{

/// What one evaluated step decided.
struct TriggerOutcome
{
  std::int64_t step = 0;
  double time = 0.0;
  /// Per script: false when its trigger did not fire (or the queries failed); true for
  /// scripts without a trigger.
  std::vector<bool> allowed;
  std::vector<std::string> fired; ///< scripts whose trigger fired
  std::map<std::string, QueryResult> queries;
  std::map<std::string, double> expressions;
  std::string failure; ///< the queries failed (the same text on every rank)
  std::string warning; ///< rank 0: the history file could not be written (once)
  double seconds = 0.0;
};

class StepTriggers
{
public:
  /// Parses the scripts' triggers and the options' queries (fields checked
  /// against options.fields when given). Throws InSituError naming the script or
  /// query, the character and what was expected. `historyPath`: "" for no file;
  /// only `rank` 0 writes it.
  StepTriggers(const std::vector<PipelineScript>& scripts, const InSituOptions& options,
               std::string historyPath, int rank);

  /// Whether there is anything to evaluate (a trigger or a query).
  bool active() const { return !Triggers.empty() || !Reported.empty(); }
  bool hasTrigger(std::size_t script) const;
  /// The history file this rank writes, once it holds a row; empty otherwise.
  std::string writtenHistory() const { return File && Rows > 0 ? HistoryPath : std::string(); }

  /// Runs the step's queries over `communicator` (collective; one MPI call) and
  /// decides the triggers. Never throws for a query problem: it is in `failure`.
  TriggerOutcome evaluate(MPI_Comm communicator, std::int64_t step, double time,
                          const ForestDescription& forest);

private:
  struct ScriptTrigger
  {
    std::size_t script;
    std::string name;
    Trigger trigger;
    std::vector<std::size_t> queries; ///< the condition's queries in the history
  };
  struct ReportedExpression
  {
    Expression expression;
    std::vector<std::size_t> queries;
  };

  std::vector<std::size_t> track(const Expression& expression);
  /// Whether `text` is exactly one of the history's queries (its column is there).
  bool isQueryText(const std::string& text) const;

  std::size_t Scripts = 0;
  std::vector<ScriptTrigger> Triggers;
  std::vector<ReportedExpression> Reported;
  QueryHistory History;
  std::unique_ptr<QueryHistoryFile> File;
  std::string HistoryPath;
  std::size_t Rows = 0;
};

} // namespace canopy
