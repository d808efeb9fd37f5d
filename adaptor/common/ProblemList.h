// The problems found in a forest description, collected so that they are all
// reported at once (one InvalidForest naming each) instead of one per attempt.
// Used by validateForest (Canopy::forest) and P4estForest (Canopy::p4est).
// Header only.
#pragma once

#include "canopy/ForestValidation.h"

#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace canopy
{

class ProblemList
{
public:
  /// `prefix` starts every message (e.g. "p4est forest: "), empty by default.
  explicit ProblemList(std::string prefix = {}) : Prefix(std::move(prefix)) {}

  /// One problem: the prefix, then `parts` as an ostream writes them.
  template <typename... Parts>
  void add(const Parts&... parts)
  {
    std::ostringstream out;
    out << this->Prefix;
    (out << ... << parts);
    this->Lines.push_back(out.str());
  }

  bool empty() const { return this->Lines.empty(); }

  /// The problems so far; the list is left empty.
  std::vector<std::string> take() { return std::exchange(this->Lines, {}); }

  /// Throws InvalidForest with every problem so far (when going on makes no sense).
  [[noreturn]] void raise() { throw InvalidForest(this->take()); }

  void raiseIfAny()
  {
    if (!this->empty())
    {
      this->raise();
    }
  }

private:
  std::string Prefix;
  std::vector<std::string> Lines;
};

} // namespace canopy
