// ClippedPolytope (adaptor/filters/ClippedPolytope.h), through its own header:
// a convex region clipped to a box, and whether a cell overlaps it with
// positive volume. Its vertices are checked against regions whose volume is
// known in closed form (a tetrahedron, a half cube, a wedge, a pyramid, a
// frustum, the same far from the origin), by the volume of their convex hull
// computed here from the vertices alone; its overlap answers against a brute
// force that clips each cell by the region's planes (tests/support/ConvexClip.h)
// on random regions and cells, and on hand-worked cells that touch the region
// exactly along a face, an edge or a corner (not overlapping).
#include "ClippedPolytope.h"
#include "ConvexClip.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace canopy::testing
{
namespace
{

HalfSpace halfSpace(double nx, double ny, double nz, double offset)
{
  return {{{nx, ny, nz}}, offset};
}

/// The region's half-spaces and the box's six, relative to the anchor.
std::vector<HalfSpace> withBox(std::vector<HalfSpace> halfSpaces, const Vec3& anchor,
                               const Vec3& lo, const Vec3& hi)
{
  for (int a = 0; a < 3; ++a)
  {
    Vec3 n{{0, 0, 0}};
    n[a] = 1;
    halfSpaces.push_back({n, hi[a] - anchor[a]});
    n[a] = -1;
    halfSpaces.push_back({n, anchor[a] - lo[a]});
  }
  return halfSpaces;
}

/// Volume of the convex hull of `vertices`, whose faces lie on `planes` (the
/// half-spaces that bound it): per plane, the vertices on it sorted by angle
/// make a face, and the faces' pyramids from the vertices' centroid add up.
double hullVolume(const std::vector<Vec3>& vertices, const std::vector<HalfSpace>& planes)
{
  std::vector<Vec3> unique;
  double scale = 0;
  for (const Vec3& v : vertices)
  {
    scale = std::max({scale, std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
  }
  const double tolerance = 1e-9 * scale;
  for (const Vec3& v : vertices)
  {
    const bool seen = std::any_of(unique.begin(), unique.end(),
                                  [&](const Vec3& u)
                                  {
                                    return std::abs(u[0] - v[0]) <= tolerance &&
                                           std::abs(u[1] - v[1]) <= tolerance &&
                                           std::abs(u[2] - v[2]) <= tolerance;
                                  });
    if (!seen)
    {
      unique.push_back(v);
    }
  }
  if (unique.size() < 4)
  {
    return 0;
  }
  Vec3 centre{{0, 0, 0}};
  for (const Vec3& v : unique)
  {
    for (int a = 0; a < 3; ++a)
    {
      centre[a] += v[a] / static_cast<double>(unique.size());
    }
  }
  double volume = 0;
  for (const HalfSpace& h : planes)
  {
    const double length = std::sqrt(dot(h.normal, h.normal));
    std::vector<ClipPoint> face;
    for (const Vec3& v : unique)
    {
      if (std::abs(dot(h.normal, v) - h.offset) <= tolerance * length)
      {
        face.push_back(v);
      }
    }
    if (face.size() < 3)
    {
      continue;
    }
    Vec3 faceCentre{{0, 0, 0}};
    for (const ClipPoint& p : face)
    {
      for (int a = 0; a < 3; ++a)
      {
        faceCentre[a] += p[a] / static_cast<double>(face.size());
      }
    }
    const Vec3 n{{h.normal[0] / length, h.normal[1] / length, h.normal[2] / length}};
    const Vec3 helper = std::abs(n[0]) < 0.9 ? Vec3{{1, 0, 0}} : Vec3{{0, 1, 0}};
    Vec3 e1 = cross(n, helper);
    const double l1 = std::sqrt(dot(e1, e1));
    e1 = {{e1[0] / l1, e1[1] / l1, e1[2] / l1}};
    const Vec3 e2 = cross(n, e1);
    std::sort(face.begin(), face.end(),
              [&](const ClipPoint& p, const ClipPoint& q)
              {
                const Vec3 dp = sub(p, faceCentre);
                const Vec3 dq = sub(q, faceCentre);
                return std::atan2(dot(dp, e2), dot(dp, e1)) < std::atan2(dot(dq, e2), dot(dq, e1));
              });
    const double height = (h.offset - dot(h.normal, centre)) / length;
    volume += polygonArea(face) * height / 3;
  }
  return volume;
}

struct ClosedForm
{
  const char* name;
  std::vector<HalfSpace> halfSpaces;
  Vec3 anchor;
  Vec3 lo;
  Vec3 hi;
  double volume;
};

TEST(ClippedPolytope, VolumesOfKnownRegionsFromTheirVertices)
{
  const std::vector<ClosedForm> cases{
      {"tetrahedron x + y + z <= 1 in the unit cube",
       {halfSpace(1, 1, 1, 1)},
       {{0, 0, 0}},
       {{0, 0, 0}},
       {{1, 1, 1}},
       1.0 / 6},
      {"the unit cube halved through its centre",
       {halfSpace(1, 1, 1, 1.5)},
       {{0, 0, 0}},
       {{0, 0, 0}},
       {{1, 1, 1}},
       0.5},
      {"a wedge z <= 0.5 + 0.25 x, anchored at the box's centre",
       {halfSpace(-0.25, 0, 1, 0.125)}, // n . (p - (0.5, 0.5, 0.5)) <= 0.125
       {{0.5, 0.5, 0.5}},
       {{0, 0, 0}},
       {{1, 1, 1}},
       0.625},
      {"a pyramid |x| <= z, |y| <= z of height 1",
       {halfSpace(1, 0, -1, 0), halfSpace(-1, 0, -1, 0), halfSpace(0, 1, -1, 0),
        halfSpace(0, -1, -1, 0)},
       {{0, 0, 0}},
       {{-1, -1, 0}},
       {{1, 1, 1}},
       4.0 / 3},
      {"a view frustum |x| <= z / 2, |y| <= z / 4, 1 <= z <= 3, inside a larger box",
       {halfSpace(1, 0, -0.5, 0), halfSpace(-1, 0, -0.5, 0), halfSpace(0, 1, -0.25, 0),
        halfSpace(0, -1, -0.25, 0), halfSpace(0, 0, -1, -1), halfSpace(0, 0, 1, 3)},
       {{0, 0, 0}},
       {{-10, -10, -10}},
       {{10, 10, 10}},
       4 * 0.5 * 0.25 * (27.0 - 1.0) / 3},
      {"a box the region contains",
       {halfSpace(1, 0, 0, 5)},
       {{0, 0, 0}},
       {{0, 0, 0}},
       {{1, 2, 3}},
       6},
      {"the tetrahedron, 2^-10 wide, 2^30 from the origin (bounds exact in binary)",
       {halfSpace(1, 1, 1, 0x1p-10)},
       {{0x1p30, 0x1p30, 0x1p30}},
       {{0x1p30, 0x1p30, 0x1p30}},
       {{0x1p30 + 0x1p-10, 0x1p30 + 0x1p-10, 0x1p30 + 0x1p-10}},
       0x1p-30 / 6},
  };
  for (const ClosedForm& c : cases)
  {
    SCOPED_TRACE(c.name);
    const ClippedPolytope polytope(c.halfSpaces, c.anchor, c.lo, c.hi);
    ASSERT_FALSE(polytope.empty());
    for (const Vec3& v : polytope.vertices())
    {
      for (const HalfSpace& h : withBox(c.halfSpaces, c.anchor, c.lo, c.hi))
      {
        EXPECT_LE(dot(h.normal, v), h.offset + 1e-9 * (1 + std::abs(h.offset)))
            << "a vertex outside the region";
      }
    }
    const double volume =
        hullVolume(polytope.vertices(), withBox(c.halfSpaces, c.anchor, c.lo, c.hi));
    EXPECT_NEAR(volume, c.volume, 1e-12 * c.volume);
    // The whole box overlaps it, as does any cell inside it with positive volume.
    EXPECT_TRUE(polytope.overlaps(c.lo, c.hi));
  }
}

TEST(ClippedPolytope, TheTetrahedronsVerticesAreItsFourCorners)
{
  const ClippedPolytope polytope({halfSpace(1, 1, 1, 1)}, {{0, 0, 0}}, {{0, 0, 0}}, {{1, 1, 1}});
  std::vector<Vec3> corners = polytope.vertices();
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  EXPECT_EQ(corners, (std::vector<Vec3>{{{0, 0, 0}}, {{0, 0, 1}}, {{0, 1, 0}}, {{1, 0, 0}}}));
}

TEST(ClippedPolytope, RegionsWithoutVolumeAreEmpty)
{
  const Vec3 origin{{0, 0, 0}};
  const Vec3 one{{1, 1, 1}};
  // Missing the box; a plane (two half-spaces facing each other); touching the
  // box along a face only.
  for (const auto& halfSpaces :
       {std::vector<HalfSpace>{halfSpace(-1, 0, 0, -2)},
        std::vector<HalfSpace>{halfSpace(1, 0, 0, 0.5), halfSpace(-1, 0, 0, -0.5)},
        std::vector<HalfSpace>{halfSpace(1, 0, 0, 0)},
        std::vector<HalfSpace>{halfSpace(1, 1, 1, 0)}})
  {
    const ClippedPolytope polytope(halfSpaces, origin, origin, one);
    EXPECT_TRUE(polytope.empty());
    EXPECT_FALSE(polytope.overlaps(origin, one));
    EXPECT_FALSE(polytope.overlaps({{-5, -5, -5}}, {{5, 5, 5}}));
  }
}

TEST(ClippedPolytope, CellsTouchingTheRegionDoNotOverlapIt)
{
  // The unit cube halved by x + y + z <= 1.5, anchored at (0.5, 0.5, 0.5), where
  // the touching corner lies: every comparison below is exact.
  const Vec3 centre{{0.5, 0.5, 0.5}};
  const ClippedPolytope half({halfSpace(1, 1, 1, 0)}, centre, {{0, 0, 0}}, {{1, 1, 1}});
  EXPECT_FALSE(half.overlaps({{0.5, 0.5, 0.5}}, {{1, 1, 1}})) << "a corner on the plane";
  EXPECT_TRUE(half.overlaps({{0.5, 0.5, 0.25}}, {{1, 1, 0.75}}));
  EXPECT_TRUE(half.overlaps({{0, 0, 0}}, {{0.5, 0.5, 0.5}}));
  // Along the box's faces (exact: axis-aligned), inside and outside it.
  const ClippedPolytope cube({}, centre, {{0, 0, 0}}, {{1, 1, 1}});
  EXPECT_FALSE(cube.overlaps({{1, 0, 0}}, {{2, 1, 1}})) << "a face shared with the box";
  EXPECT_FALSE(cube.overlaps({{1, 1, 0}}, {{2, 2, 1}})) << "an edge shared with the box";
  EXPECT_FALSE(cube.overlaps({{1, 1, 1}}, {{2, 2, 2}})) << "a corner shared with the box";
  EXPECT_TRUE(cube.overlaps({{0.75, 0.75, 0.75}}, {{2, 2, 2}}));
  // A wedge x <= z: the cell [0.5, 1] x [0, 1] x [0, 0.5] touches its plane along an edge.
  const ClippedPolytope wedge({halfSpace(1, 0, -1, 0)}, centre, {{0, 0, 0}}, {{1, 1, 1}});
  EXPECT_FALSE(wedge.overlaps({{0.5, 0, 0}}, {{1, 1, 0.5}})) << "an edge on the plane";
  EXPECT_TRUE(wedge.overlaps({{0.25, 0, 0.25}}, {{0.75, 1, 0.75}}));
}

/// ConvexClip's planes (inside where a x + b y + c z + d >= 0) for half-spaces
/// relative to `anchor`, each moved by `slack` times its normal's length
/// outward (positive) or inward (negative).
std::vector<ClipPlane> clipPlanes(const std::vector<HalfSpace>& halfSpaces, const Vec3& anchor,
                                  double slack)
{
  std::vector<ClipPlane> planes;
  for (const HalfSpace& h : halfSpaces)
  {
    const double length = std::sqrt(dot(h.normal, h.normal));
    planes.push_back({{-h.normal[0], -h.normal[1], -h.normal[2],
                       h.offset + dot(h.normal, anchor) + slack * length}});
  }
  return planes;
}

TEST(ClippedPolytope, OverlapsEqualBruteForceOnRandomRegionsAndCells)
{
  // Random convex regions (3 to 6 half-spaces through points near the box,
  // bounded or not) and random cells, in and around the box. The brute force
  // clips the cell (cut to the box) by the planes, moved a little outward and a
  // little inward: no volume even outward, the cell must not overlap; volume
  // even inward, it must. Cells within rounding of touching go either way.
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(0, 1);
  std::normal_distribution<double> gauss(0, 1);
  const Vec3 boxLo{{-1, 0.5, 2}};
  const Vec3 boxHi{{1, 2, 2.5}};
  int overlapping = 0;
  int apart = 0;
  for (int region = 0; region < 60; ++region)
  {
    std::vector<HalfSpace> halfSpaces;
    const Vec3 anchor{{boxLo[0] + 2 * unit(random), boxLo[1] + 1.5 * unit(random),
                       boxLo[2] + 0.5 * unit(random)}};
    const int count = 3 + static_cast<int>(random() % 4);
    for (int i = 0; i < count; ++i)
    {
      const Vec3 normal{{gauss(random), gauss(random), gauss(random)}};
      const Vec3 through{{boxLo[0] + 2 * unit(random), boxLo[1] + 1.5 * unit(random),
                          boxLo[2] + 0.5 * unit(random)}};
      halfSpaces.push_back({normal, dot(normal, sub(through, anchor))});
    }
    const ClippedPolytope polytope(halfSpaces, anchor, boxLo, boxHi);
    const auto outward = clipPlanes(halfSpaces, anchor, 1e-9);
    const auto inward = clipPlanes(halfSpaces, anchor, -1e-9);
    for (int c = 0; c < 200; ++c)
    {
      double b[6];
      for (int a = 0; a < 3; ++a)
      {
        const double extent = boxHi[a] - boxLo[a];
        const double size = extent * (c % 2 == 0 ? 0.05 : 0.4) * (0.1 + unit(random));
        const double lo = boxLo[a] - 0.2 * extent + 1.4 * extent * unit(random);
        b[2 * a] = lo;
        b[2 * a + 1] = lo + size;
      }
      // The cell cut to the box (exact: axis-aligned); empty when they are apart.
      double cut[6];
      bool meetsBox = true;
      for (int a = 0; a < 3; ++a)
      {
        cut[2 * a] = std::max(b[2 * a], boxLo[a]);
        cut[2 * a + 1] = std::min(b[2 * a + 1], boxHi[a]);
        meetsBox = meetsBox && cut[2 * a] < cut[2 * a + 1];
      }
      const bool surely = meetsBox && clippedVolume(cut, inward) > 0;
      const bool surelyNot = !meetsBox || clippedVolume(cut, outward) == 0;
      const bool answer = polytope.overlaps({{b[0], b[2], b[4]}}, {{b[1], b[3], b[5]}});
      if (surely)
      {
        ++overlapping;
        EXPECT_TRUE(answer) << "region " << region << ", cell " << c << ": a part of volume "
                            << clippedVolume(cut, inward) << " is inside";
      }
      else if (surelyNot)
      {
        ++apart;
        EXPECT_FALSE(answer) << "region " << region << ", cell " << c << ": nothing is inside";
      }
    }
  }
  // Both answers asked for often (fixed seed): the comparison is not vacuous.
  EXPECT_GT(overlapping, 500);
  EXPECT_GT(apart, 5000);
}

} // namespace
} // namespace canopy::testing
