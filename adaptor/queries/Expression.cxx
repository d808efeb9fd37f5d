#include "Expression.h"

#include <cmath>
#include <limits>

namespace canopy
{

ExpressionError::ExpressionError(std::size_t position, const std::string& message)
    : std::invalid_argument("at character " + std::to_string(position) + ": " + message),
      Position(position)
{
}

Expression::Expression(std::string text, std::vector<ExpressionNode> nodes, std::size_t root,
                       std::vector<Query> queries, std::size_t historyDepth)
    : Text(std::move(text)), Nodes(std::move(nodes)), Root(root), Queries(std::move(queries)),
      HistoryDepth(historyDepth)
{
}

double Expression::evaluate(const ExpressionHistory& history) const
{
  return this->evaluate(this->Root, 0, false, history);
}

bool Expression::holds(const ExpressionHistory& history) const
{
  const double value = this->evaluate(history);
  return value != 0.0 && !std::isnan(value);
}

double Expression::evaluate(std::size_t at, std::size_t shift, bool atLastFiring,
                            const ExpressionHistory& history) const
{
  using Op = ExpressionNode::Op;
  const ExpressionNode& node = this->Nodes[at];
  const auto truth = [](double v) { return v != 0.0 && !std::isnan(v); };
  const auto a = [&] { return this->evaluate(node.a, shift, atLastFiring, history); };
  const auto b = [&] { return this->evaluate(node.b, shift, atLastFiring, history); };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  switch (node.op)
  {
  case Op::Number:
    return node.number;
  case Op::Query:
    if (atLastFiring)
    {
      return shift == 0 && history.atLastFiring ? history.atLastFiring(node.query) : nan;
    }
    return history.value(node.query, shift);
  case Op::Shifted:
    return this->evaluate(node.a, shift + node.shift, atLastFiring, history);
  case Op::AtLastFiring:
    return this->evaluate(node.a, 0, true, history);
  case Op::Negate:
    return -a();
  case Op::Abs:
    return std::abs(a());
  case Op::Not:
    return truth(a()) ? 0.0 : 1.0;
  case Op::Add:
    return a() + b();
  case Op::Subtract:
    return a() - b();
  case Op::Multiply:
    return a() * b();
  case Op::Divide:
    return a() / b();
  case Op::Less:
    return a() < b() ? 1.0 : 0.0;
  case Op::LessEqual:
    return a() <= b() ? 1.0 : 0.0;
  case Op::Greater:
    return a() > b() ? 1.0 : 0.0;
  case Op::GreaterEqual:
    return a() >= b() ? 1.0 : 0.0;
  case Op::Equal:
    return a() == b() ? 1.0 : 0.0;
  case Op::NotEqual:
  {
    const double x = a();
    const double y = b();
    return x != y && !std::isnan(x) && !std::isnan(y) ? 1.0 : 0.0; // NaN compares false
  }
  case Op::And:
    return truth(a()) && truth(b()) ? 1.0 : 0.0;
  case Op::Or:
    return truth(a()) || truth(b()) ? 1.0 : 0.0;
  }
  return nan;
}

} // namespace canopy
