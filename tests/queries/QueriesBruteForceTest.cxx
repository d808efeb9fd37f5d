// Every query against a brute force over the whole forest's leaves, on random
// forests (masks, holes in the root grid, trees split between ranks with the
// other ranks' parts absent, breadth-first and depth-first storage, 1D to 3D,
// binary and ternary), at whatever number of ranks the test runs on: the same
// results on every rank, minimum and maximum at the leaf the tie rule names,
// exactly one MPI call per runQueries.
//
// The oracle shares no code with the queries: leaves, levels and positions come
// from RandomForest's own node table, centres and volumes from the bounds VTK's
// geometry cursor gives on the grid built from the whole forest.
#include "CountedCollectives.h"
#include "HtgWalk.h"
#include "RandomForest.h"
#include "RankPart.h"

#include <canopy/HtgBuilder.h>
#include <canopy/Queries.h>

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <tuple>

namespace
{

using namespace canopy;
using namespace canopy::testing;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double inf = std::numeric_limits<double>::infinity();

int worldRank()
{
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

int worldSize()
{
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

/// A second hash per node, for the non-finite values.
double otherHash(std::size_t tree, std::size_t node)
{
  return wholeHash(tree + 100003, node * 7 + 3);
}

/// The fields every node of the whole forest has, by name and component.
double fieldValue(const std::string& field, int component, std::size_t tree, std::size_t node)
{
  const double h = wholeHash(tree, node);
  const double g = otherHash(tree, node);
  if (field == "tied") // 1/16 steps: many ties, values on range and bin edges
  {
    return g < 0.03 ? nan : g < 0.05 ? inf : g < 0.06 ? -inf : std::floor(h * 16) / 16;
  }
  if (field == "leafy") // leaves only, fine steps, a few NaN
  {
    return g < 0.04 ? nan : std::floor(h * 64) / 64 - 0.5;
  }
  if (field == "vector") // float, 3 components
  {
    return static_cast<double>(static_cast<float>(h * (component + 1)));
  }
  return static_cast<double>(static_cast<std::int32_t>(h * 5)); // "count", int32: all ties
}

struct Case
{
  int dimension;
  int branchFactor;
  double maskProbability;
  bool depthFirst;
  bool holes;
  std::uint64_t seed;
};

std::string caseName(const ::testing::TestParamInfo<Case>& info)
{
  const Case& c = info.param;
  return std::to_string(c.dimension) + "D_b" + std::to_string(c.branchFactor) +
         (c.maskProbability > 0 ? "_masked" : "") + (c.depthFirst ? "_depthFirst" : "") +
         (c.holes ? "_holes" : "") + "_seed" + std::to_string(c.seed);
}

/// A leaf of the whole forest as the oracle sees it.
struct OracleLeaf
{
  std::size_t tree;
  std::size_t node;
  std::int64_t rootIndex;
  int level;
  std::array<std::int64_t, 3> index;
  std::array<double, 3> centre;
  double volume;
};

std::vector<OracleLeaf> visibleLeaves(RandomForest& whole, int dimension, int flatAxis)
{
  const ForestDescription& description = whole.description();
  auto grid = buildHyperTreeGrid(description, FieldRequest::none());
  std::vector<int> axes;
  for (int a = 0; a < 3; ++a)
  {
    if ((dimension == 2 && a != flatAxis) || dimension == 3 || (dimension == 1 && a == 0))
    {
      axes.push_back(a);
    }
  }
  const auto b = static_cast<std::int64_t>(description.branchFactor);
  std::vector<OracleLeaf> leaves;
  for (std::size_t t = 0; t < description.trees.size(); ++t)
  {
    const auto& nodes = whole.nodes()[t];
    // Positions from the node table: a child's digit per axis, x fastest.
    std::vector<std::array<std::int64_t, 3>> index(nodes.size(), {{0, 0, 0}});
    for (std::size_t n = 1; n < nodes.size(); ++n)
    {
      index[n] = index[static_cast<std::size_t>(nodes[n].parent)];
      int digits = nodes[n].childIndex;
      for (int a : axes)
      {
        index[n][static_cast<std::size_t>(a)] =
            index[n][static_cast<std::size_t>(a)] * b + digits % b;
        digits /= static_cast<int>(b);
      }
    }
    forEachNode(
        grid, description.trees[t].rootIndex, whole.refinement()[t], whole.childrenPerNode(),
        [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor, std::size_t n)
        {
          if (!cursor->IsLeaf() || cursor->IsMasked())
          {
            return;
          }
          double bounds[6];
          cursor->GetBounds(bounds);
          OracleLeaf leaf{t,           n,  description.trees[t].rootIndex, nodes[n].level, index[n],
                          {{0, 0, 0}}, 1.0};
          for (int a = 0; a < 3; ++a)
          {
            leaf.centre[static_cast<std::size_t>(a)] = 0.5 * (bounds[2 * a] + bounds[2 * a + 1]);
          }
          for (int a : axes)
          {
            leaf.volume *= bounds[2 * a + 1] - bounds[2 * a];
          }
          leaves.push_back(leaf);
        });
  }
  return leaves;
}

/// This rank's part with the test's fields, stored as the part's slots say.
struct RankFields
{
  std::vector<double> tied;
  std::vector<double> leafy;
  std::vector<float> vector;
  std::vector<std::int32_t> count;
  std::vector<std::vector<std::uint8_t>> masks;
  /// (whole tree, whole node) of each present visible-or-not leaf of this rank.
  std::vector<std::pair<std::size_t, std::size_t>> leaves;

  RankFields(RankPart& part, const RandomForest& whole)
  {
    std::vector<std::pair<std::int64_t, std::pair<std::size_t, std::size_t>>> leafSlots;
    std::vector<std::pair<std::size_t, std::size_t>> nodeAtSlot;
    std::int64_t next = 0;
    for (std::size_t t = 0; t < part.trees.size(); ++t)
    {
      const PartitionedTree& tree = part.trees[t];
      for (std::size_t n = 0; n < tree.refinement.size(); ++n)
      {
        if (tree.absent[n])
        {
          continue;
        }
        const std::int64_t slot =
            part.slots.empty() || part.description.trees[t].storageSlots == nullptr
                ? next
                : part.slots[t][n];
        ++next;
        const auto whole = std::make_pair(tree.wholeTree, tree.wholeNode[n]);
        if (nodeAtSlot.size() <= static_cast<std::size_t>(slot))
        {
          nodeAtSlot.resize(static_cast<std::size_t>(slot) + 1);
        }
        nodeAtSlot[static_cast<std::size_t>(slot)] = whole;
        if (!tree.refinement[n])
        {
          leafSlots.push_back({slot, whole});
          leaves.push_back(whole);
        }
      }
      // The whole forest's mask, on this rank's nodes.
      const auto& wholeMask = whole.masked()[tree.wholeTree];
      std::vector<std::uint8_t> mask(tree.refinement.size(), 0);
      for (std::size_t n = 0; n < mask.size(); ++n)
      {
        mask[n] = wholeMask.empty() ? 0 : wholeMask[tree.wholeNode[n]];
      }
      masks.push_back(std::move(mask));
    }
    std::sort(leafSlots.begin(), leafSlots.end());
    for (const auto& [t, n] : nodeAtSlot)
    {
      tied.push_back(fieldValue("tied", 0, t, n));
      for (int c = 0; c < 3; ++c)
      {
        vector.push_back(static_cast<float>(fieldValue("vector", c, t, n)));
      }
      count.push_back(static_cast<std::int32_t>(fieldValue("count", 0, t, n)));
    }
    for (const auto& [slot, whole] : leafSlots)
    {
      leafy.push_back(fieldValue("leafy", 0, whole.first, whole.second));
    }
    ForestDescription& d = part.description;
    for (std::size_t t = 0; t < d.trees.size(); ++t)
    {
      d.trees[t].masked = masks[t].data();
    }
    d.fields.push_back(FieldDescription::aos("tied", tied.data(), tied.size()));
    d.fields.push_back(
        FieldDescription::aos("leafy", leafy.data(), leafy.size(), 1, Centering::LeavesOnly));
    d.fields.push_back(FieldDescription::aos("vector", vector.data(), count.size(), 3));
    d.fields.push_back(FieldDescription::aos("count", count.data(), count.size()));
  }
};

struct Asked
{
  std::string field;
  int component;
  std::array<double, 2> range;
  std::array<double, 3> histogram; // low, high, bins
};

const std::vector<Asked> asked = {{"tied", 0, {{0.25, 0.5}}, {{0.0, 0.5, 8}}},
                                  {"leafy", 0, {{-0.25, 0.125}}, {{-0.5, 0.5, 5}}},
                                  {"vector", 1, {{0.5, 1.5}}, {{0.0, 2.0, 7}}},
                                  {"count", 0, {{1, 3}}, {{0, 4, 4}}}};

std::vector<Query> queriesFor(const Asked& a)
{
  const std::string& f = a.field;
  const int c = a.component;
  return {Query::minimum(f, c),
          Query::maximum(f, c),
          Query::count(f, a.range[0], a.range[1], c),
          Query::volume(f, a.range[0], a.range[1], c),
          Query::count(f, a.range[1], a.range[1], c), // a point range
          Query::sum(f, c),
          Query::mean(f, c),
          Query::integral(f, c),
          Query::l2Norm(f, c),
          Query::histogram(f, a.histogram[0], a.histogram[1], static_cast<int>(a.histogram[2]), c),
          Query::nonFinite(f, c),
          Query::cells(f, c)};
}

/// The brute-force answer to `query` over `leaves`.
QueryResult expected(const Query& query, const std::vector<OracleLeaf>& leaves)
{
  QueryResult result;
  std::vector<const OracleLeaf*> finite;
  std::int64_t nonFinite = 0;
  for (const OracleLeaf& leaf : leaves)
  {
    const double v = fieldValue(query.field, query.component, leaf.tree, leaf.node);
    if (std::isfinite(v))
    {
      finite.push_back(&leaf);
    }
    else
    {
      ++nonFinite;
    }
  }
  auto value = [&](const OracleLeaf* leaf)
  { return fieldValue(query.field, query.component, leaf->tree, leaf->node); };
  // The tie rule: the leaf first in its root's breadth-first order (the whole tree's
  // node numbers are that order: level by level, each level in child order).
  auto key = [&](const OracleLeaf* leaf) { return std::make_pair(leaf->rootIndex, leaf->node); };
  double sum = 0, volume = 0, integral = 0, squares = 0;
  for (const OracleLeaf* leaf : finite)
  {
    sum += value(leaf);
    volume += leaf->volume;
    integral += value(leaf) * leaf->volume;
    squares += value(leaf) * value(leaf) * leaf->volume;
  }
  switch (query.kind)
  {
  case QueryKind::Minimum:
  case QueryKind::Maximum:
  {
    const bool maximum = query.kind == QueryKind::Maximum;
    const OracleLeaf* best = nullptr;
    for (const OracleLeaf* leaf : finite)
    {
      if (best == nullptr || (maximum ? value(leaf) > value(best) : value(leaf) < value(best)) ||
          (value(leaf) == value(best) && key(leaf) < key(best)))
      {
        best = leaf;
      }
    }
    if (best)
    {
      result.value = value(best);
      result.location.rootIndex = best->rootIndex;
      result.location.level = best->level;
      result.location.index = best->index;
      result.location.centre = best->centre;
      result.location.rank = static_cast<int>(best - leaves.data()); // the leaf, for the rank check
    }
    break;
  }
  case QueryKind::Count:
  case QueryKind::Volume:
  {
    double c = 0, v = 0;
    for (const OracleLeaf* leaf : finite)
    {
      if (query.low <= value(leaf) && value(leaf) <= query.high)
      {
        c += 1;
        v += leaf->volume;
      }
    }
    result.value = query.kind == QueryKind::Count ? c : v;
    break;
  }
  case QueryKind::Sum:
    result.value = sum;
    break;
  case QueryKind::Mean:
    result.value = finite.empty() ? nan : integral / volume;
    break;
  case QueryKind::Integral:
    result.value = integral;
    break;
  case QueryKind::L2Norm:
    result.value = std::sqrt(squares);
    break;
  case QueryKind::Histogram:
  {
    result.bins.assign(static_cast<std::size_t>(query.bins), 0);
    for (const OracleLeaf* leaf : finite)
    {
      const double v = value(leaf);
      if (v < query.low)
      {
        ++result.below;
      }
      else if (v > query.high)
      {
        ++result.above;
      }
      else
      {
        const double width = (query.high - query.low) / query.bins;
        int bin = 0;
        while (bin + 1 < query.bins && v >= query.low + (bin + 1) * width)
        {
          ++bin;
        }
        ++result.bins[static_cast<std::size_t>(bin)];
      }
    }
    std::int64_t inside = 0;
    for (auto c : result.bins)
    {
      inside += c;
    }
    result.value = static_cast<double>(inside);
    break;
  }
  case QueryKind::NonFinite:
    result.value = static_cast<double>(nonFinite);
    break;
  case QueryKind::Cells:
    result.value = static_cast<double>(finite.size());
    break;
  }
  return result;
}

/// A fingerprint of every bit of the results, to compare ranks.
std::uint64_t fingerprint(const std::vector<QueryResult>& results)
{
  std::string bytes;
  auto put = [&](const void* data, std::size_t size)
  { bytes.append(static_cast<const char*>(data), size); };
  for (const QueryResult& r : results)
  {
    put(&r.value, sizeof r.value);
    put(&r.location.rank, sizeof r.location.rank);
    put(&r.location.rootIndex, sizeof r.location.rootIndex);
    put(&r.location.level, sizeof r.location.level);
    put(r.location.index.data(), sizeof r.location.index);
    put(r.location.centre.data(), sizeof r.location.centre);
    put(r.bins.data(), r.bins.size() * sizeof(std::int64_t));
    put(&r.below, sizeof r.below);
    put(&r.above, sizeof r.above);
  }
  return checksum(bytes.data(), bytes.size());
}

bool sameOrBothNan(double a, double b)
{
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

class QueriesBruteForce : public ::testing::TestWithParam<Case>
{
};

TEST_P(QueriesBruteForce, EveryQueryEqualsTheBruteForceOnEveryRankInOneCall)
{
  const Case& c = GetParam();
  RandomForestOptions options;
  options.dimension = c.dimension;
  options.branchFactor = c.branchFactor;
  options.rootCells = {{3, 2, 2}};
  options.flatAxis = 1; // 2D in the xz-plane
  options.maxLevels = c.dimension == 3 ? 4 : 6;
  options.refineProbability = c.dimension == 1 ? 0.7 : 0.45;
  options.maskProbability = c.maskProbability;
  options.seed = c.seed;
  options.skipEveryOtherRoot = c.holes;
  options.origin = {{-1.5, 0.25, 3.0}};
  RandomForest whole(options);
  const std::vector<OracleLeaf> leaves = visibleLeaves(whole, c.dimension, options.flatAxis);
  ASSERT_FALSE(leaves.empty());

  RankPart part(whole.description(), worldRank(), worldSize(), c.depthFirst);
  RankFields fields(part, whole);
  if (c.depthFirst)
  {
    // With slot maps the trees may come in any order: the last root first.
    std::reverse(part.description.trees.begin(), part.description.trees.end());
  }

  std::vector<Query> queries;
  for (const Asked& a : asked)
  {
    const auto more = queriesFor(a);
    queries.insert(queries.end(), more.begin(), more.end());
  }
  const long long before = mpiCallsMade();
  const std::vector<QueryResult> results = runQueries(MPI_COMM_WORLD, part.description, queries);
  EXPECT_EQ(mpiCallsMade() - before, 1) << "every query of a call in one collective";
  ASSERT_EQ(results.size(), queries.size());

  for (std::size_t q = 0; q < queries.size(); ++q)
  {
    const Query& query = queries[q];
    const QueryResult want = expected(query, leaves);
    const QueryResult& got = results[q];
    SCOPED_TRACE(query.text());
    if (query.kind == QueryKind::Minimum || query.kind == QueryKind::Maximum ||
        query.kind == QueryKind::Count || query.kind == QueryKind::NonFinite ||
        query.kind == QueryKind::Cells || query.kind == QueryKind::Histogram)
    {
      EXPECT_TRUE(sameOrBothNan(got.value, want.value)) << got.value << " vs " << want.value;
    }
    else
    {
      EXPECT_NEAR(got.value, want.value, 1e-11 * (1 + std::abs(want.value)));
    }
    if (query.kind == QueryKind::Minimum || query.kind == QueryKind::Maximum)
    {
      EXPECT_EQ(got.location.rootIndex, want.location.rootIndex);
      EXPECT_EQ(got.location.level, want.location.level);
      EXPECT_EQ(got.location.index, want.location.index);
      for (std::size_t a = 0; a < 3; ++a)
      {
        EXPECT_NEAR(got.location.centre[a], want.location.centre[a], 1e-12);
      }
      // The rank named is the one holding that leaf.
      const OracleLeaf& leaf = leaves[static_cast<std::size_t>(want.location.rank)];
      const bool mine = std::find(fields.leaves.begin(), fields.leaves.end(),
                                  std::make_pair(leaf.tree, leaf.node)) != fields.leaves.end();
      EXPECT_EQ(got.location.rank == worldRank(), mine);
    }
    if (query.kind == QueryKind::Histogram)
    {
      EXPECT_EQ(got.bins, want.bins);
      EXPECT_EQ(got.below, want.below);
      EXPECT_EQ(got.above, want.above);
    }
  }

  // The same bits on every rank.
  const std::uint64_t mine = fingerprint(results);
  std::vector<std::uint64_t> all(static_cast<std::size_t>(worldSize()));
  MPI_Allgather(&mine, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD);
  for (std::uint64_t other : all)
  {
    EXPECT_EQ(other, mine);
  }
}

INSTANTIATE_TEST_SUITE_P(
    RandomForests, QueriesBruteForce,
    ::testing::Values(Case{3, 2, 0.0, false, false, 1}, Case{3, 2, 0.15, true, false, 2},
                      Case{3, 2, 0.1, false, true, 3}, Case{2, 2, 0.1, true, true, 4},
                      Case{2, 3, 0.1, false, false, 5}, Case{3, 3, 0.05, true, false, 6},
                      Case{1, 2, 0.1, false, false, 7}, Case{1, 3, 0.0, true, true, 8}),
    caseName);

TEST(QueriesRefused, AnUnknownFieldOnOneRankIsRefusedOnEveryRankWithoutAHang)
{
  RandomForestOptions options;
  options.seed = 11;
  RandomForest whole(options);
  RankPart part(whole.description(), worldRank(), worldSize(), false);
  RankFields fields(part, whole);
  if (worldRank() == worldSize() - 1)
  {
    part.description.fields.pop_back(); // "count" is unknown on the last rank
  }
  const long long before = mpiCallsMade();
  try
  {
    runQueries(MPI_COMM_WORLD, part.description, {Query::maximum("count")});
    FAIL() << "no QueryError";
  }
  catch (const QueryError& error)
  {
    const std::string what = error.what();
    EXPECT_NE(what.find("failed on rank(s) " + std::to_string(worldSize() - 1)), std::string::npos)
        << what;
    if (worldRank() == worldSize() - 1)
    {
      EXPECT_NE(what.find("no field 'count' in the forest"), std::string::npos) << what;
    }
  }
  EXPECT_EQ(mpiCallsMade() - before, 1);
}

TEST(QueriesRefused, BadRangesAndBinsAreRefused)
{
  RandomForestOptions options;
  RandomForest whole(options);
  RankPart part(whole.description(), worldRank(), worldSize(), false);
  RankFields fields(part, whole);
  for (const Query& bad : {Query::count("tied", 1, 0), Query::histogram("tied", 0, 1, 0),
                           Query::histogram("tied", 1, 1, 4), Query::maximum("vector", 3)})
  {
    EXPECT_THROW(runQueries(MPI_COMM_WORLD, part.description, {bad}), QueryError) << bad.text();
  }
}

TEST(QueriesOverTheCurrentRange, AHistogramOverTheFieldsRangeCostsOneMoreCollective)
{
  RandomForestOptions options;
  options.dimension = 3;
  options.maskProbability = 0.1;
  options.seed = 21;
  RandomForest whole(options);
  const std::vector<OracleLeaf> leaves = visibleLeaves(whole, 3, options.flatAxis);
  RankPart part(whole.description(), worldRank(), worldSize(), false);
  RankFields fields(part, whole);
  for (const auto& [field, component] : {std::make_pair("tied", 0), std::make_pair("vector", 2)})
  {
    const Query query = Query::histogram(field, 6, component);
    EXPECT_TRUE(query.overCurrentRange());
    const long long before = mpiCallsMade();
    const std::vector<QueryResult> got = runQueries(MPI_COMM_WORLD, part.description, {query});
    EXPECT_EQ(mpiCallsMade() - before, 2) << "the range first, then the bins";
    const double low = expected(Query::minimum(field, component), leaves).value;
    const double high = expected(Query::maximum(field, component), leaves).value;
    ASSERT_LT(low, high);
    const QueryResult want = expected(Query::histogram(field, low, high, 6, component), leaves);
    EXPECT_EQ(got[0].low, low);
    EXPECT_EQ(got[0].high, high);
    EXPECT_EQ(got[0].bins, want.bins);
    EXPECT_EQ(got[0].below, 0);
    EXPECT_EQ(got[0].above, 0);
    EXPECT_EQ(got[0].value, want.value) << "every finite leaf in a bin";
  }
  // A histogram with a given range beside it: still two collectives, not three.
  const long long before = mpiCallsMade();
  runQueries(MPI_COMM_WORLD, part.description,
             {Query::histogram("tied", 4), Query::histogram("tied", 0, 1, 4)});
  EXPECT_EQ(mpiCallsMade() - before, 2);
}

TEST(QueryText, TextsAreTheExpressionLanguagesSpelling)
{
  EXPECT_EQ(Query::histogram("v", 10, 1).text(), "histogram(v[1], 10)");
  EXPECT_EQ(Query::maximum("scalar").text(), "max(scalar)");
  EXPECT_EQ(Query::volume("scalar", 0.5, 1).text(), "volume(scalar, 0.5, 1)");
  EXPECT_EQ(Query::histogram("v", -1, 0.1, 10, 2).text(), "histogram(v[2], -1, 0.1, 10)");
  EXPECT_EQ(Query::l2Norm("p").text(), "l2(p)");
}

} // namespace
