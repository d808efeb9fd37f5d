// How failures reach the simulation's output: every rank's failures are
// gathered (ParaView silences stderr on ranks above 0) and rank 0 logs them,
// with the Python tracebacks of the other ranks.
#pragma once

#include "CollectiveAgreement.h"

#include <string>
#include <vector>

namespace canopy
{

/// The items, `separator` between them.
std::string joined(const std::vector<std::string>& items, const char* separator);

class FailureLog
{
public:
  explicit FailureLog(const CollectiveAgreement& agreement) : Agreement(agreement) {}

  /// Logs these failures (known on every rank) once: on rank 0.
  void log(const std::vector<std::string>& failures) const;

  /// Every rank's failure ("rank R, <localFailure>"), gathered and logged with
  /// the other ranks' tracebacks ("<localTraceback>": "step 4: Python traceback
  /// of the script '...':\n..."). Collective; `after` bounds the wait by the
  /// step time limit.
  std::vector<std::string> gather(const std::string& localFailure,
                                  const std::string& localTraceback = {},
                                  const CollectiveAgreement::After* after = nullptr) const;

private:
  const CollectiveAgreement& Agreement;
};

} // namespace canopy
