// One rank's share of every query on one component of one field, and how shares
// of several ranks combine: the statistics every query of the field reads (finite
// and non-finite leaves, sums, extremes with their leaves), the ranged counts and
// the histograms. Packed into a fixed number of int64 and double words, so all the
// fields' shares travel in one collective.
#pragma once

#include <canopy/Queries.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace canopy
{

/// A leaf's global id as the tie rule orders it: by root index, then level (coarser
/// first), then the leaf's position in its root's complete tree at that level in child
/// order (x fastest; Morton order) -- the order a breadth-first walk of the tree visits.
struct CellKey
{
  std::int64_t rootIndex = 0;
  std::int64_t level = 0;
  std::array<std::int64_t, 3> index{{0, 0, 0}};
  std::int64_t branch = 2; ///< the forest's branch factor

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

  /// What every finite leaf adds (FieldPass keeps them in registers, then adds them here).
  struct Totals
  {
    std::int64_t finite = 0;
    std::int64_t nonFinite = 0;
    double sum = 0.0;
    double volume = 0.0;
    double integral = 0.0;
    double squares = 0.0;
  };
  void addTotals(const Totals& totals);

  /// A leaf that may be the minimum (`maximum` false) or the maximum: taken by the tie
  /// rule. Out of line: called only for values at or beyond the extreme so far.
  /// Returns whether it was taken; its centre is then given with setCentre().
  bool offer(double value, const CellKey& key, std::int64_t rank, bool maximum);
  void setCentre(const std::array<double, 3>& centre, bool maximum)
  {
    (maximum ? Maximum : Minimum).centre = centre;
  }
  const Extreme& minimum() const { return Minimum; }
  const Extreme& maximum() const { return Maximum; }

  /// The ranges' counts and volumes, and each histogram's counts (bins, below, above),
  /// for FieldPass to add to.
  std::int64_t* rangeCounts() { return RangeCount.data(); }
  double* rangeVolumes() { return RangeVolume.data(); }
  std::int64_t* histogramCounts(std::size_t histogram) { return HistogramCounts[histogram].data(); }

  /// Bin of `value` in `bins`' counts: 0 .. count-1, then below, then above.
  static std::size_t binOf(const FieldQuerySet::Bins& bins, double value)
  {
    const auto count = static_cast<std::size_t>(bins.count);
    if (value < bins.low)
    {
      return count;
    }
    if (value > bins.high)
    {
      return count + 1;
    }
    const double position = (value - bins.low) / (bins.high - bins.low) * bins.count;
    const auto bin = static_cast<std::size_t>(position); // >= 0: value >= low
    return bin < count ? bin : count - 1;                // value == high: the last bin
  }

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
