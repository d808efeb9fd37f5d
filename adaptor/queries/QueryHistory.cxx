#include "QueryHistory.h"

#include <limits>

namespace canopy
{

QueryHistory::QueryHistory(std::vector<Query> queries, std::size_t depth)
    : Queries(std::move(queries)), Depth(depth)
{
}

std::size_t QueryHistory::indexOf(const Query& query)
{
  const std::string text = query.text();
  for (std::size_t q = 0; q < Queries.size(); ++q)
  {
    if (Queries[q].text() == text)
    {
      return q;
    }
  }
  Queries.push_back(query);
  return Queries.size() - 1;
}

void QueryHistory::keepAtLeast(std::size_t depth)
{
  Depth = depth > Depth ? depth : Depth;
}

void QueryHistory::record(std::vector<double> values)
{
  Steps.push_front(std::move(values));
  while (Steps.size() > Depth + 1)
  {
    Steps.pop_back();
  }
}

double QueryHistory::value(std::size_t query, std::size_t stepsAgo) const
{
  if (stepsAgo >= Steps.size() || query >= Steps[stepsAgo].size())
  {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return Steps[stepsAgo][query];
}

} // namespace canopy
