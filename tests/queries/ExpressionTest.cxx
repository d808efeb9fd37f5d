// The expression language: what valid expressions evaluate to from a history of
// query values, the exact message of each kind of refusal, and a fuzz loop
// (random texts and mutations of valid ones): never a crash, never a hang, every
// refusal an ExpressionError with a position inside the text (or just after it).
#include "ExpressionParser.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <map>
#include <random>

namespace
{

using namespace canopy;

const std::vector<std::string> fields = {"scalar", "velocity", "level"};

/// A history where query q's value k steps ago is table[text][k] (NaN past its end).
ExpressionHistory historyOf(const Expression& expression,
                            const std::map<std::string, std::vector<double>>& table,
                            long long lastFiring = -1)
{
  ExpressionHistory history;
  history.value = [&expression, &table](std::size_t query, std::size_t ago)
  {
    const auto& values = table.at(expression.queries().at(query).text());
    return ago < values.size() ? values[ago] : std::nan("");
  };
  if (lastFiring >= 0)
  {
    history.atLastFiring = [&expression, &table, lastFiring](std::size_t query)
    {
      return table.at(expression.queries().at(query).text())
          .at(static_cast<std::size_t>(lastFiring));
    };
  }
  return history;
}

double evaluate(const std::string& text, const std::map<std::string, std::vector<double>>& table,
                long long lastFiring = -1)
{
  const Expression expression = parseExpression(text, fields);
  return expression.evaluate(historyOf(expression, table, lastFiring));
}

TEST(Expression, ValidExpressionsEvaluateAsArithmeticAndLogicSay)
{
  const std::map<std::string, std::vector<double>> table = {
      {"max(scalar)", {0.95, 0.85, 0.5}},
      {"volume(scalar, 0.5, 1)", {2.5, 2.0, 1.0}},
      {"min(velocity[2])", {-3.0}},
      {"count(level, 2, 3)", {12, 12}}};
  EXPECT_EQ(evaluate("max(scalar) > 0.9", table), 1.0);
  EXPECT_EQ(evaluate("max(scalar)@-1 > 0.9", table), 0.0);
  EXPECT_EQ(evaluate("prev(max(scalar))", table), 0.85);
  EXPECT_EQ(evaluate("prev(prev(max(scalar)))", table), 0.5);
  EXPECT_EQ(evaluate("max(scalar)@-2", table), 0.5);
  EXPECT_TRUE(std::isnan(evaluate("max(scalar)@-3", table))); // before the history
  EXPECT_EQ(evaluate("volume(scalar, 0.5, 1) > 1.2 * prev(volume(scalar, 0.5, 1))", table), 1.0);
  EXPECT_EQ(evaluate("volume(scalar,0.5,1.0)@-1 > 1.2 * volume(scalar, 5e-1, 1)@-2", table), 1.0);
  EXPECT_EQ(evaluate("1 + 2 * 3 - 4 / 2", table), 5.0);
  EXPECT_EQ(evaluate("(1 + 2) * 3", table), 9.0);
  EXPECT_EQ(evaluate("-min(velocity[2]) == 3", table), 1.0);
  EXPECT_EQ(evaluate("abs(min(velocity[2]))", table), 3.0);
  EXPECT_EQ(evaluate("not max(scalar) > 0.9 or count(level, 2, 3) >= 12", table), 1.0);
  EXPECT_EQ(evaluate("not (max(scalar) > 0.9 or count(level, 2, 3) >= 12)", table), 0.0);
  EXPECT_EQ(evaluate("max(scalar) > 0.9 and count(level, 2, 3) != 12", table), 0.0);
  EXPECT_EQ(evaluate("1 < 2 and 2 <= 2 and 3 >= 3 and 4 > 3 and 5 == 5", table), 1.0);
  EXPECT_EQ(evaluate("count(level, 2, 3) == prev(count(level, 2, 3))", table), 1.0);
  // A comparison with NaN is false, != included; NaN is not true, and "not NaN" is.
  EXPECT_EQ(evaluate("max(scalar)@-5 != 1", table), 0.0);
  EXPECT_EQ(evaluate("max(scalar)@-5 or 0", table), 0.0);
  EXPECT_EQ(evaluate("not max(scalar)@-5", table), 1.0);
  // last(): at the step the trigger last fired; NaN before it ever fired.
  EXPECT_EQ(evaluate("max(scalar) - last(max(scalar))", table, 2), 0.95 - 0.5);
  EXPECT_TRUE(std::isnan(evaluate("last(max(scalar))", table)));
}

TEST(Expression, QueriesAreCollectedOnceAndHistoryDepthIsTheFurthestBack)
{
  const Expression e = parseExpression(
      "max(scalar) > prev(max(scalar)) and volume(scalar, 0.5, 1)@-3 < prev(volume(scalar, "
      "0.5, 1.0)@-2) + cells(level)",
      fields);
  ASSERT_EQ(e.queries().size(), 3u);
  EXPECT_EQ(e.queries()[0].text(), "max(scalar)");
  EXPECT_EQ(e.queries()[1].text(), "volume(scalar, 0.5, 1)");
  EXPECT_EQ(e.queries()[1].kind, QueryKind::Volume);
  EXPECT_EQ(e.queries()[1].low, 0.5);
  EXPECT_EQ(e.queries()[1].high, 1.0);
  EXPECT_EQ(e.queries()[2].text(), "cells(level)");
  EXPECT_EQ(e.historyDepth(), 3u);
  EXPECT_EQ(parseExpression("1 > 0", fields).historyDepth(), 0u);
  EXPECT_EQ(parseExpression("prev(prev(max(scalar))@-4)", fields).historyDepth(), 6u);
  // Any field name is taken when the simulation's fields are not known.
  EXPECT_EQ(parseExpression("max(anything[2]) > 0", {}).queries()[0].text(), "max(anything[2])");
}

std::string refusal(const std::string& text)
{
  try
  {
    parseExpression(text, fields);
  }
  catch (const ExpressionError& error)
  {
    return error.what();
  }
  return "accepted";
}

TEST(Expression, RefusalsNameTheCharacterAndWhatWasExpected)
{
  EXPECT_EQ(refusal(""), "at character 1: expected an expression, found the end of the text");
  EXPECT_EQ(refusal("   "), "at character 4: expected an expression, found the end of the text");
  EXPECT_EQ(refusal("maxx(scalar) > 1"),
            "at character 1: unknown function 'maxx' (expected one of: min, max, sum, mean, "
            "integral, l2, nonfinite, cells, count, volume, prev, last, abs)");
  EXPECT_EQ(refusal("max(pressure) > 1"),
            "at character 5: unknown field 'pressure' (fields: scalar, velocity, level)");
  EXPECT_EQ(refusal("volume(scalar) > 1"),
            "at character 1: 'volume' takes 3 arguments (field, low, high), found 1");
  EXPECT_EQ(refusal("1 + volume(scalar, 0.5)"),
            "at character 5: 'volume' takes 3 arguments (field, low, high), found 2");
  EXPECT_EQ(refusal("max(scalar, 1)"),
            "at character 1: 'max' takes 1 argument (a field), found more");
  EXPECT_EQ(refusal("max()"), "at character 1: 'max' takes 1 argument (a field), found none");
  EXPECT_EQ(refusal("prev(1, 2)"), "at character 1: 'prev' takes 1 argument, found more");
  EXPECT_EQ(refusal("max(scalar) >"),
            "at character 14: expected a number, a query or '(', found the end of the text");
  EXPECT_EQ(refusal("(max(scalar) > 1"),
            "at character 17: expected ')', found the end of the text");
  EXPECT_EQ(refusal("max(scalar) 1"),
            "at character 13: expected an operator or the end of the expression, found '1'");
  EXPECT_EQ(refusal("max scalar"), "at character 5: expected '(' after 'max', found 'scalar'");
  EXPECT_EQ(refusal("max(1)"), "at character 5: expected a field name, found '1'");
  EXPECT_EQ(refusal("max(scalar)@1"),
            "at character 13: expected '-' after '@' (q@-k: k evaluated steps ago), found '1'");
  EXPECT_EQ(refusal("max(scalar)@-0"),
            "at character 15: expected a number of steps from 1 to 1000 after '@-'");
  EXPECT_EQ(refusal("max(scalar)@-x"),
            "at character 14: expected a whole number of steps after '@-', found 'x'");
  EXPECT_EQ(refusal("volume(scalar, 1, 0.5)"),
            "at character 1: 'volume': the range's low end is above its high end");
  EXPECT_EQ(refusal("count(scalar, inf, 1)"),
            "at character 15: expected the range's low end, found 'inf'");
  EXPECT_EQ(refusal("count(scalar, 0x1, 2)"),
            "at character 15: expected the range's low end (a decimal number), found '0x1'");
  EXPECT_EQ(refusal("1 < 2 < 3"),
            "at character 7: comparisons do not chain: use 'and' between two comparisons");
  EXPECT_EQ(refusal("max(scalar) > 1 $"),
            "at character 17: expected an operator or the end of the expression, found '$'");
  EXPECT_EQ(refusal("max(velocity[x])"), "at character 14: expected a component number, found 'x'");
  EXPECT_EQ(refusal(std::string(70, '(') + "1" + std::string(70, ')')),
            "at character 65: nested deeper than 64 levels");
  EXPECT_EQ(refusal(std::string(64, '(') + "1" + std::string(64, ')')), "accepted");
  EXPECT_EQ(refusal(std::string(65, '-') + "1"), "at character 65: nested deeper than 64 levels");
  EXPECT_EQ(refusal(std::string(5000, '1')),
            "at character 4097: the expression is longer than 4096 characters");
  EXPECT_EQ(refusal("max(scalar) > 1e999"),
            "at character 15: expected a number (a finite decimal number), found '1e999'");
}

TEST(Expression, FuzzedTextsNeverCrashOrHang)
{
  const std::vector<std::string> valid = {
      "max(scalar) > 0.9", "volume(scalar, 0.5, 1) > 1.2 * prev(volume(scalar, 0.5, 1))",
      "not (min(velocity[1]) < -2 or count(level, 2, 3)@-2 >= 10) and abs(sum(scalar)) != 0",
      "mean(scalar) - last(mean(scalar)) > 0.1 * l2(scalar) / cells(scalar)",
      "integral(level) <= nonfinite(scalar) + prev(prev(max(level)))@-3"};
  const std::string alphabet = "()[],.@-+*/<>=! 0123456789eaxmnotrdvlu_sc\t\x01\xff";
  std::mt19937_64 random(12345);
  const auto started = std::chrono::steady_clock::now();
  std::size_t accepted = 0;
  std::size_t refused = 0;
  for (int round = 0; round < 20000; ++round)
  {
    std::string text;
    if (round % 2 == 0)
    {
      const std::size_t length = random() % 60;
      for (std::size_t i = 0; i < length; ++i)
      {
        text += alphabet[random() % alphabet.size()];
      }
    }
    else
    {
      text = valid[random() % valid.size()];
      const int edits = 1 + static_cast<int>(random() % 4);
      for (int e = 0; e < edits && !text.empty(); ++e)
      {
        const std::size_t at = random() % text.size();
        switch (random() % 4)
        {
        case 0:
          text.erase(at, 1 + random() % 3);
          break;
        case 1:
          text.insert(at, 1, alphabet[random() % alphabet.size()]);
          break;
        case 2:
          text[at] = alphabet[random() % alphabet.size()];
          break;
        default:
          text.insert(at, text.substr(random() % text.size(), random() % 12)); // duplicate
        }
      }
    }
    try
    {
      const Expression expression = parseExpression(text, fields);
      ExpressionHistory history;
      history.value = [](std::size_t q, std::size_t ago)
      { return static_cast<double>(q) - static_cast<double>(ago) * 0.5; };
      expression.evaluate(history);
      ++accepted;
    }
    catch (const ExpressionError& error)
    {
      ++refused;
      EXPECT_GE(error.position(), 1u) << text;
      EXPECT_LE(error.position(), text.size() + 1) << text << ": " << error.what();
      EXPECT_EQ(std::string(error.what())
                    .rfind("at character " + std::to_string(error.position()) + ": ", 0),
                0u);
    }
  }
  EXPECT_GT(accepted, 100u); // the mutations keep some valid
  EXPECT_GT(refused, 10000u);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(),
            20.0);
}

} // namespace
