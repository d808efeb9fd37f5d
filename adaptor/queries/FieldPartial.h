// One rank's share of every query on one component of one field, and how shares
// of several ranks combine: the statistics every query of the field reads (finite
// and non-finite leaves, sums, extremes with their leaves), the ranged counts and
// the histograms. Packed into a fixed number of int64 and double words, so all the
// fields' shares travel in one collective.
#pragma once

#include "canopy/Queries.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace canopy
{

/// A leaf's global id as the tie rule orders it: (rootIndex, level, k, j, i).
struct CellKey
{
  std::int64_t rootIndex = 0;
  std::int64_t level = 0;
  std::array<std::int64_t, 3> index{{0, 0, 0}};

  bool operator<(const CellKey& other) const;
};

/// An extreme value and its leaf.
struct Extreme
{
  double value = 0.0;
  bool found = false;
  CellKey key;
  std::int64_t rank = -1;
  std::array<double, 3> centre{{0.0, 0.0, 0.0}};

  /// Whether (value, key) should replace this minimum (`maximum` false) or maximum.
  bool takes(double candidate, const CellKey& candidateKey, bool maximum) const
  {
    if (!found)
    {
      return true;
    }
    if (candidate != value)
    {
      return maximum ? candidate > value : candidate < value;
    }
    return candidateKey < key;
  }
};

/// [low, high] ranges and histograms asked of one field's component.
struct FieldQuerySet
{
  std::string field;
  int component = 0;
  std::vector<std::array<double, 2>> ranges;
  struct Bins
  {
    double low;
    double high;
    int count;
  };
  std::vector<Bins> histograms;

  std::size_t int64Words() const;
  std::size_t doubleWords() const;
};

class FieldPartial
{
public:
  explicit FieldPartial(const FieldQuerySet& request);

  /// Takes one leaf's value. `where` gives its (CellKey, centre) when it may be an extreme.
  template <typename Where>
  void add(double value, double volume, Where&& where)
  {
    if (!std::isfinite(value))
    {
      ++NonFinite;
      return;
    }
    ++Finite;
    Sum += value;
    Volume += volume;
    Integral += value * volume;
    Squares += value * value * volume;
    const bool minimumCandidate = !Minimum.found || value <= Minimum.value;
    const bool maximumCandidate = !Maximum.found || value >= Maximum.value;
    if (minimumCandidate || maximumCandidate)
    {
      const CellKey key = where.key();
      if (minimumCandidate && Minimum.takes(value, key, false))
      {
        Minimum = {value, true, key, where.rank(), where.centre(key)};
      }
      if (maximumCandidate && Maximum.takes(value, key, true))
      {
        Maximum = {value, true, key, where.rank(), where.centre(key)};
      }
    }
    for (std::size_t r = 0; r < RangeCount.size(); ++r)
    {
      if (Request->ranges[r][0] <= value && value <= Request->ranges[r][1])
      {
        ++RangeCount[r];
        RangeVolume[r] += volume;
      }
    }
    for (std::size_t h = 0; h < Request->histograms.size(); ++h)
    {
      HistogramCounts[h][binOf(Request->histograms[h], value)] += 1;
    }
  }

  /// Bin of `value` in `bins`' counts: 0 .. count-1, then below, then above.
  static std::size_t binOf(const FieldQuerySet::Bins& bins, double value);

  /// Appends this share's words; reads them back (the same request's layout).
  void pack(std::int64_t*& int64s, double*& doubles) const;
  void unpack(const std::int64_t*& int64s, const double*& doubles);
  /// Combines another rank's share into this one (rank order decides sums' rounding).
  void merge(const FieldPartial& other);

  /// The result of `query`, which must be on this partial's field and component;
  /// `range` and `histogram` index its request's ranges and histograms.
  QueryResult result(const Query& query, std::size_t range, std::size_t histogram) const;

private:
  const FieldQuerySet* Request;
  std::int64_t Finite = 0;
  std::int64_t NonFinite = 0;
  double Sum = 0.0;
  double Volume = 0.0;
  double Integral = 0.0;
  double Squares = 0.0;
  Extreme Minimum;
  Extreme Maximum;
  std::vector<std::int64_t> RangeCount;
  std::vector<double> RangeVolume;
  std::vector<std::vector<std::int64_t>> HistogramCounts;
};

} // namespace canopy
