// A condition or derived number over queries, e.g. "max(scalar) > 0.9" or
// "volume(scalar, 0.5, 1) > 1.2 * prev(volume(scalar, 0.5, 1))": parsed once
// (ExpressionParser.h), then evaluated each step from the history of its queries'
// values. Never evaluated by Python: the language is Canopy's own (docs/queries.md).
#pragma once

#include <canopy/Queries.h>

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace canopy
{

/// A refused expression: what() is "at character N: <what was expected or is wrong>".
class ExpressionError : public std::invalid_argument
{
public:
  ExpressionError(std::size_t position, const std::string& message);
  /// 1-based character where the problem is (the length + 1 at the end of the text).
  std::size_t position() const { return Position; }

private:
  std::size_t Position;
};

/// One operation of an expression's tree (the tree is a vector of them, children by index).
struct ExpressionNode
{
  enum class Op
  {
    Number,
    Query,        ///< `query`'s value, `shift` evaluated steps ago (added to the enclosing shift)
    Shifted,      ///< operand `a` evaluated `shift` steps earlier (prev(), @-k)
    AtLastFiring, ///< operand `a` at the step the trigger last fired (last(); shifts inside
                  ///< it read NaN)
    Negate,
    Not,
    Add,
    Subtract,
    Multiply,
    Divide,
    Less,
    LessEqual,
    Greater,
    GreaterEqual,
    Equal,
    NotEqual,
    And,
    Or,
    Abs
  };
  Op op = Op::Number;
  double number = 0.0;
  std::size_t query = 0; ///< index into Expression::queries()
  std::size_t shift = 0;
  std::size_t a = 0;
  std::size_t b = 0;
};

/// What an evaluation reads: a query's value some evaluated steps ago (NaN if the
/// history is shorter), and its value at the step the trigger last fired (empty or
/// NaN: never fired). Queries are numbered as Expression::queries().
struct ExpressionHistory
{
  std::function<double(std::size_t query, std::size_t stepsAgo)> value;
  std::function<double(std::size_t query)> atLastFiring;
};

class Expression
{
public:
  Expression(std::string text, std::vector<ExpressionNode> nodes, std::size_t root,
             std::vector<Query> queries, std::size_t historyDepth);

  const std::string& text() const { return Text; }
  /// The distinct queries the expression reads, in order of first appearance.
  const std::vector<Query>& queries() const { return Queries; }
  /// The most evaluated steps back it looks (prev() and @-k; last() not counted).
  std::size_t historyDepth() const { return HistoryDepth; }

  /// The expression's value (comparisons, and, or, not give 1 or 0; NaN compares
  /// false and is not true).
  double evaluate(const ExpressionHistory& history) const;
  /// evaluate() as a condition: true when the value is neither 0 nor NaN.
  bool holds(const ExpressionHistory& history) const;

private:
  /// `atLastFiring`: inside last(), where queries read their value at the last firing.
  double evaluate(std::size_t node, std::size_t shift, bool atLastFiring,
                  const ExpressionHistory& history) const;

  std::string Text;
  std::vector<ExpressionNode> Nodes;
  std::size_t Root;
  std::vector<Query> Queries;
  std::size_t HistoryDepth;
};

} // namespace canopy
