#include <canopy/Queries.h>

#include "FieldPartial.h"
#include "FieldPass.h"
#include "ForestLayout.h"
#include "LeafGeometry.h"

#include <canopy/ForestValidation.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <utility>

namespace canopy
{
namespace
{

Query make(QueryKind kind, std::string field, int component, double low = 0.0, double high = 0.0,
           int bins = 0)
{
  Query query;
  query.kind = kind;
  query.field = std::move(field);
  query.component = component;
  query.low = low;
  query.high = high;
  query.bins = bins;
  return query;
}

/// The shortest text that reads back as the same double.
std::string number(double value)
{
  char text[40];
  for (int digits = 15; digits <= 17; ++digits)
  {
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value)
    {
      break;
    }
  }
  return text;
}

const char* functionName(QueryKind kind)
{
  switch (kind)
  {
  case QueryKind::Minimum:
    return "min";
  case QueryKind::Maximum:
    return "max";
  case QueryKind::Count:
    return "count";
  case QueryKind::Volume:
    return "volume";
  case QueryKind::Sum:
    return "sum";
  case QueryKind::Mean:
    return "mean";
  case QueryKind::Integral:
    return "integral";
  case QueryKind::L2Norm:
    return "l2";
  case QueryKind::Histogram:
    return "histogram";
  case QueryKind::NonFinite:
    return "nonfinite";
  case QueryKind::Cells:
    return "cells";
  }
  return "?";
}

/// Where each query's answer is: its field request, range and histogram.
struct QueryPlan
{
  std::vector<FieldQuerySet> requests;
  struct Place
  {
    std::size_t request;
    std::size_t range;
    std::size_t histogram;
  };
  std::vector<Place> places;
};

QueryPlan plan(const std::vector<Query>& queries)
{
  QueryPlan plan;
  std::map<std::pair<std::string, int>, std::size_t> known;
  for (const Query& query : queries)
  {
    const auto key = std::make_pair(query.field, query.component);
    auto found = known.find(key);
    if (found == known.end())
    {
      found = known.emplace(key, plan.requests.size()).first;
      plan.requests.push_back({query.field, query.component, {}, {}});
    }
    FieldQuerySet& request = plan.requests[found->second];
    QueryPlan::Place place{found->second, 0, 0};
    if (query.kind == QueryKind::Count || query.kind == QueryKind::Volume)
    {
      place.range = request.ranges.size();
      request.ranges.push_back({{query.low, query.high}});
    }
    else if (query.kind == QueryKind::Histogram)
    {
      place.histogram = request.histograms.size();
      request.histograms.push_back({query.low, query.high, query.bins});
    }
    plan.places.push_back(place);
  }
  return plan;
}

std::string checkQuery(const Query& query)
{
  const std::string name = "'" + query.text() + "'";
  if (query.component < 0)
  {
    return name + ": negative component";
  }
  if ((query.kind == QueryKind::Count || query.kind == QueryKind::Volume) &&
      !(query.low <= query.high))
  {
    return name + ": the range's low end is above its high end (or NaN)";
  }
  if (query.kind == QueryKind::Histogram)
  {
    if (query.bins < 1)
    {
      return name + ": a histogram needs at least one bin";
    }
    if (!(query.low < query.high) || !std::isfinite(query.high - query.low))
    {
      return name + ": a histogram needs finite low < high";
    }
  }
  return {};
}

/// Tuple index of a leaf in a LeavesOnly field with a slot map: leaves ordered by slot.
std::vector<std::size_t> leafOrdinalsBySlot(const ForestDescription& forest,
                                            const ForestLayout& layout)
{
  std::vector<std::size_t> ordinal(layout.totalPresentNodes, 0);
  std::vector<std::uint8_t> isLeaf(layout.totalPresentNodes, 0);
  for (const TreeDescription& tree : forest.trees)
  {
    for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
    {
      if (!tree.refinement[n] && !(tree.absent && tree.absent[n]))
      {
        isLeaf[static_cast<std::size_t>(tree.storageSlots[n])] = 1;
      }
    }
  }
  std::size_t next = 0;
  for (std::size_t s = 0; s < ordinal.size(); ++s)
  {
    ordinal[s] = next;
    next += isLeaf[s];
  }
  return ordinal;
}

/// This rank's shares, or the reason it has none.
std::string localShares(const ForestDescription& forest, const std::vector<Query>& queries,
                        const QueryPlan& plan, int rank, std::vector<FieldPartial>& partials)
{
  for (const Query& query : queries)
  {
    const std::string problem = checkQuery(query);
    if (!problem.empty())
    {
      return problem;
    }
  }
  if (forest.blockCellsPerSide != 0)
  {
    return "queries on block forests are not supported";
  }
  ForestLayout layout;
  try
  {
    layout = layoutForest(forest);
  }
  catch (const InvalidForest& error)
  {
    std::string text = "invalid forest:";
    for (const auto& problem : error.problems())
    {
      text += " " + problem + ";";
    }
    return text;
  }
  std::vector<const FieldDescription*> fields;
  for (const FieldQuerySet& request : plan.requests)
  {
    const FieldDescription* found = nullptr;
    for (const FieldDescription& field : forest.fields)
    {
      found = field.name == request.field ? &field : found;
    }
    if (found == nullptr)
    {
      return "no field '" + request.field + "' in the forest";
    }
    if (request.component >= found->components)
    {
      return "field '" + request.field + "' has " + std::to_string(found->components) +
             " component(s), component " + std::to_string(request.component) + " asked for";
    }
    fields.push_back(found);
  }
  const LeafGeometry geometry(forest);
  std::vector<std::size_t> ordinalOfSlot;
  std::vector<WalkParent> scratch;
  for (std::size_t r = 0; r < plan.requests.size(); ++r)
  {
    const FieldDescription& field = *fields[r];
    if (layout.explicitSlots && field.centering == Centering::LeavesOnly && ordinalOfSlot.empty())
    {
      ordinalOfSlot = leafOrdinalsBySlot(forest, layout);
    }
    const int component = plan.requests[r].component;
    FieldPartial& partial = partials[r];
    switch (field.type)
    {
    case ValueType::Float32:
      passOverField<float>(forest, geometry, field, component, plan.requests[r], ordinalOfSlot,
                           rank, scratch, partial);
      break;
    case ValueType::Float64:
      passOverField<double>(forest, geometry, field, component, plan.requests[r], ordinalOfSlot,
                            rank, scratch, partial);
      break;
    case ValueType::Int32:
      passOverField<std::int32_t>(forest, geometry, field, component, plan.requests[r],
                                  ordinalOfSlot, rank, scratch, partial);
      break;
    case ValueType::Int64:
      passOverField<std::int64_t>(forest, geometry, field, component, plan.requests[r],
                                  ordinalOfSlot, rank, scratch, partial);
      break;
    }
  }
  return {};
}

} // namespace

Query Query::minimum(std::string field, int component)
{
  return make(QueryKind::Minimum, std::move(field), component);
}
Query Query::maximum(std::string field, int component)
{
  return make(QueryKind::Maximum, std::move(field), component);
}
Query Query::count(std::string field, double low, double high, int component)
{
  return make(QueryKind::Count, std::move(field), component, low, high);
}
Query Query::volume(std::string field, double low, double high, int component)
{
  return make(QueryKind::Volume, std::move(field), component, low, high);
}
Query Query::sum(std::string field, int component)
{
  return make(QueryKind::Sum, std::move(field), component);
}
Query Query::mean(std::string field, int component)
{
  return make(QueryKind::Mean, std::move(field), component);
}
Query Query::integral(std::string field, int component)
{
  return make(QueryKind::Integral, std::move(field), component);
}
Query Query::l2Norm(std::string field, int component)
{
  return make(QueryKind::L2Norm, std::move(field), component);
}
Query Query::histogram(std::string field, double low, double high, int bins, int component)
{
  return make(QueryKind::Histogram, std::move(field), component, low, high, bins);
}
Query Query::histogram(std::string field, int bins, int component)
{
  const double unknown = std::numeric_limits<double>::quiet_NaN();
  return make(QueryKind::Histogram, std::move(field), component, unknown, unknown, bins);
}
bool Query::overCurrentRange() const
{
  return this->kind == QueryKind::Histogram && std::isnan(this->low) && std::isnan(this->high);
}
Query Query::nonFinite(std::string field, int component)
{
  return make(QueryKind::NonFinite, std::move(field), component);
}
Query Query::cells(std::string field, int component)
{
  return make(QueryKind::Cells, std::move(field), component);
}

std::string Query::text() const
{
  std::string text = std::string(functionName(this->kind)) + "(" + this->field;
  if (this->component != 0)
  {
    text += "[" + std::to_string(this->component) + "]";
  }
  if (this->kind == QueryKind::Count || this->kind == QueryKind::Volume ||
      (this->kind == QueryKind::Histogram && !this->overCurrentRange()))
  {
    text += ", " + number(this->low) + ", " + number(this->high);
  }
  if (this->kind == QueryKind::Histogram)
  {
    text += ", " + std::to_string(this->bins);
  }
  return text + ")";
}

namespace
{
/// The queries with every histogram over the current range given that range, found by
/// one reduction of the fields' minima and maxima (collective; none without such a
/// histogram).
std::vector<Query> withCurrentRanges(MPI_Comm communicator, const ForestDescription& forest,
                                     std::vector<Query> queries);
} // namespace

std::vector<QueryResult> runQueries(MPI_Comm communicator, const ForestDescription& forest,
                                    const std::vector<Query>& asked)
{
  const std::vector<Query> queries = withCurrentRanges(communicator, forest, asked);
  int rank = 0;
  int ranks = 1;
  MPI_Comm_rank(communicator, &rank);
  MPI_Comm_size(communicator, &ranks);
  const QueryPlan queryPlan = plan(queries);
  std::vector<FieldPartial> partials;
  std::size_t int64Words = 1; // the rank's status: 0 ok, 1 failed
  std::size_t doubleWords = 0;
  for (const FieldQuerySet& request : queryPlan.requests)
  {
    partials.emplace_back(request);
    int64Words += request.int64Words();
    doubleWords += request.doubleWords();
  }
  std::string problem;
  try
  {
    problem = localShares(forest, queries, queryPlan, rank, partials);
  }
  catch (const std::exception& error)
  {
    problem = error.what();
  }

  // Every share in one buffer: int64 words, then double words; one collective.
  const std::size_t bytes = int64Words * sizeof(std::int64_t) + doubleWords * sizeof(double);
  std::vector<std::int64_t> int64s(int64Words, 0);
  std::vector<double> doubles(doubleWords, 0.0);
  int64s[0] = problem.empty() ? 0 : 1;
  if (problem.empty())
  {
    std::int64_t* i = int64s.data() + 1;
    double* d = doubles.data();
    for (const FieldPartial& partial : partials)
    {
      partial.pack(i, d);
    }
  }
  std::vector<unsigned char> mine(bytes);
  std::memcpy(mine.data(), int64s.data(), int64Words * sizeof(std::int64_t));
  if (doubleWords > 0)
  {
    std::memcpy(mine.data() + int64Words * sizeof(std::int64_t), doubles.data(),
                doubleWords * sizeof(double));
  }
  std::vector<unsigned char> all(bytes * static_cast<std::size_t>(ranks));
  MPI_Allgather(mine.data(), static_cast<int>(bytes), MPI_BYTE, all.data(), static_cast<int>(bytes),
                MPI_BYTE, communicator);

  std::vector<FieldPartial> total;
  std::string failedRanks;
  for (int r = 0; r < ranks; ++r)
  {
    const unsigned char* share = all.data() + bytes * static_cast<std::size_t>(r);
    std::memcpy(int64s.data(), share, int64Words * sizeof(std::int64_t));
    if (doubleWords > 0)
    {
      std::memcpy(doubles.data(), share + int64Words * sizeof(std::int64_t),
                  doubleWords * sizeof(double));
    }
    if (int64s[0] != 0)
    {
      failedRanks += (failedRanks.empty() ? "" : ", ") + std::to_string(r);
      continue;
    }
    const std::int64_t* i = int64s.data() + 1;
    const double* d = doubles.data();
    for (std::size_t p = 0; p < partials.size(); ++p)
    {
      FieldPartial share(queryPlan.requests[p]);
      share.unpack(i, d);
      if (total.size() < partials.size())
      {
        total.push_back(share);
      }
      else
      {
        total[p].merge(share);
      }
    }
  }
  if (!failedRanks.empty())
  {
    throw QueryError(
        "canopy::runQueries: the queries failed on rank(s) " + failedRanks +
        (problem.empty() ? std::string() : "; on rank " + std::to_string(rank) + ": " + problem));
  }
  std::vector<QueryResult> results;
  results.reserve(queries.size());
  for (std::size_t q = 0; q < queries.size(); ++q)
  {
    const QueryPlan::Place& place = queryPlan.places[q];
    results.push_back(total[place.request].result(queries[q], place.range, place.histogram));
    if (queries[q].kind == QueryKind::Histogram)
    {
      results.back().low = queries[q].low;
      results.back().high = queries[q].high;
    }
  }
  return results;
}

namespace
{
std::vector<Query> withCurrentRanges(MPI_Comm communicator, const ForestDescription& forest,
                                     std::vector<Query> queries)
{
  std::vector<Query> extremes;
  for (const Query& query : queries)
  {
    if (query.overCurrentRange())
    {
      extremes.push_back(Query::minimum(query.field, query.component));
      extremes.push_back(Query::maximum(query.field, query.component));
    }
  }
  if (extremes.empty())
  {
    return queries;
  }
  // Every rank has the same queries, so every rank makes this call: the first collective.
  const std::vector<QueryResult> found = runQueries(communicator, forest, extremes);
  std::size_t next = 0;
  for (Query& query : queries)
  {
    if (!query.overCurrentRange())
    {
      continue;
    }
    const double low = found[next].value;
    const double high = found[next + 1].value;
    next += 2;
    if (std::isnan(low))
    {
      query.low = 0.0; // no finite value anywhere: every bin empty
      query.high = 1.0;
    }
    else if (low == high)
    {
      const double half = std::max(1.0, std::abs(low)) / 2;
      query.low = low - half;
      query.high = low + half;
    }
    else
    {
      query.low = low;
      query.high = high;
    }
  }
  return queries;
}

} // namespace

} // namespace canopy
