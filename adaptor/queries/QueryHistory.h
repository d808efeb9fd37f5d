// The values of a set of queries at the last evaluated steps, newest first: what
// prev(), @-k and last() read. Keeps as many steps as the deepest look back needs.
#pragma once

#include <canopy/Queries.h>

#include <cstddef>
#include <deque>
#include <string>
#include <vector>

namespace canopy
{

class QueryHistory
{
public:
  /// `depth`: how many steps before the newest are kept.
  QueryHistory(std::vector<Query> queries, std::size_t depth);

  const std::vector<Query>& queries() const { return Queries; }
  /// Index of the query with `query`'s text; adds it if new (before any record()).
  std::size_t indexOf(const Query& query);
  /// Keeps at least `depth` steps before the newest from now on.
  void keepAtLeast(std::size_t depth);

  /// One evaluated step's values, one per query, in queries() order.
  void record(std::vector<double> values);
  /// Query `query`'s value `stepsAgo` evaluated steps before the newest (0: newest);
  /// NaN when not recorded (before the first steps, or further back than kept).
  double value(std::size_t query, std::size_t stepsAgo) const;
  std::size_t recordedSteps() const { return Steps.size(); }

private:
  std::vector<Query> Queries;
  std::size_t Depth;
  std::deque<std::vector<double>> Steps; ///< newest first
};

} // namespace canopy
