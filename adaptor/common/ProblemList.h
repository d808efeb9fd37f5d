// The problems found in a description, collected so that they are all
// reported at once (one exception naming each: InvalidForest for forests)
// instead of one per attempt. Used by validateForest (Canopy::forest) and
// P4estForest (Canopy::p4est). Header only; it knows no Canopy type (the caller
// names the exception), so that nothing in adaptor/common depends on the layers
// above it.
#pragma once

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

  /// Throws `Error` (constructed from the list of problems) with every problem
  /// so far, when going on makes no sense.
  template <typename Error>
  [[noreturn]] void raise()
  {
    throw Error(this->take());
  }

  template <typename Error>
  void raiseIfAny()
  {
    if (!this->empty())
    {
      this->raise<Error>();
    }
  }

private:
  std::string Prefix;
  std::vector<std::string> Lines;
};

} // namespace canopy
