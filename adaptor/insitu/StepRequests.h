// Which scripts run at a step: each script's own answer (its triggers, its
// RequestDataDescription), agreed over ranks (a script runs only where it is
// due on every rank), and the fields the due scripts need.
#pragma once

#include "CatalystScript.h"
#include "CollectiveAgreement.h"
#include "FailureLog.h"

#include <canopy/ForestDescription.h>
#include <canopy/HtgBuilder.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace canopy
{

using ScriptList = std::vector<std::unique_ptr<CatalystScript>>;

struct StepRequests
{
  std::int64_t step = 0;
  double time = 0.0;
  std::vector<bool> due;             ///< per script, the same on every rank
  std::vector<std::string> failures; ///< requests that failed, ranks that disagreed (logged)
  bool anyDue() const;
};

/// Asks every script, then agrees over ranks. Collective.
StepRequests requestScripts(const ScriptList& scripts, const CollectiveAgreement& agreement,
                            const FailureLog& failureLog, std::int64_t step, double time);

/// The forest's fields the due scripts asked for (all of them if one asked for all).
FieldRequest fieldsNeeded(const ScriptList& scripts, const std::vector<bool>& due,
                          const ForestDescription& forest);

} // namespace canopy
