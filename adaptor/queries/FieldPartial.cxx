#include "FieldPartial.h"

#include <cmath>
#include <tuple>

namespace canopy
{

bool CellKey::operator<(const CellKey& other) const
{
  if (rootIndex != other.rootIndex || level != other.level)
  {
    return std::tie(rootIndex, level) < std::tie(other.rootIndex, other.level);
  }
  // The same level of the same root: the first child digit (from the root down) that
  // differs decides; a digit is x + b y + b^2 z, so z, then y, then x.
  std::int64_t place = 1;
  for (std::int64_t l = 1; l < level; ++l)
  {
    place *= branch;
  }
  for (; place >= 1; place /= branch)
  {
    for (std::size_t axis = 3; axis-- > 0;)
    {
      const std::int64_t mine = index[axis] / place % branch;
      const std::int64_t theirs = other.index[axis] / place % branch;
      if (mine != theirs)
      {
        return mine < theirs;
      }
    }
  }
  return false;
}

namespace
{

constexpr std::size_t extremeInt64s = 8;  // found, root, level, i, j, k, branch, rank
constexpr std::size_t extremeDoubles = 4; // value, centre

void packExtreme(const Extreme& extreme, std::int64_t*& int64s, double*& doubles)
{
  *int64s++ = extreme.found ? 1 : 0;
  *int64s++ = extreme.key.rootIndex;
  *int64s++ = extreme.key.level;
  for (std::int64_t i : extreme.key.index)
  {
    *int64s++ = i;
  }
  *int64s++ = extreme.key.branch;
  *int64s++ = extreme.rank;
  *doubles++ = extreme.value;
  for (double c : extreme.centre)
  {
    *doubles++ = c;
  }
}

void unpackExtreme(Extreme& extreme, const std::int64_t*& int64s, const double*& doubles)
{
  extreme.found = *int64s++ != 0;
  extreme.key.rootIndex = *int64s++;
  extreme.key.level = *int64s++;
  for (std::int64_t& i : extreme.key.index)
  {
    i = *int64s++;
  }
  extreme.key.branch = *int64s++;
  extreme.rank = *int64s++;
  extreme.value = *doubles++;
  for (double& c : extreme.centre)
  {
    c = *doubles++;
  }
}

void mergeExtreme(Extreme& mine, const Extreme& other, bool maximum)
{
  if (other.found && mine.takes(other.value, other.key, maximum))
  {
    mine = other;
  }
}

CellLocation locationOf(const Extreme& extreme)
{
  CellLocation location;
  if (extreme.found)
  {
    location.rank = static_cast<int>(extreme.rank);
    location.rootIndex = extreme.key.rootIndex;
    location.level = static_cast<int>(extreme.key.level);
    location.index = extreme.key.index;
    location.centre = extreme.centre;
  }
  return location;
}

} // namespace

std::size_t FieldQuerySet::int64Words() const
{
  std::size_t words = 2 + 2 * extremeInt64s + ranges.size();
  for (const Bins& bins : histograms)
  {
    words += static_cast<std::size_t>(bins.count) + 2;
  }
  return words;
}

std::size_t FieldQuerySet::doubleWords() const
{
  return 4 + 2 * extremeDoubles + ranges.size();
}

FieldPartial::FieldPartial(const FieldQuerySet& request)
    : Request(&request), RangeCount(request.ranges.size(), 0),
      RangeVolume(request.ranges.size(), 0.0)
{
  for (const FieldQuerySet::Bins& bins : request.histograms)
  {
    HistogramCounts.emplace_back(static_cast<std::size_t>(bins.count) + 2, 0);
  }
}

void FieldPartial::addTotals(const Totals& totals)
{
  Finite += totals.finite;
  NonFinite += totals.nonFinite;
  Sum += totals.sum;
  Volume += totals.volume;
  Integral += totals.integral;
  Squares += totals.squares;
}

bool FieldPartial::offer(double value, const CellKey& key, std::int64_t rank, bool maximum)
{
  Extreme& extreme = maximum ? Maximum : Minimum;
  if (!extreme.takes(value, key, maximum))
  {
    return false;
  }
  extreme = {value, true, key, rank, {{0.0, 0.0, 0.0}}};
  return true;
}

void FieldPartial::pack(std::int64_t*& int64s, double*& doubles) const
{
  *int64s++ = Finite;
  *int64s++ = NonFinite;
  *doubles++ = Sum;
  *doubles++ = Volume;
  *doubles++ = Integral;
  *doubles++ = Squares;
  packExtreme(Minimum, int64s, doubles);
  packExtreme(Maximum, int64s, doubles);
  for (std::size_t r = 0; r < RangeCount.size(); ++r)
  {
    *int64s++ = RangeCount[r];
    *doubles++ = RangeVolume[r];
  }
  for (const auto& counts : HistogramCounts)
  {
    for (std::int64_t c : counts)
    {
      *int64s++ = c;
    }
  }
}

void FieldPartial::unpack(const std::int64_t*& int64s, const double*& doubles)
{
  Finite = *int64s++;
  NonFinite = *int64s++;
  Sum = *doubles++;
  Volume = *doubles++;
  Integral = *doubles++;
  Squares = *doubles++;
  unpackExtreme(Minimum, int64s, doubles);
  unpackExtreme(Maximum, int64s, doubles);
  for (std::size_t r = 0; r < RangeCount.size(); ++r)
  {
    RangeCount[r] = *int64s++;
    RangeVolume[r] = *doubles++;
  }
  for (auto& counts : HistogramCounts)
  {
    for (std::int64_t& c : counts)
    {
      c = *int64s++;
    }
  }
}

void FieldPartial::merge(const FieldPartial& other)
{
  Finite += other.Finite;
  NonFinite += other.NonFinite;
  Sum += other.Sum;
  Volume += other.Volume;
  Integral += other.Integral;
  Squares += other.Squares;
  mergeExtreme(Minimum, other.Minimum, false);
  mergeExtreme(Maximum, other.Maximum, true);
  for (std::size_t r = 0; r < RangeCount.size(); ++r)
  {
    RangeCount[r] += other.RangeCount[r];
    RangeVolume[r] += other.RangeVolume[r];
  }
  for (std::size_t h = 0; h < HistogramCounts.size(); ++h)
  {
    for (std::size_t b = 0; b < HistogramCounts[h].size(); ++b)
    {
      HistogramCounts[h][b] += other.HistogramCounts[h][b];
    }
  }
}

QueryResult FieldPartial::result(const Query& query, std::size_t range, std::size_t histogram) const
{
  QueryResult result;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  switch (query.kind)
  {
  case QueryKind::Minimum:
  case QueryKind::Maximum:
  {
    const Extreme& extreme = query.kind == QueryKind::Minimum ? Minimum : Maximum;
    result.value = extreme.found ? extreme.value : nan;
    result.location = locationOf(extreme);
    break;
  }
  case QueryKind::Count:
    result.value = static_cast<double>(RangeCount[range]);
    break;
  case QueryKind::Volume:
    result.value = RangeVolume[range];
    break;
  case QueryKind::Sum:
    result.value = Sum;
    break;
  case QueryKind::Mean:
    result.value = Finite > 0 ? Integral / Volume : nan;
    break;
  case QueryKind::Integral:
    result.value = Integral;
    break;
  case QueryKind::L2Norm:
    result.value = std::sqrt(Squares);
    break;
  case QueryKind::Histogram:
  {
    const auto& counts = HistogramCounts[histogram];
    result.bins.assign(counts.begin(), counts.end() - 2);
    result.below = counts[counts.size() - 2];
    result.above = counts.back();
    std::int64_t inside = 0;
    for (std::int64_t c : result.bins)
    {
      inside += c;
    }
    result.value = static_cast<double>(inside);
    break;
  }
  case QueryKind::NonFinite:
    result.value = static_cast<double>(NonFinite);
    break;
  case QueryKind::Cells:
    result.value = static_cast<double>(Finite);
    break;
  }
  return result;
}

} // namespace canopy
