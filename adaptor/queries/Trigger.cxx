#include "Trigger.h"

#include <cstdlib>
#include <stdexcept>

namespace canopy
{

Trigger::Trigger(Expression condition, const std::string& mode) : Condition(std::move(condition))
{
  if (mode.empty() || mode == "while")
  {
    Mode = TriggerMode::WhileTrue;
  }
  else if (mode == "rising")
  {
    Mode = TriggerMode::RisingEdge;
  }
  else if (mode.compare(0, 6, "every:") == 0 && mode.size() > 6 &&
           mode.find_first_not_of("0123456789", 6) == std::string::npos && mode.size() < 16 &&
           std::atoll(mode.c_str() + 6) >= 1)
  {
    Mode = TriggerMode::AtMostEvery;
    Every = std::atoll(mode.c_str() + 6);
  }
  else
  {
    throw std::invalid_argument("trigger mode '" + mode +
                                "': expected 'while', 'rising' or 'every:N' (N >= 1 steps)");
  }
}

bool Trigger::decide(std::int64_t step,
                     const std::function<double(std::size_t query, std::size_t stepsAgo)>& values)
{
  ExpressionHistory history;
  history.value = values;
  if (Fired)
  {
    history.atLastFiring = [this](std::size_t query) { return AtLastFiring[query]; };
  }
  const bool heldBefore = Held;
  Held = Condition.holds(history);
  bool fires = Held;
  if (Mode == TriggerMode::RisingEdge)
  {
    fires = Held && !heldBefore;
  }
  else if (Mode == TriggerMode::AtMostEvery)
  {
    fires = Held && (!Fired || step - LastFiredStep >= Every);
  }
  if (fires)
  {
    Fired = true;
    LastFiredStep = step;
    AtLastFiring.clear();
    for (std::size_t q = 0; q < Condition.queries().size(); ++q)
    {
      AtLastFiring.push_back(values(q, 0));
    }
  }
  return fires;
}

} // namespace canopy
