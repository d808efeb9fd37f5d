#include "FailureLog.h"

#include <vtkLogger.h>

namespace canopy
{

std::string joined(const std::vector<std::string>& items, const char* separator)
{
  std::string text;
  for (const auto& item : items)
  {
    text += (text.empty() ? "" : separator) + item;
  }
  return text;
}

void FailureLog::log(const std::vector<std::string>& failures) const
{
  if (this->Agreement.rank() != 0)
  {
    return;
  }
  for (const auto& failure : failures)
  {
    vtkLogF(ERROR, "canopy: %s", failure.c_str());
  }
}

std::vector<std::string> FailureLog::gather(const std::string& localFailure,
                                            const std::string& localTraceback,
                                            const CollectiveAgreement::After* after) const
{
  const std::string traceback = localFailure.empty() ? std::string() : localTraceback;
  auto failures = this->Agreement.gatherFailures(localFailure, after, traceback);
  if (failures.empty())
  {
    return failures;
  }
  // Every rank knows that some rank failed: the tracebacks can be gathered too.
  const auto tracebacks = this->Agreement.gatherOnRoot(traceback);
  this->log(failures);
  for (std::size_t rank = 1; rank < tracebacks.size(); ++rank)
  {
    if (!tracebacks[rank].empty())
    {
      vtkLogF(ERROR, "canopy: rank %zu, %s", rank, tracebacks[rank].c_str());
    }
  }
  return failures;
}

} // namespace canopy
