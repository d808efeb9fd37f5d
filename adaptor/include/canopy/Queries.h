// Queries: numbers about a field the simulation describes, computed on its own
// arrays in place (leaves only, no vtkHyperTreeGrid built), reduced over the
// ranks in one collective for all the queries of a call.
//
//   std::vector<canopy::Query> queries = {canopy::Query::maximum("density"),
//                                         canopy::Query::volume("density", 0.5, 1.0)};
//   auto results = canopy::runQueries(MPI_COMM_WORLD, forest, queries);   // collective
//   results[0].value, results[0].location.centre, results[1].value ...
//
// What counts: the present, visible leaves (not absent, no masked ancestor or self).
// A leaf whose value is NaN or +-Inf is counted by nonFinite() and left out of every
// other query. See docs/queries.md for each query's definition and the tie rule.
#pragma once

#include <canopy/ForestDescription.h>

#include <mpi.h>

#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace canopy
{

enum class QueryKind
{
  Minimum,   ///< smallest finite value, with where it is
  Maximum,   ///< largest finite value, with where it is
  Count,     ///< leaves with low <= value <= high
  Volume,    ///< their volume (area in 2D, length in 1D)
  Sum,       ///< sum of the values (not weighted)
  Mean,      ///< volume-weighted mean: integral / volume of the finite leaves
  Integral,  ///< sum of value * volume
  L2Norm,    ///< sqrt(sum of value^2 * volume)
  Histogram, ///< leaves per bin: `bins` equal bins over [low, high]
  NonFinite, ///< leaves whose value is NaN or +-Inf
  Cells      ///< leaves with a finite value
};

/// One query on one component of one field. Build with the factories.
struct Query
{
  QueryKind kind = QueryKind::Maximum;
  std::string field;
  int component = 0;
  double low = 0.0;  ///< Count, Volume, Histogram
  double high = 0.0; ///< Count, Volume, Histogram
  int bins = 0;      ///< Histogram

  static Query minimum(std::string field, int component = 0);
  static Query maximum(std::string field, int component = 0);
  static Query count(std::string field, double low, double high, int component = 0);
  static Query volume(std::string field, double low, double high, int component = 0);
  static Query sum(std::string field, int component = 0);
  static Query mean(std::string field, int component = 0);
  static Query integral(std::string field, int component = 0);
  static Query l2Norm(std::string field, int component = 0);
  static Query histogram(std::string field, double low, double high, int bins, int component = 0);
  /// `bins` equal bins over the current range of the field's finite values, [min, max]
  /// (a field of one value v: [v - h, v + h] with h = max(1, |v|) / 2; no finite value:
  /// [0, 1]).
  /// The range is found first, by a reduction of its own: a call with such a histogram
  /// costs two collectives instead of one. Its `low` and `high` are NaN until then.
  static Query histogram(std::string field, int bins, int component = 0);

  /// A histogram whose range is the current one (low and high NaN).
  bool overCurrentRange() const;
  static Query nonFinite(std::string field, int component = 0);
  static Query cells(std::string field, int component = 0);

  /// The query as the expression language writes it, e.g. "volume(scalar, 0.5, 1)",
  /// "max(velocity[1])"; the key of StepReport::queries.
  std::string text() const;
};

/// Where a minimum or maximum is: a leaf named independently of the partition by its
/// root cell, level and integer position within the root at that level.
struct CellLocation
{
  int rank = -1;               ///< the rank that holds the leaf (-1: no finite value anywhere)
  std::int64_t rootIndex = -1; ///< root cell, i fastest, then j, then k
  int level = -1;              ///< 0: the root cell itself
  /// Position along x, y, z among the root's branchFactor^level cells per axis at
  /// `level` (0 on flat axes). (rootIndex, level, index) is the leaf's global id.
  std::array<std::int64_t, 3> index{{0, 0, 0}};
  std::array<double, 3> centre{{0.0, 0.0, 0.0}};
};

struct QueryResult
{
  /// The number asked for (Count, NonFinite, Cells: a count, exact below 2^53;
  /// Histogram: the leaves inside [low, high]). NaN when no leaf has a finite value
  /// (Minimum, Maximum, Mean).
  double value = std::numeric_limits<double>::quiet_NaN();
  /// Minimum and Maximum: the leaf (tie rule: the smallest (rootIndex, level, k, j, i)).
  CellLocation location;
  /// Histogram: leaves per bin (bin b holds low + b w <= v < low + (b+1) w, the
  /// last bin also v == high), and outside the range.
  std::vector<std::int64_t> bins;
  std::int64_t below = 0;
  std::int64_t above = 0;
  /// Histogram: the range its bins cover (the one asked, or the current range found).
  double low = std::numeric_limits<double>::quiet_NaN();
  double high = std::numeric_limits<double>::quiet_NaN();
};

/// A query that cannot run: unknown field or component, empty range, no bins, a block
/// forest (not supported yet), an invalid forest on some rank. Thrown by runQueries on
/// every rank alike; what() names the rank(s) and the problem.
class QueryError : public std::invalid_argument
{
public:
  using std::invalid_argument::invalid_argument;
};

/// Runs `queries` on this rank's part of `forest` and reduces them over
/// `communicator` in one collective (MPI_Allgather; two when a histogram is over the
/// current range, whose range is reduced first). Collective: every rank calls it
/// with the same queries. Returns one result per query, in order, the same on every
/// rank (bit for bit). `forest` and its arrays are only read during the call; nothing is
/// kept. Throws QueryError (every rank) if the queries cannot run on some rank.
std::vector<QueryResult> runQueries(MPI_Comm communicator, const ForestDescription& forest,
                                    const std::vector<Query>& queries);

} // namespace canopy
