#include "ExpressionParser.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>

namespace canopy
{
namespace
{

constexpr std::size_t longestText = 4096;
constexpr int deepestNesting = 64;
constexpr std::size_t furthestBack = 1000;

using Op = ExpressionNode::Op;

struct QueryFunction
{
  QueryKind kind;
  bool ranged;
};

const std::map<std::string, QueryFunction>& queryFunctions()
{
  static const std::map<std::string, QueryFunction> functions = {
      {"min", {QueryKind::Minimum, false}},
      {"max", {QueryKind::Maximum, false}},
      {"sum", {QueryKind::Sum, false}},
      {"mean", {QueryKind::Mean, false}},
      {"integral", {QueryKind::Integral, false}},
      {"l2", {QueryKind::L2Norm, false}},
      {"nonfinite", {QueryKind::NonFinite, false}},
      {"cells", {QueryKind::Cells, false}},
      {"count", {QueryKind::Count, true}},
      {"volume", {QueryKind::Volume, true}}};
  return functions;
}

const char* const functionList =
    "min, max, sum, mean, integral, l2, nonfinite, cells, count, volume, prev, last, abs";

class Parser
{
public:
  Parser(const std::string& text, const std::vector<std::string>& fields)
      : Text(text), Fields(fields)
  {
  }

  Expression parse()
  {
    if (Text.size() > longestText)
    {
      throw ExpressionError(longestText + 1, "the expression is longer than " +
                                                 std::to_string(longestText) + " characters");
    }
    skipSpace();
    if (At >= Text.size())
    {
      fail("expected an expression, found the end of the text");
    }
    const std::size_t root = parseOr();
    skipSpace();
    if (At < Text.size())
    {
      fail("expected an operator or the end of the expression, found " + found());
    }
    const std::size_t deepest = deepestShift(root);
    return Expression(Text, std::move(Nodes), root, std::move(Queries), deepest);
  }

private:
  [[noreturn]] void fail(const std::string& message) const
  {
    throw ExpressionError(At + 1, message);
  }
  [[noreturn]] void failAt(std::size_t at, const std::string& message) const
  {
    throw ExpressionError(at + 1, message);
  }

  void skipSpace()
  {
    while (At < Text.size() && std::isspace(static_cast<unsigned char>(Text[At])))
    {
      ++At;
    }
  }

  /// What is at the cursor, for messages.
  std::string found() const
  {
    if (At >= Text.size())
    {
      return "the end of the text";
    }
    const unsigned char c = static_cast<unsigned char>(Text[At]);
    if (std::isalnum(c) || c == '_')
    {
      std::size_t end = At;
      while (end < Text.size() &&
             (std::isalnum(static_cast<unsigned char>(Text[end])) || Text[end] == '_'))
      {
        ++end;
      }
      return "'" + Text.substr(At, end - At) + "'";
    }
    if (std::isprint(c))
    {
      return "'" + std::string(1, Text[At]) + "'";
    }
    return "a byte " + std::to_string(static_cast<int>(c));
  }

  /// Consumes `token` (after spaces) if it is next; words only as whole words.
  bool accept(const std::string& token)
  {
    skipSpace();
    if (Text.compare(At, token.size(), token) != 0)
    {
      return false;
    }
    const bool word = std::isalpha(static_cast<unsigned char>(token[0]));
    const std::size_t end = At + token.size();
    if (word && end < Text.size() &&
        (std::isalnum(static_cast<unsigned char>(Text[end])) || Text[end] == '_'))
    {
      return false;
    }
    At = end;
    return true;
  }

  void expect(const std::string& token, const std::string& what)
  {
    if (!accept(token))
    {
      fail("expected " + what + ", found " + found());
    }
  }

  std::size_t add(ExpressionNode node)
  {
    Nodes.push_back(node);
    return Nodes.size() - 1;
  }

  std::size_t binary(Op op, std::size_t a, std::size_t b)
  {
    ExpressionNode node;
    node.op = op;
    node.a = a;
    node.b = b;
    return add(node);
  }

  /// Guards the recursion: every rule that can nest goes through here.
  struct Nesting
  {
    Parser& parser;
    Nesting(Parser& p, std::size_t at) : parser(p)
    {
      if (++parser.Depth > deepestNesting)
      {
        parser.failAt(at, "nested deeper than " + std::to_string(deepestNesting) + " levels");
      }
    }
    ~Nesting() { --parser.Depth; }
  };

  std::size_t parseOr()
  {
    std::size_t left = parseAnd();
    while (accept("or"))
    {
      left = binary(Op::Or, left, parseAnd());
    }
    return left;
  }

  std::size_t parseAnd()
  {
    std::size_t left = parseNot();
    while (accept("and"))
    {
      left = binary(Op::And, left, parseNot());
    }
    return left;
  }

  std::size_t parseNot()
  {
    skipSpace();
    const std::size_t at = At;
    if (accept("not"))
    {
      Nesting nesting(*this, at);
      return binary(Op::Not, parseNot(), 0);
    }
    return parseComparison();
  }

  std::size_t parseComparison()
  {
    const std::size_t left = parseSum();
    static const std::pair<const char*, Op> comparisons[] = {
        {"<=", Op::LessEqual}, {">=", Op::GreaterEqual}, {"==", Op::Equal},
        {"!=", Op::NotEqual},  {"<", Op::Less},          {">", Op::Greater}};
    for (const auto& [token, op] : comparisons)
    {
      if (accept(token))
      {
        const std::size_t right = parseSum();
        skipSpace();
        for (const auto& [other, ignored] : comparisons)
        {
          (void)ignored;
          if (Text.compare(At, std::char_traits<char>::length(other), other) == 0)
          {
            fail("comparisons do not chain: use 'and' between two comparisons");
          }
        }
        return binary(op, left, right);
      }
    }
    return left;
  }

  std::size_t parseSum()
  {
    std::size_t left = parseProduct();
    for (;;)
    {
      if (accept("+"))
      {
        left = binary(Op::Add, left, parseProduct());
      }
      else if (accept("-"))
      {
        left = binary(Op::Subtract, left, parseProduct());
      }
      else
      {
        return left;
      }
    }
  }

  std::size_t parseProduct()
  {
    std::size_t left = parseUnary();
    for (;;)
    {
      if (accept("*"))
      {
        left = binary(Op::Multiply, left, parseUnary());
      }
      else if (accept("/"))
      {
        left = binary(Op::Divide, left, parseUnary());
      }
      else
      {
        return left;
      }
    }
  }

  std::size_t parseUnary()
  {
    skipSpace();
    const std::size_t at = At;
    if (accept("-"))
    {
      Nesting nesting(*this, at);
      return binary(Op::Negate, parseUnary(), 0);
    }
    return parsePostfix();
  }

  std::size_t parsePostfix()
  {
    const std::size_t operand = parsePrimary();
    if (!accept("@"))
    {
      return operand;
    }
    expect("-", "'-' after '@' (q@-k: k evaluated steps ago)");
    skipSpace();
    const std::size_t steps = wholeNumber("a whole number of steps after '@-'");
    if (steps < 1 || steps > furthestBack)
    {
      fail("expected a number of steps from 1 to " + std::to_string(furthestBack) + " after '@-'");
    }
    return shifted(operand, steps);
  }

  std::size_t shifted(std::size_t operand, std::size_t steps)
  {
    ExpressionNode node;
    node.op = Op::Shifted;
    node.a = operand;
    node.shift = steps;
    return add(node);
  }

  /// The furthest back the subtree at `node` reads.
  std::size_t deepestShift(std::size_t at) const
  {
    const ExpressionNode& node = Nodes[at];
    switch (node.op)
    {
    case Op::Number:
    case Op::Query:
      return 0;
    case Op::Shifted:
      return node.shift + deepestShift(node.a);
    case Op::AtLastFiring:
      return 0;
    case Op::Negate:
    case Op::Not:
    case Op::Abs:
      return deepestShift(node.a);
    default:
      return std::max(deepestShift(node.a), deepestShift(node.b));
    }
  }

  std::size_t wholeNumber(const std::string& what)
  {
    const std::size_t start = At;
    std::size_t value = 0;
    while (At < Text.size() && std::isdigit(static_cast<unsigned char>(Text[At])))
    {
      value =
          std::min<std::size_t>(value * 10 + static_cast<std::size_t>(Text[At] - '0'), 1000000000);
      ++At;
    }
    if (At == start)
    {
      fail("expected " + what + ", found " + found());
    }
    return value;
  }

  /// A number literal, optionally signed (for a query's range).
  double number(const std::string& what)
  {
    skipSpace();
    const std::size_t start = At;
    if (At < Text.size() && (Text[At] == '-' || Text[At] == '+'))
    {
      ++At;
    }
    const char* begin = Text.c_str() + At;
    if (At >= Text.size() ||
        !(std::isdigit(static_cast<unsigned char>(Text[At])) || Text[At] == '.'))
    {
      At = start;
      fail("expected " + what + ", found " + found());
    }
    char* end = nullptr;
    errno = 0;
    double value = std::strtod(begin, &end);
    if (end == begin || errno == ERANGE || !std::isfinite(value))
    {
      At = start;
      fail("expected " + what + " (a finite decimal number), found " + found());
    }
    // strtod also reads hexadecimal, "inf" and "nan": only decimal digits, '.', 'e' here.
    for (const char* c = begin; c < end; ++c)
    {
      if (!(std::isdigit(static_cast<unsigned char>(*c)) || *c == '.' || *c == 'e' || *c == 'E' ||
            *c == '+' || *c == '-'))
      {
        At = start;
        fail("expected " + what + " (a decimal number), found " + found());
      }
    }
    At += static_cast<std::size_t>(end - begin);
    if (Text[start] == '-')
    {
      value = -value;
    }
    return value;
  }

  std::string name()
  {
    skipSpace();
    const std::size_t start = At;
    while (At < Text.size() &&
           (std::isalnum(static_cast<unsigned char>(Text[At])) || Text[At] == '_'))
    {
      ++At;
    }
    return Text.substr(start, At - start);
  }

  std::size_t parsePrimary()
  {
    skipSpace();
    if (At >= Text.size())
    {
      fail("expected a number, a query or '(', found the end of the text");
    }
    const unsigned char c = static_cast<unsigned char>(Text[At]);
    if (std::isdigit(c) || c == '.')
    {
      ExpressionNode node;
      node.op = Op::Number;
      node.number = number("a number");
      return add(node);
    }
    Nesting nesting(*this, At); // a parenthesis or a call: one level more
    if (accept("("))
    {
      const std::size_t inside = parseOr();
      expect(")", "')'");
      return inside;
    }
    if (!(std::isalpha(c) || c == '_'))
    {
      fail("expected a number, a query or '(', found " + found());
    }
    const std::size_t start = At;
    const std::string function = name();
    const auto query = queryFunctions().find(function);
    const bool history = function == "prev" || function == "last" || function == "abs";
    if (query == queryFunctions().end() && !history)
    {
      failAt(start, "unknown function '" + function + "' (expected one of: " + functionList + ")");
    }
    expect("(", "'(' after '" + function + "'");
    if (history)
    {
      const std::size_t inside = parseOr();
      if (accept(","))
      {
        failAt(start, "'" + function + "' takes 1 argument, found more");
      }
      expect(")", "')' closing '" + function + "('");
      if (function == "prev")
      {
        return shifted(inside, 1);
      }
      ExpressionNode node;
      node.op = function == "last" ? Op::AtLastFiring : Op::Abs;
      node.a = inside;
      return add(node);
    }
    return parseQuery(start, function, query->second);
  }

  std::size_t parseQuery(std::size_t start, const std::string& function, const QueryFunction& kind)
  {
    const std::string signature =
        "'" + function + "' takes " +
        (kind.ranged ? "3 arguments (field, low, high)" : "1 argument (a field)");
    skipSpace();
    if (accept(")"))
    {
      failAt(start, signature + ", found none");
    }
    const std::size_t fieldAt = At;
    if (At >= Text.size() ||
        !(std::isalpha(static_cast<unsigned char>(Text[At])) || Text[At] == '_'))
    {
      fail("expected a field name, found " + found());
    }
    Query query;
    query.kind = kind.kind;
    query.field = name();
    if (!Fields.empty() && std::find(Fields.begin(), Fields.end(), query.field) == Fields.end())
    {
      std::string known;
      for (const auto& field : Fields)
      {
        known += (known.empty() ? "" : ", ") + field;
      }
      failAt(fieldAt, "unknown field '" + query.field + "' (fields: " + known + ")");
    }
    if (accept("["))
    {
      skipSpace();
      const std::size_t component = wholeNumber("a component number");
      if (component > 1000)
      {
        fail("expected a component number below 1000");
      }
      query.component = static_cast<int>(component);
      expect("]", "']'");
    }
    std::size_t given = 1;
    if (kind.ranged)
    {
      if (!accept(","))
      {
        skipSpace();
        if (At < Text.size() && Text[At] == ')')
        {
          failAt(start, signature + ", found " + std::to_string(given));
        }
        fail("expected ',' after the field, found " + found());
      }
      query.low = number("the range's low end");
      ++given;
      if (!accept(","))
      {
        skipSpace();
        if (At < Text.size() && Text[At] == ')')
        {
          failAt(start, signature + ", found " + std::to_string(given));
        }
        fail("expected ',' after the low end, found " + found());
      }
      query.high = number("the range's high end");
      ++given;
      if (!(query.low <= query.high))
      {
        failAt(start, "'" + function + "': the range's low end is above its high end");
      }
    }
    skipSpace();
    if (At < Text.size() && Text[At] == ',')
    {
      failAt(start, signature + ", found more");
    }
    expect(")", "')' closing '" + function + "('");
    ExpressionNode node;
    node.op = Op::Query;
    const std::string key = query.text();
    std::size_t index = 0;
    while (index < Queries.size() && Queries[index].text() != key)
    {
      ++index;
    }
    if (index == Queries.size())
    {
      Queries.push_back(query);
    }
    node.query = index;
    return add(node);
  }

  const std::string& Text;
  const std::vector<std::string>& Fields;
  std::size_t At = 0;
  int Depth = 0;
  std::vector<ExpressionNode> Nodes;
  std::vector<Query> Queries;
};

} // namespace

Expression parseExpression(const std::string& text, const std::vector<std::string>& fields)
{
  return Parser(text, fields).parse();
}

} // namespace canopy
