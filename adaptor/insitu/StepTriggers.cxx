#include "StepTriggers.h"

#include "ExpressionParser.h"

#include <chrono>
#include <filesystem>

namespace canopy
{
namespace
{

/// The value of the last "--name=value" among `arguments` (dashes or underscores in
/// the name, as canopy_catalyst.settings() takes them), or nothing.
std::optional<std::string> argument(const std::vector<std::string>& arguments,
                                    const std::string& name)
{
  std::string underscored = name;
  for (char& c : underscored)
  {
    c = c == '-' ? '_' : c;
  }
  std::optional<std::string> value;
  for (const auto& given : arguments)
  {
    for (const std::string& spelling : {"--" + name + "=", "--" + underscored + "="})
    {
      if (given.compare(0, spelling.size(), spelling) == 0)
      {
        value = given.substr(spelling.size());
      }
    }
  }
  return value;
}

std::string scriptName(const std::string& path)
{
  return std::filesystem::path(path).filename().string();
}

} // namespace

StepTriggers::StepTriggers(const std::vector<PipelineScript>& scripts, const InSituOptions& options,
                           std::string historyPath, int rank)
    : Scripts(scripts.size()), History({}, 0)
{
  for (std::size_t s = 0; s < scripts.size(); ++s)
  {
    const auto condition = argument(scripts[s].arguments, "trigger");
    const auto mode = argument(scripts[s].arguments, "trigger-mode");
    const std::string where = "canopy::InSitu: the script '" + scripts[s].path + "'";
    if (!condition || condition->find_first_not_of(" \t") == std::string::npos)
    {
      if (mode)
      {
        throw InSituError(where + ": --trigger-mode without --trigger");
      }
      continue;
    }
    try
    {
      Expression expression = parseExpression(*condition, options.fields);
      Trigger trigger(std::move(expression), mode.value_or(""));
      auto queries = this->track(trigger.condition());
      Triggers.push_back({s, scriptName(scripts[s].path), std::move(trigger), std::move(queries)});
    }
    catch (const ExpressionError& error)
    {
      throw InSituError(where + ": --trigger=" + *condition + ": " + error.what());
    }
    catch (const std::invalid_argument& error)
    {
      throw InSituError(where + ": --trigger-mode: " + error.what());
    }
  }
  for (const std::string& text : options.queries)
  {
    try
    {
      Expression expression = parseExpression(text, options.fields);
      auto queries = this->track(expression);
      Reported.push_back({std::move(expression), std::move(queries)});
    }
    catch (const ExpressionError& error)
    {
      throw InSituError("canopy::InSitu: the query '" + text + "': " + error.what());
    }
  }
  if (rank == 0 && this->active() && !historyPath.empty())
  {
    std::vector<std::string> columns;
    for (const Query& query : History.queries())
    {
      columns.push_back(query.text());
    }
    for (const auto& reported : Reported)
    {
      if (!isQueryText(reported.expression.text()))
      {
        columns.push_back(reported.expression.text());
      }
    }
    for (const auto& t : Triggers)
    {
      columns.push_back(t.name + ": " + t.trigger.condition().text());
      columns.push_back(t.name + ": fired");
    }
    File = std::make_unique<QueryHistoryFile>(historyPath, columns);
    HistoryPath = historyPath;
  }
}

std::vector<std::size_t> StepTriggers::track(const Expression& expression)
{
  std::vector<std::size_t> indices;
  for (const Query& query : expression.queries())
  {
    indices.push_back(History.indexOf(query));
  }
  History.keepAtLeast(expression.historyDepth());
  return indices;
}

bool StepTriggers::isQueryText(const std::string& text) const
{
  for (const Query& query : History.queries())
  {
    if (query.text() == text)
    {
      return true;
    }
  }
  return false;
}

bool StepTriggers::hasTrigger(std::size_t script) const
{
  for (const auto& t : Triggers)
  {
    if (t.script == script)
    {
      return true;
    }
  }
  return false;
}

TriggerOutcome StepTriggers::evaluate(MPI_Comm communicator, std::int64_t step, double time,
                                      const ForestDescription& forest)
{
  const auto start = std::chrono::steady_clock::now();
  TriggerOutcome outcome;
  outcome.step = step;
  outcome.time = time;
  outcome.allowed.assign(Scripts, true);
  std::vector<double> values(History.queries().size(), std::numeric_limits<double>::quiet_NaN());
  try
  {
    const auto results = runQueries(communicator, forest, History.queries());
    for (std::size_t q = 0; q < results.size(); ++q)
    {
      values[q] = results[q].value;
      outcome.queries[History.queries()[q].text()] = results[q];
    }
  }
  catch (const QueryError& error)
  {
    // The part before "; on rank" is the same on every rank.
    const std::string what = error.what();
    outcome.failure =
        "step " + std::to_string(step) + ": " + what.substr(0, what.find("; on rank"));
  }
  History.record(values); // a failed step is in the history as NaN
  std::vector<double> row = values;
  for (const auto& reported : Reported)
  {
    ExpressionHistory history;
    history.value = [&](std::size_t q, std::size_t ago)
    { return History.value(reported.queries[q], ago); };
    const double value = reported.expression.evaluate(history);
    outcome.expressions[reported.expression.text()] = value;
    if (!isQueryText(reported.expression.text()))
    {
      row.push_back(value); // a bare query has its column already
    }
  }
  for (auto& t : Triggers)
  {
    const bool fires =
        outcome.failure.empty() && t.trigger.decide(step, [&](std::size_t q, std::size_t ago)
                                                    { return History.value(t.queries[q], ago); });
    outcome.allowed[t.script] = fires;
    if (fires)
    {
      outcome.fired.push_back(t.name);
    }
    row.push_back(t.trigger.held() ? 1.0 : 0.0);
    row.push_back(fires ? 1.0 : 0.0);
  }
  if (File)
  {
    outcome.warning = File->write(step, time, row);
    Rows += outcome.warning.empty() ? 1 : 0;
  }
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return outcome;
}

} // namespace canopy
