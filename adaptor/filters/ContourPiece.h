// What one part of a contour's traversal produces: points keyed by the dual edge
// they lie on, and the cells (segments or triangles) joining them. Neighbouring
// cells share their points through the key, not through a geometric locator;
// parts are merged by the same key (ContourBuilder.h).
#pragma once

#include <vtkType.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace canopy
{

/// A dual vertex: a visible leaf's centre, or its projection onto the domain's
/// boundary (DualCellContour.h), with its field value.
struct DualVertex
{
  /// The leaf's global index times 64, plus, for a boundary vertex, the sides
  /// it was projected onto (2 bits per active axis: below, above).
  std::uint64_t key = 0;
  std::array<double, 3> x{{0, 0, 0}};
  double value = 0;
  /// The leaf's global index; a cell's centroid (DualCellContour.h): -(k + 1),
  /// k its index in the piece's `centroids`.
  vtkIdType leaf = 0;
  /// Every cell this vertex is in comes from one piece: a leaf touching no side
  /// of its tree (its corners are inside the tree, whose cells one task makes),
  /// or a centroid (one cell's own). An edge between two such vertices is made
  /// by one piece only: its point needs no merging by key.
  bool own = false;
};

/// A contour point: the dual edge (its vertices' keys, lower first) and the
/// contour value's index.
struct ContourPointKey
{
  std::uint64_t low = 0;
  std::uint64_t high = 0;
  std::uint32_t contour = 0;
  bool operator==(const ContourPointKey& o) const
  {
    return low == o.low && high == o.high && contour == o.contour;
  }
};

struct ContourPointKeyHash
{
  std::size_t operator()(const ContourPointKey& k) const
  {
    std::uint64_t h = k.low * 0x9E3779B97F4A7C15ull;
    h ^= (k.high + 0x632BE59BD9B4E019ull + (h << 6) + (h >> 2)) * 0xBF58476D1CE4E5B9ull;
    h ^= k.contour + (h >> 29);
    return static_cast<std::size_t>(h ^ (h >> 32));
  }
};

/// Key -> point id, open addressing (linear probing) in two flat arrays: no
/// allocation per point, which a node-based map pays for every crossing.
class ContourPointIndex
{
public:
  /// The id of `key`, inserting `id` when it is new (second: whether it was).
  std::pair<vtkIdType, bool> emplace(const ContourPointKey& key, vtkIdType id)
  {
    if (2 * (Count + 1) > Ids.size())
    {
      grow();
    }
    std::size_t at = ContourPointKeyHash{}(key) & (Ids.size() - 1);
    while (Ids[at] >= 0)
    {
      if (Keys[at] == key)
      {
        return {Ids[at], false};
      }
      at = (at + 1) & (Ids.size() - 1);
    }
    Keys[at] = key;
    Ids[at] = id;
    ++Count;
    return {id, true};
  }

  /// Room for `count` keys without growing.
  void reserve(std::size_t count)
  {
    while (2 * count > Ids.size())
    {
      grow();
    }
  }

private:
  void grow()
  {
    std::vector<ContourPointKey> keys(std::max<std::size_t>(64, 2 * Ids.size()));
    std::vector<vtkIdType> ids(keys.size(), -1);
    const std::size_t mask = keys.size() - 1;
    for (std::size_t i = 0; i < Ids.size(); ++i)
    {
      if (Ids[i] >= 0)
      {
        std::size_t at = ContourPointKeyHash{}(Keys[i]) & mask;
        while (ids[at] >= 0)
        {
          at = (at + 1) & mask;
        }
        keys[at] = Keys[i];
        ids[at] = Ids[i];
      }
    }
    Keys.swap(keys);
    Ids.swap(ids);
  }

  std::vector<ContourPointKey> Keys;
  std::vector<vtkIdType> Ids;
  std::size_t Count = 0;
};

struct ContourPiece
{
  /// The piece's number: what makes its centroids' keys unique.
  std::uint32_t id = 0;
  /// A centroid's leaves (DualCellContour.h): its value is their weighted sum.
  struct Centroid
  {
    std::array<vtkIdType, 8> leaves{};
    std::array<double, 8> weights{};
    int count = 0;
  };
  std::vector<Centroid> centroids;
  std::vector<std::array<double, 3>> points;
  std::vector<ContourPointKey> keys;
  /// Per point: the leaves at its edge's ends (lower position first) and the
  /// weight of the second one (the point is at (1 - t) x_first + t x_second).
  std::vector<std::array<vtkIdType, 2>> leaves;
  std::vector<double> weights;
  /// Per point: whether another piece may make it too (merged by key).
  std::vector<unsigned char> shared;
  /// Cells: verticesPerCell local point ids each (2: segments, 3: triangles).
  std::vector<vtkIdType> cells;
  /// 3D: per triangle, the unit vector against the field's gradient in its
  /// tetrahedron (the linear interpolant's): what the points' normals average.
  std::vector<std::array<double, 3>> cellNormals;
  /// 3D: per triangle, 1 when another rank draws it (ContourGhosts.h): made
  /// here only for its points' normals, left out of the output.
  std::vector<unsigned char> foreign;
  ContourPointIndex index;

  /// The key of the next centroid: above every leaf's (bit 63), unique over
  /// the pieces.
  std::uint64_t centroidKey() const
  {
    return (std::uint64_t{1} << 63) | (static_cast<std::uint64_t>(id) << 32) |
           static_cast<std::uint64_t>(centroids.size());
  }

  /// The point where contour `contour` (value `value`) crosses the edge from
  /// `a` to `b` (their values on either side of it), made once.
  vtkIdType point(const DualVertex& a, const DualVertex& b, std::uint32_t contour, double value)
  {
    const DualVertex& lo = a.key < b.key ? a : b;
    const DualVertex& hi = a.key < b.key ? b : a;
    const ContourPointKey key{lo.key, hi.key, contour};
    const auto found = index.emplace(key, static_cast<vtkIdType>(points.size()));
    if (!found.second)
    {
      return found.first;
    }
    // From the end lower in position (x, then y, then z; the key where they
    // coincide), whichever cell asks: the same bits every time, and on every
    // rank (keys are a rank's own numbering; positions are not).
    const bool keyOrder = lo.x == hi.x ? true : lo.x < hi.x;
    const DualVertex& p = keyOrder ? lo : hi;
    const DualVertex& q = keyOrder ? hi : lo;
    const double t = (value - p.value) / (q.value - p.value);
    const vtkIdType id = found.first;
    points.push_back({{p.x[0] + t * (q.x[0] - p.x[0]), p.x[1] + t * (q.x[1] - p.x[1]),
                       p.x[2] + t * (q.x[2] - p.x[2])}});
    keys.push_back(key);
    leaves.push_back({{p.leaf, q.leaf}});
    weights.push_back(t);
    // An edge with a centroid is one cell's own.
    const bool own = (lo.own && hi.own) || (lo.key >> 63) != 0 || (hi.key >> 63) != 0;
    shared.push_back(own ? 0 : 1);
    return id;
  }
};

} // namespace canopy
