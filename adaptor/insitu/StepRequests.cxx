#include "StepRequests.h"

#include <vtkLogger.h>

#include <algorithm>
#include <chrono>

namespace canopy
{

bool StepRequests::anyDue() const
{
  return std::any_of(this->due.begin(), this->due.end(), [](bool due) { return due; });
}

StepRequests requestScripts(const ScriptList& scripts, const CollectiveAgreement& agreement,
                            const FailureLog& failureLog, std::int64_t step, double time)
{
  const std::string stepText = "step " + std::to_string(step) + ": ";
  StepRequests requests{step, time, std::vector<bool>(scripts.size(), false), {}};
  std::vector<ScriptState> states(scripts.size(), ScriptState::NotDue);
  std::string localErrors;
  std::string tracebacks;
  const auto since = std::chrono::steady_clock::now();
  double extraSeconds = 0.0;
  for (std::size_t i = 0; i < scripts.size(); ++i)
  {
    auto& script = *scripts[i];
    std::string error;
    extraSeconds = std::max(extraSeconds, script.extraSeconds());
    states[i] = script.request(step, time, error);
    if (states[i] == ScriptState::Failed)
    {
      localErrors += (localErrors.empty() ? "" : "; ") + error;
      if (!script.lastTraceback().empty())
      {
        tracebacks += stepText + "Python traceback of the script '" + script.path() + "':\n" +
                      script.lastTraceback();
      }
    }
  }
  const CollectiveAgreement::After asking{
      "RequestDataDescription of the scripts at step " + std::to_string(step), since, extraSeconds};
  const auto agreed = agreement.agree(states, &asking);
  bool anyProblem = false;
  for (std::size_t i = 0; i < scripts.size(); ++i)
  {
    anyProblem = anyProblem || agreed.maximum[i] == ScriptState::Failed ||
                 agreed.minimum[i] != agreed.maximum[i];
    requests.due[i] = agreed.minimum[i] == ScriptState::Due;
  }
  if (!anyProblem)
  {
    return requests;
  }
  requests.failures =
      failureLog.gather(localErrors.empty() ? std::string() : stepText + localErrors, tracebacks);
  std::vector<std::string> disagreements;
  for (std::size_t i = 0; i < scripts.size(); ++i)
  {
    if (agreed.maximum[i] != ScriptState::Failed && agreed.minimum[i] != agreed.maximum[i])
    {
      disagreements.push_back(stepText + "ranks disagree whether '" + scripts[i]->path() +
                              "' runs; skipped");
    }
  }
  failureLog.log(disagreements);
  requests.failures.insert(requests.failures.end(), disagreements.begin(), disagreements.end());
  return requests;
}

FieldRequest fieldsNeeded(const ScriptList& scripts, const std::vector<bool>& due,
                          const ForestDescription& forest)
{
  std::vector<std::string> present;
  for (std::size_t i = 0; i < scripts.size(); ++i)
  {
    if (!due[i])
    {
      continue;
    }
    const auto& script = *scripts[i];
    if (script.needsAllFields())
    {
      return FieldRequest::all();
    }
    unsigned int found = 0;
    for (const auto& field : forest.fields)
    {
      if (script.needsField(field.name))
      {
        ++found;
        if (std::find(present.begin(), present.end(), field.name) == present.end())
        {
          present.push_back(field.name);
        }
      }
    }
    if (found < script.numberOfNeededFields())
    {
      vtkVLogF(vtkLogger::VERBOSITY_TRACE,
               "canopy: '%s' asks for %u field(s) the forest does not have", script.path().c_str(),
               script.numberOfNeededFields() - found);
    }
  }
  return FieldRequest::only(present);
}

} // namespace canopy
