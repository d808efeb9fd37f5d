// A trigger: a condition (Expression) and when it fires given the condition's
// value at each evaluated step: every step it holds, on its rising edge only, or
// while it holds but at most once every N steps. Keeps the little state that
// needs (did it hold last time, when did it last fire).
#pragma once

#include "Expression.h"

#include <cstdint>
#include <string>
#include <vector>

namespace canopy
{

enum class TriggerMode
{
  WhileTrue,  ///< "while": every evaluated step the condition holds
  RisingEdge, ///< "rising": a step it holds after one it did not (or the first step)
  AtMostEvery ///< "every:N": while it holds, but N steps at least after the last firing
};

class Trigger
{
public:
  /// `mode` as the script's --trigger-mode= says it: "while" (default when empty),
  /// "rising" or "every:N" (N >= 1). Throws std::invalid_argument naming what it expects.
  Trigger(Expression condition, const std::string& mode);

  const Expression& condition() const { return Condition; }
  TriggerMode mode() const { return Mode; }
  /// "every:N": N; otherwise 0.
  std::int64_t everySteps() const { return Every; }

  /// Evaluates the condition at `step` (steps increase from call to call) from
  /// `values` (a query's value some evaluated steps ago) and says whether the
  /// trigger fires; last() reads the step of the previous firing.
  bool decide(std::int64_t step,
              const std::function<double(std::size_t query, std::size_t stepsAgo)>& values);

  /// Whether the condition held at the last decide().
  bool held() const { return Held; }

private:
  Expression Condition;
  TriggerMode Mode = TriggerMode::WhileTrue;
  std::int64_t Every = 0;
  bool Held = false;
  bool Fired = false;
  std::int64_t LastFiredStep = 0;
  std::vector<double> AtLastFiring; ///< the condition's queries' values then
};

} // namespace canopy
