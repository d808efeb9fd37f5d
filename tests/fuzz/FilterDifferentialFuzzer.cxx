// libFuzzer target: Canopy's filters against the brute-force oracles the unit tests
// use (tests/support), on forests, masks, split trees, cameras and selections decoded
// from the input (docs/testing.md, "Differential fuzzing of the filters").
//
// Each input is decoded into a random forest (RandomForest: 1D, 2D or 3D, branch factor
// 2 or 3, a few roots, bounded depth, a mask, roots without trees, both storage orders,
// dyadic or irregular root coordinates), optionally split between 2 to 4 simulated
// ranks (RankPart: p4est's partition, other ranks' parts absent), a camera (parallel or
// perspective, position, focal point, view up, scale or angle, viewport, pixel
// threshold) and a selection (locations, ids, value range, box or frustum; inverted or
// not, masked cells allowed or not, by properties or a vtkSelection). Then, on the whole
// forest and on every rank's part:
//  - vtkCanopyAdaptiveSurface, in one filter re-executed: the full surface, the culled
//    surface, with level of detail, with level of detail and no culling, and (3D) with
//    back faces skipped. 1D and 2D: the emitted cells are checked node by node against a
//    top-down walk of VTK's cursors (HtgWalk.h) deciding culling by clipping the node
//    with VTK's own frustum planes (CameraPlanes.h, ConvexClip.h) and level of detail by
//    VTK's own projection matrix. 3D: the full surface is exactly the boundary of the
//    visible leaves' voxels (VoxelBoundary.h); the culled one exactly the full surface's
//    faces that overlap the view; without culling, level of detail gives exactly the
//    boundary of the nodes where descent stops (a grid pruned there, voxelized).
//  - vtkCanopyExtractSelection, in both output modes: exactly the cells the documented
//    rules give on VTK's cursors' nodes (docs/filters.md), with the counters, the
//    bounds, the cells' geometry and fields; then the masked grid's full surface, and
//    the same selection inverted on the masked grid (the pipelines' chain).
//  - vtkCanopyContour (2D, 3D) of a linear field read from the input, in full and with the
//    view's level of detail: every point away from the boundary on the field's plane,
//    none inside a masked cell at full resolution over equal cubic roots,
//    no cell twice, and without masks or missing trees watertight (every edge or segment
//    end off the domain's boundary used exactly twice).
//  - split forests (masked too: each rank masks what the whole forest masks): every
//    rank's part alone as above, and the ranks together: the same cells as the whole
//    forest (selections, 1D and 2D surfaces; without a mask, 3D faces), each once; with
//    level of detail, every pixel drawn by one rank.
// Every comparison is exact: where a decision falls within rounding of a boundary (a
// leaf touching a plane, a footprint equal to the threshold) both answers are taken,
// and nowhere else (bounds are exact for binary trees over dyadic coordinates, there
// the rules are checked to the last bit). Anything else aborts with a message on stderr
// (libFuzzer saves the input). Nothing is tolerated. (What it found is fixed and kept
// fixed by its input: wide perspective views' culling excess in ViewVolume,
// corpus_filters/known_wide_view_culling_excess; faces drawn inside a coarser node
// where level of detail stops, in AdaptiveSurfaceBuilder's face queries,
// corpus_filters/regression_lod_interior_face.) CANOPY_FUZZ_DESCRIBE=1: one line
// per input saying what it decoded to (tests/fuzz/make_filter_corpus.py --check reads it).
//
// Input format (tests/fuzz/make_filter_corpus.py writes inputs in it): bytes read front
// to back, every read past the end is 0.
//   forest   shape: bits 0-1 dimension (1: 1D, 2: 2D, else 3D), bit 2 branch factor 3,
//                   bits 3-4 flat (2D) or line (1D) axis (% 3), bit 5 depth-first
//                   storage, bit 6 dyadic root coordinates, bit 7 every other root
//                   without a tree
//            roots: cells per axis 1 + v % 3, 1 + v / 3 % 3, 1 + v / 9 % 3
//            levels: 1 + v % (cap by dimension and branch factor)
//            refinement probability 0.15 + 0.5 v / 255; mask probability (v - 96) / 530
//                   above 96, else no mask; 4 bytes seed
//            ranks: 1 + v % 4 (split: every root has a tree); origin: Origins[v % 8]
//   camera   flags: bit 0 parallel, bit 1 along an axis (bits 2-3 axis, bit 4 sign), bit 5
//                   a vtkCamera (else the filter's camera properties)
//            focal point: 3 bytes, fractions of the bounds; azimuth, elevation; distance;
//            view up angle; parallel scale or view angle; viewport Viewports[v % 8];
//            pixel threshold Thresholds[v % 4]
//   select   flags: bits 0-2 mode (% 5: locations, ids, value range, box, frustum), bit 3
//                   invert, bit 4 allow masked, bit 5 a vtkSelection on port 1, bit 6 its
//                   INVERSE key, bit 7 INDICES (not GLOBALIDS)
//            locations: count 1 + v % 24, 3 bytes each (kind, pick, detail)
//            ids: count 1 + v % 32, 2 bytes each (v % (cells + 4) - 2)
//            value range: field and component, low and high (2 bytes each: bit 15 a
//                   node's exact value, else a fraction of the field's range)
//            box: 2 bytes per axis (bit 7: a leaf's bound, 0x7f: infinite, else a fraction)
//            frustum: source (camera planes, camera corners, six axis-aligned planes,
//                   random planes), near, far, aspect, then 6 or 18 bytes of planes
//   contour  the linear field's gradient (3 bytes), the value's place in its range
#include "CameraPlanes.h"
#include "ConvexClip.h"
#include "FlatPolygons.h"
#include "HtgWalk.h"
#include "PartitionedForest.h"
#include "RandomForest.h"
#include "RankPart.h"
#include "VoxelBoundary.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>
#include <canopy/filters/vtkCanopyContour.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <vtkBitArray.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkIdList.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSelection.h>
#include <vtkSelectionNode.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace canopy::testing
{
namespace
{

/// Keeps each input to a few milliseconds.
constexpr std::size_t NodeBudget = 2000;
/// wholeValue (RankPart.h) is unique below 1000 nodes per tree.
constexpr std::size_t TreeNodeBudget = 999;
/// Dyadic origins (exact bounds for binary trees), near zero and far from it.
constexpr std::array<double, 8> Origins{{0.0, -3.5, 7.25, 1024.0, -20.5, 0.5, 1048576.0, -96.0}};
constexpr std::array<std::array<int, 2>, 8> Viewports{{{{400, 400}},
                                                       {{640, 480}},
                                                       {{64, 48}},
                                                       {{16, 16}},
                                                       {{300, 900}},
                                                       {{1024, 256}},
                                                       {{7, 5}},
                                                       {{128, 96}}}};
constexpr std::array<double, 4> Thresholds{{1.0, 2.5, 8.0, 0.75}};

class Input
{
public:
  Input(const std::uint8_t* data, std::size_t size) : Data(data), Size(size) {}
  std::uint8_t byte() { return Position < Size ? Data[Position++] : 0; }
  unsigned word() { return static_cast<unsigned>(byte()) << 8 | byte(); }
  std::uint32_t word32() { return static_cast<std::uint32_t>(word()) << 16 | word(); }
  double fraction() { return byte() / 255.0; }

private:
  const std::uint8_t* Data;
  std::size_t Size;
  std::size_t Position = 0;
};

/// What the input decoded to and what is being checked: printed with any failure.
std::string Decoded;
std::string Stage;

[[noreturn]] void fail(const std::string& message)
{
  std::fprintf(stderr, "canopy filters fuzzer: %s\n  while: %s\n  input: %s\n", message.c_str(),
               Stage.c_str(), Decoded.c_str());
  std::fflush(stderr);
  std::abort();
}

std::string str(double x)
{
  std::ostringstream out;
  out.precision(17);
  out << x;
  return out.str();
}

std::string boxStr(const double b[6])
{
  std::string s = "[";
  for (int i = 0; i < 6; ++i)
  {
    s += str(b[i]) + (i == 5 ? "]" : i % 2 ? " x " : ", ");
  }
  return s;
}

// ---- Three-valued decisions: exact in general position, both answers within rounding ----

enum class Tri
{
  No,
  Maybe,
  Yes
};

Tri triOf(bool yes, bool no)
{
  return yes ? Tri::Yes : no ? Tri::No : Tri::Maybe;
}

Tri either(Tri a, Tri b)
{
  return static_cast<int>(a) > static_cast<int>(b) ? a : b;
}

Tri both(Tri a, Tri b)
{
  return static_cast<int>(a) < static_cast<int>(b) ? a : b;
}

Tri negated(Tri a)
{
  return a == Tri::Yes ? Tri::No : a == Tri::No ? Tri::Yes : Tri::Maybe;
}

const char* triName(Tri t)
{
  return t == Tri::Yes ? "yes" : t == Tri::No ? "no" : "within rounding";
}

/// Decisions taken both ways, for the summary line.
std::size_t Ambiguous = 0;

// ---- A grid as VTK's cursors see it: every node, masked subtrees included ----

struct NodeTruth
{
  bool reached = false;
  vtkIdType parent = -1;
  int level = 0;
  bool leaf = false;
  bool masked = false;
  bool absent = false;
  bool absentBelow = false; ///< a strict descendant is absent
  double b[6];
  std::vector<vtkIdType> children;     ///< in child order
  std::pair<long, long> whole{-1, -1}; ///< tree and breadth-first node in the whole forest
};

struct GridTruth
{
  vtkHyperTreeGrid* htg = nullptr;
  int dimension = 0;
  std::vector<int> active;
  std::array<std::vector<double>, 3> coords;
  double bounds[6];
  double extent = 0; ///< largest side of the domain
  double scale = 0;  ///< largest |coordinate| plus the extent
  double tol = 0;    ///< 0 when bounds are exact (binary trees over dyadic coordinates)
  std::vector<NodeTruth> nodes;
  std::map<vtkIdType, vtkIdType> rootOf; ///< root cell index -> its root's global index
  std::vector<vtkIdType> roots;

  const NodeTruth& at(vtkIdType id) const
  {
    if (id < 0 || id >= static_cast<vtkIdType>(nodes.size()) ||
        !nodes[static_cast<std::size_t>(id)].reached)
    {
      fail("cell id " + std::to_string(id) + " is not a node of the grid");
    }
    return nodes[static_cast<std::size_t>(id)];
  }
  /// Reachable through unmasked nodes only (what VTK shows).
  bool visible(vtkIdType id) const
  {
    for (; id >= 0; id = at(id).parent)
    {
      if (at(id).masked)
      {
        return false;
      }
    }
    return true;
  }
  /// Selectable by the selection's rules: no absent node, and no masked one unless
  /// masked cells are allowed, from the root down to it.
  bool selectable(vtkIdType id, bool allowMasked) const
  {
    for (; id >= 0; id = at(id).parent)
    {
      if (at(id).absent || (!allowMasked && at(id).masked))
      {
        return false;
      }
    }
    return true;
  }
  bool near(double a, double b) const { return std::abs(a - b) <= tol; }
};

GridTruth readGrid(vtkHyperTreeGrid* htg, bool exactBounds)
{
  GridTruth g;
  g.htg = htg;
  g.dimension = static_cast<int>(htg->GetDimension());
  vtkDataArray* axes[3] = {htg->GetXCoordinates(), htg->GetYCoordinates(), htg->GetZCoordinates()};
  double largest = 0;
  for (int a = 0; a < 3; ++a)
  {
    for (vtkIdType i = 0; i < axes[a]->GetNumberOfTuples(); ++i)
    {
      g.coords[a].push_back(axes[a]->GetComponent(i, 0));
      largest = std::max(largest, std::abs(g.coords[a].back()));
    }
    g.bounds[2 * a] = g.coords[a].front();
    g.bounds[2 * a + 1] = g.coords[a].back();
    if (g.coords[a].size() > 1)
    {
      g.active.push_back(a);
    }
    g.extent = std::max(g.extent, g.bounds[2 * a + 1] - g.bounds[2 * a]);
  }
  g.scale = largest + g.extent;
  g.tol = exactBounds ? 0.0 : 1e-12 * g.scale;
  g.nodes.resize(static_cast<std::size_t>(htg->GetNumberOfCells()));
  auto* ghosts = vtkUnsignedCharArray::SafeDownCast(
      htg->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()));
  vtkBitArray* mask = htg->HasMask() ? htg->GetMask() : nullptr;
  // Below masked nodes too (masked cells may be selected): VTK's cursors assert that
  // they never enter a masked node, so they walk the same trees without the mask.
  vtkNew<vtkHyperTreeGrid> open;
  open->CopyEmptyStructure(htg);
  open->SetMask(nullptr);
  std::size_t reached = 0;
  vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
  htg->InitializeTreeIterator(it);
  vtkIdType index = 0;
  while (vtkHyperTree* tree = it.GetNextTree(index))
  {
    open->SetTree(index, tree);
  }
  htg->InitializeTreeIterator(it);
  while (it.GetNextTree(index))
  {
    vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> cursor;
    open->InitializeNonOrientedGeometryCursor(cursor, index);
    auto walk = [&](auto& self, vtkIdType parent) -> vtkIdType
    {
      const vtkIdType id = cursor->GetGlobalNodeIndex();
      if (id < 0 || id >= static_cast<vtkIdType>(g.nodes.size()) ||
          g.nodes[static_cast<std::size_t>(id)].reached)
      {
        fail("oracle: VTK's cursor reached cell " + std::to_string(id) + " twice or out of range");
      }
      NodeTruth& n = g.nodes[static_cast<std::size_t>(id)];
      n.reached = true;
      ++reached;
      n.parent = parent;
      n.level = static_cast<int>(cursor->GetLevel());
      n.leaf = cursor->IsLeaf();
      n.masked = mask && id < mask->GetNumberOfValues() && mask->GetValue(id) != 0;
      n.absent = ghosts && (ghosts->GetValue(id) & vtkDataSetAttributes::DUPLICATECELL);
      cursor->GetBounds(n.b);
      if (!n.leaf)
      {
        for (unsigned char c = 0; c < cursor->GetNumberOfChildren(); ++c)
        {
          cursor->ToChild(c);
          const vtkIdType child = self(self, id);
          cursor->ToParent();
          g.nodes[static_cast<std::size_t>(id)].children.push_back(child);
        }
      }
      return id;
    };
    const vtkIdType root = walk(walk, -1);
    g.rootOf[index] = root;
    g.roots.push_back(root);
  }
  if (reached != g.nodes.size())
  {
    fail("oracle: VTK's cursors reached " + std::to_string(reached) + " of " +
         std::to_string(g.nodes.size()) + " cells");
  }
  // Absent strict descendants, children after their parents in a breadth-first order.
  std::vector<vtkIdType> order(g.roots);
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    for (vtkIdType c : g.nodes[static_cast<std::size_t>(order[i])].children)
    {
      order.push_back(c);
    }
  }
  for (std::size_t i = order.size(); i-- > 0;)
  {
    const NodeTruth& n = g.nodes[static_cast<std::size_t>(order[i])];
    if (n.parent >= 0 && (n.absent || n.absentBelow))
    {
      g.nodes[static_cast<std::size_t>(n.parent)].absentBelow = true;
    }
  }
  // The oracle's own reading must agree with HtgWalk.h's (what the unit tests use).
  std::map<vtkIdType, const LeafBox*> visible;
  const auto leaves = visibleLeafBoxes(htg);
  for (const LeafBox& leaf : leaves)
  {
    visible[leaf.global] = &leaf;
  }
  std::size_t mine = 0;
  for (vtkIdType id = 0; id < static_cast<vtkIdType>(g.nodes.size()); ++id)
  {
    if (g.nodes[static_cast<std::size_t>(id)].leaf && g.visible(id))
    {
      ++mine;
      if (!visible.count(id))
      {
        fail("oracle: leaf " + std::to_string(id) + " visible to the walk, not to HtgWalk");
      }
    }
  }
  if (mine != visible.size())
  {
    fail("oracle: the walk and HtgWalk disagree on the visible leaves");
  }
  return g;
}

/// Unsplit forest: the whole forest's node of every cell (docs/api.md's numbering).
void mapWhole(GridTruth& g, const RandomForest& forest)
{
  for (std::size_t t = 0; t < forest.nodes().size(); ++t)
  {
    for (std::size_t n = 0; n < forest.nodes()[t].size(); ++n)
    {
      const vtkIdType id = forest.cellOf(t, n);
      g.nodes[static_cast<std::size_t>(id)].whole = {static_cast<long>(t), static_cast<long>(n)};
    }
  }
  // And HtgWalk's reading of the same trees agrees where its cursors go.
  for (std::size_t t = 0; t < forest.nodes().size(); ++t)
  {
    forEachNode(g.htg, forest.description().trees[t].rootIndex, forest.refinement()[t],
                forest.childrenPerNode(),
                [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor, std::size_t n)
                {
                  if (cursor->GetGlobalNodeIndex() != forest.cellOf(t, n))
                  {
                    fail("oracle: cell numbering differs from docs/api.md's");
                  }
                });
  }
}

/// A rank's part: its nodes' whole-forest nodes. Breadth-first over the cursors' tree
/// (masked subtrees too), and HtgWalk's numbering agrees where its cursors go.
void mapRank(GridTruth& g, const RankPart& part, std::size_t children)
{
  for (const PartitionedTree& tree : part.trees)
  {
    std::vector<vtkIdType> order{g.rootOf.at(tree.rootIndex)};
    for (std::size_t i = 0; i < order.size(); ++i)
    {
      const auto& c = g.at(order[i]).children;
      order.insert(order.end(), c.begin(), c.end());
    }
    if (order.size() != tree.wholeNode.size())
    {
      fail("oracle: rank tree at root " + std::to_string(tree.rootIndex) + " has " +
           std::to_string(order.size()) + " nodes, its description " +
           std::to_string(tree.wholeNode.size()));
    }
    for (std::size_t n = 0; n < order.size(); ++n)
    {
      const std::pair<long, long> key{static_cast<long>(tree.wholeTree),
                                      static_cast<long>(tree.wholeNode[n])};
      g.nodes[static_cast<std::size_t>(order[n])].whole = key;
    }
    forEachNode(g.htg, tree.rootIndex, tree.refinement, children,
                [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor, std::size_t n)
                {
                  if (cursor->GetGlobalNodeIndex() != order[n])
                  {
                    fail("oracle: HtgWalk numbers a rank's nodes otherwise");
                  }
                });
  }
}

/// The corners of a 2D node's rectangle, in order around it.
std::vector<ClipPoint> rectangleOf(const GridTruth& g, const double b[6])
{
  const int u = g.active[0];
  const int v = g.active[1];
  std::vector<ClipPoint> r(4, ClipPoint{{b[0], b[2], b[4]}});
  r[1][u] = b[2 * u + 1];
  r[2][u] = b[2 * u + 1];
  r[2][v] = b[2 * v + 1];
  r[3][v] = b[2 * v + 1];
  return r;
}

/// Does the node's box share a part of positive length (1D), area (2D) or volume
/// (3D) with the region inside every plane? `inner`: the planes moved inward by the
/// slack, `outer`: outward (ConvexClip.h measures both).
Tri overlapsPlanes(const GridTruth& g, const double b[6], const std::vector<ClipPlane>& inner,
                   const std::vector<ClipPlane>& outer)
{
  double whole = 0;
  double surely = 0;
  double maybe = 0;
  if (g.dimension == 3)
  {
    whole = (b[1] - b[0]) * (b[3] - b[2]) * (b[5] - b[4]);
    surely = clippedVolume(b, inner);
    maybe = clippedVolume(b, outer);
  }
  else if (g.dimension == 2)
  {
    const auto r = rectangleOf(g, b);
    whole = polygonArea(r);
    surely = clippedArea(r, inner);
    maybe = clippedArea(r, outer);
  }
  else
  {
    const int u = g.active[0];
    const ClipPoint p{{b[0], b[2], b[4]}};
    ClipPoint q = p;
    q[u] = b[2 * u + 1];
    whole = b[2 * u + 1] - b[2 * u];
    surely = clippedLength(p, q, inner);
    maybe = clippedLength(p, q, outer);
  }
  const Tri t = triOf(surely > 1e-12 * whole, !(maybe > 0));
  Ambiguous += t == Tri::Maybe;
  return t;
}

/// Planes moved by `slack` (a distance; positive: outward).
std::vector<ClipPlane> movedPlanes(const std::vector<ClipPlane>& planes, double slack)
{
  std::vector<ClipPlane> moved;
  for (const ClipPlane& h : planes)
  {
    const double norm = std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    moved.push_back({{h[0], h[1], h[2], h[3] + slack * norm}});
  }
  return moved;
}

// ---- The view, as VTK's camera defines it ----

struct View
{
  vtkSmartPointer<vtkCamera> camera;
  bool viaCamera = true; ///< the filter gets the vtkCamera, else its camera properties
  int width = 400;
  int height = 400;
  double threshold = 1;
  std::vector<ClipPlane> inner;
  std::vector<ClipPlane> outer;
  double matrix[16];
  double depthTolerance = 0;

  void prepare(const GridTruth& g)
  {
    const double aspect = static_cast<double>(width) / height;
    // Rounding of the filter's view: relative to the coordinates and the distance.
    const double slack = 1e-9 * (g.scale + camera->GetDistance());
    inner = cameraSidePlanes(camera, aspect, -slack);
    outer = cameraSidePlanes(camera, aspect, slack);
    depthTolerance = slack;
    vtkMatrix4x4* m = camera->GetCompositeProjectionTransformMatrix(aspect, -1, 1);
    for (int i = 0; i < 16; ++i)
    {
      matrix[i] = m->GetElement(i / 4, i % 4);
    }
  }

  /// Does the node project to at most `threshold` pixels (the level-of-detail stop)?
  /// By VTK's projection matrix: a point at or behind the camera makes it infinite.
  Tri stops(const double b[6]) const
  {
    double lo[2] = {1e300, 1e300};
    double hi[2] = {-1e300, -1e300};
    bool nearCamera = false;
    for (int k = 0; k < 8; ++k)
    {
      const double p[4] = {b[(k & 1) ? 1 : 0], b[(k & 2) ? 3 : 2], b[(k & 4) ? 5 : 4], 1};
      double q[4] = {0, 0, 0, 0};
      for (int r = 0; r < 4; ++r)
      {
        for (int c = 0; c < 4; ++c)
        {
          q[r] += matrix[4 * r + c] * p[c];
        }
      }
      if (!camera->GetParallelProjection())
      {
        // q[3] is the depth in front of the camera.
        if (q[3] < -depthTolerance)
        {
          return Tri::No;
        }
        if (q[3] <= depthTolerance)
        {
          nearCamera = true;
          continue;
        }
      }
      const double x = (q[0] / q[3] + 1) * 0.5 * width;
      const double y = (q[1] / q[3] + 1) * 0.5 * height;
      lo[0] = std::min(lo[0], x);
      hi[0] = std::max(hi[0], x);
      lo[1] = std::min(lo[1], y);
      hi[1] = std::max(hi[1], y);
    }
    if (nearCamera)
    {
      ++Ambiguous;
      return Tri::Maybe;
    }
    const double footprint = std::max(hi[0] - lo[0], hi[1] - lo[1]);
    const double band = 1e-8 * (threshold + footprint) + 1e-9 * (width + height);
    const Tri t = triOf(footprint <= threshold - band, footprint > threshold + band);
    Ambiguous += t == Tri::Maybe;
    return t;
  }

  Tri overlaps(const GridTruth& g, const double b[6]) const
  {
    return overlapsPlanes(g, b, inner, outer);
  }

  void configure(vtkCanopyViewDependentFilter* filter) const
  {
    filter->SetViewportSize(width, height);
    filter->SetPixelThreshold(threshold);
    if (viaCamera)
    {
      filter->SetCamera(camera);
      return;
    }
    filter->SetCamera(nullptr);
    filter->SetCameraPosition(camera->GetPosition());
    filter->SetCameraFocalPoint(camera->GetFocalPoint());
    filter->SetCameraViewUp(camera->GetViewUp());
    filter->SetParallelProjection(camera->GetParallelProjection() != 0);
    filter->SetParallelScale(camera->GetParallelScale());
    filter->SetViewAngle(camera->GetViewAngle());
  }
};

/// A camera from the input around the domain [b]: never degenerate (the filter's
/// errors for bad views are the unit tests' business).
View decodeView(Input& in, const double b[6], double extent)
{
  View v;
  const std::uint8_t flags = in.byte();
  double focal[3];
  for (int a = 0; a < 3; ++a)
  {
    focal[a] = b[2 * a] + (-0.25 + 1.5 * in.fraction()) * (b[2 * a + 1] - b[2 * a]);
  }
  const double azimuth = in.fraction() * 2 * M_PI;
  const double elevation = (in.fraction() - 0.5) * 0.98 * M_PI;
  double dop[3] = {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                   std::sin(elevation)};
  if (flags & 2)
  {
    // Along an axis: views whose frustum edges may fall exactly on cell faces.
    const int axis = (flags >> 2 & 3) % 3;
    dop[0] = dop[1] = dop[2] = 0;
    dop[axis] = (flags & 16) ? -1 : 1;
  }
  const double distance = extent * (0.05 + 3.0 * in.fraction());
  const double upAngle = in.fraction() * 2 * M_PI;
  const std::uint8_t scaleByte = in.byte();
  const auto& viewport = Viewports[in.byte() % Viewports.size()];
  v.threshold = Thresholds[in.byte() % Thresholds.size()];
  v.width = viewport[0];
  v.height = viewport[1];
  v.viaCamera = (flags & 32) != 0;
  // View up: perpendicular to the direction, turned by upAngle (along an axis: by a
  // multiple of 90 degrees, so that it is a grid axis too).
  const int helperAxis = std::abs(dop[0]) < 0.9 ? 0 : 1;
  double helper[3] = {0, 0, 0};
  helper[helperAxis] = 1;
  double e1[3] = {dop[1] * helper[2] - dop[2] * helper[1], dop[2] * helper[0] - dop[0] * helper[2],
                  dop[0] * helper[1] - dop[1] * helper[0]};
  const double l1 = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
  for (double& x : e1)
  {
    x /= l1;
  }
  const double e2[3] = {dop[1] * e1[2] - dop[2] * e1[1], dop[2] * e1[0] - dop[0] * e1[2],
                        dop[0] * e1[1] - dop[1] * e1[0]};
  const double turn = (flags & 2) ? std::floor(upAngle / (M_PI / 2)) * (M_PI / 2) : upAngle;
  const double c = (flags & 2) ? std::round(std::cos(turn)) : std::cos(turn);
  const double s = (flags & 2) ? std::round(std::sin(turn)) : std::sin(turn);
  double up[3];
  for (int a = 0; a < 3; ++a)
  {
    up[a] = c * e1[a] + s * e2[a];
  }
  v.camera = vtkSmartPointer<vtkCamera>::New();
  v.camera->SetFocalPoint(focal);
  v.camera->SetPosition(focal[0] - distance * dop[0], focal[1] - distance * dop[1],
                        focal[2] - distance * dop[2]);
  v.camera->SetViewUp(up);
  v.camera->OrthogonalizeViewUp();
  v.camera->SetParallelProjection(flags & 1);
  v.camera->SetParallelScale(extent * (0.01 + 1.2 * scaleByte / 255.0));
  v.camera->SetViewAngle(5 + 115 * scaleByte / 255.0);
  return v;
}

std::string viewStr(const View& v)
{
  const double* p = v.camera->GetPosition();
  const double* f = v.camera->GetFocalPoint();
  const double* u = v.camera->GetViewUp();
  std::ostringstream out;
  out.precision(17);
  out << (v.camera->GetParallelProjection() ? "parallel, scale " : "perspective, angle ")
      << (v.camera->GetParallelProjection() ? v.camera->GetParallelScale()
                                            : v.camera->GetViewAngle())
      << ", position (" << p[0] << ", " << p[1] << ", " << p[2] << "), focal (" << f[0] << ", "
      << f[1] << ", " << f[2] << "), up (" << u[0] << ", " << u[1] << ", " << u[2] << "), "
      << v.width << "x" << v.height << " px, threshold " << v.threshold
      << (v.viaCamera ? ", a vtkCamera" : ", camera properties");
  return out.str();
}

// ---- Running filters: any VTK error or warning is a failure ----

class ErrorWatch
{
public:
  explicit ErrorWatch(vtkObject* object)
  {
    Callback->SetClientData(&Messages);
    Callback->SetCallback(
        [](vtkObject*, unsigned long, void* data, void* call)
        {
          static_cast<std::vector<std::string>*>(data)->push_back(
              call ? static_cast<const char*>(call) : "(no message)");
        });
    object->AddObserver(vtkCommand::ErrorEvent, Callback);
    object->AddObserver(vtkCommand::WarningEvent, Callback);
  }
  void check(const std::string& what)
  {
    if (!Messages.empty())
    {
      fail(what + ": VTK reported: " + Messages.front());
    }
  }

private:
  vtkNew<vtkCallbackCommand> Callback;
  std::vector<std::string> Messages;
};

double valueOf(vtkDataArray* array, vtkIdType tuple)
{
  return array->GetComponent(tuple, 0);
}

bool sameValue(double a, double b)
{
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

/// The output's "node" field is the input's at each cell's OriginalCellId.
void checkGatheredField(vtkHyperTreeGrid* input, vtkCellData* out, vtkIdTypeArray* ids,
                        const std::string& what)
{
  vtkDataArray* source = input->GetCellData()->GetArray("node");
  vtkDataArray* gathered = out->GetArray("node");
  if (!source)
  {
    return;
  }
  if (!gathered || gathered->GetNumberOfTuples() != ids->GetNumberOfTuples())
  {
    fail(what + ": the output has no \"node\" field, or not one value per cell");
  }
  for (vtkIdType c = 0; c < ids->GetNumberOfTuples(); ++c)
  {
    if (!sameValue(valueOf(gathered, c), valueOf(source, ids->GetValue(c))))
    {
      fail(what + ": cell " + std::to_string(c) + "'s \"node\" value is not its input cell's");
    }
  }
}

// ---- The surface's cells ----

struct SurfaceCell
{
  vtkIdType id;
  int level;
  std::vector<Point> points;  ///< a segment's ends, a flat piece's four corners in order
  std::vector<Point> polygon; ///< a flat piece's points: its corners, and those on its edges
};

std::vector<SurfaceCell> surfaceCells(vtkHyperTreeGrid* input, vtkPolyData* surface, int dimension,
                                      const std::string& what)
{
  auto* ids = vtkIdTypeArray::SafeDownCast(surface->GetCellData()->GetArray("OriginalCellId"));
  auto* levels = vtkUnsignedCharArray::SafeDownCast(surface->GetCellData()->GetArray("Level"));
  const vtkIdType cells = surface->GetNumberOfCells();
  if (cells > 0 && (!ids || !levels || ids->GetNumberOfTuples() != cells ||
                    levels->GetNumberOfTuples() != cells))
  {
    fail(what + ": OriginalCellId or Level missing or not one per cell");
  }
  std::vector<SurfaceCell> out;
  for (vtkIdType c = 0; c < cells; ++c)
  {
    vtkIdType n = 0;
    const vtkIdType* points = nullptr;
    surface->GetCellPoints(c, n, points);
    const int type = surface->GetCellType(c);
    if (dimension == 1 ? n != 2 || type != VTK_LINE
                       : n < 4 || type != (n == 4 ? VTK_QUAD : VTK_POLYGON))
    {
      fail(what + ": cell " + std::to_string(c) + " is not a " +
           (dimension == 1 ? "line" : "quad or polygon"));
    }
    SurfaceCell cell{ids->GetValue(c), levels->GetValue(c), {}, {}};
    for (vtkIdType k = 0; k < n; ++k)
    {
      Point p;
      surface->GetPoint(points[k], p.data());
      cell.polygon.push_back(p);
    }
    if (dimension == 1)
    {
      cell.points = cell.polygon;
    }
    else
    {
      // A rectangle, with the corners of the pieces meeting its edges on them.
      std::array<Point, 4> corners;
      const std::string problem = rectangleProblem(cell.polygon, corners);
      if (!problem.empty())
      {
        fail(what + ": cell " + std::to_string(c) + ": " + problem);
      }
      cell.points.assign(corners.begin(), corners.end());
    }
    out.push_back(cell);
  }
  if (cells > 0)
  {
    checkGatheredField(input, surface->GetCellData(), ids, what);
  }
  return out;
}

/// A 1D or 2D cell: exactly its node's segment or rectangle, at its node's level.
void checkPlanarCellGeometry(const GridTruth& g, const SurfaceCell& cell, const std::string& what)
{
  const NodeTruth& n = g.at(cell.id);
  if (cell.level != n.level)
  {
    fail(what + ": cell of node " + std::to_string(cell.id) + " has Level " +
         std::to_string(cell.level) + ", the node is at level " + std::to_string(n.level));
  }
  // Every point is a corner of the node's box, and they are the distinct corners.
  std::set<std::array<int, 3>> corners;
  for (const Point& p : cell.points)
  {
    std::array<int, 3> corner{{0, 0, 0}};
    for (int a = 0; a < 3; ++a)
    {
      if (g.near(p[a], n.b[2 * a]))
      {
        corner[a] = 0;
      }
      else if (g.near(p[a], n.b[2 * a + 1]))
      {
        corner[a] = 1;
      }
      else
      {
        fail(what + ": a point of node " + std::to_string(cell.id) + "'s cell is not on its box " +
             boxStr(n.b) + ": " + str(p[a]) + " along axis " + std::to_string(a));
      }
    }
    corners.insert(corner);
  }
  if (corners.size() != cell.points.size())
  {
    fail(what + ": node " + std::to_string(cell.id) + "'s cell repeats a corner");
  }
}

/// 1D and 2D surfaces, node by node: the cells must be a valid outcome of the walk
/// the documentation describes (descend into a visible node whose box overlaps the
/// view; stop at leaves or, with level of detail, at nodes of at most `threshold`
/// pixels with no absent descendant), both ways where a decision is within rounding.
struct PlanarCheck
{
  const GridTruth& g;
  const View* view; ///< nullptr: the full surface
  bool cull;
  bool lod;
  std::map<vtkIdType, int> emitted;

  /// Cells emitted in the subtree of `id`; `why` says what is wrong when they are no
  /// valid outcome (the deepest node whose every outcome fails).
  std::size_t check(vtkIdType id, std::string& why) const
  {
    const NodeTruth& n = g.at(id);
    const auto found = emitted.find(id);
    const std::size_t here = found == emitted.end() ? 0 : static_cast<std::size_t>(found->second);
    const Tri inView = n.masked ? Tri::No : view && cull ? view->overlaps(g, n.b) : Tri::Yes;
    if (inView == Tri::No)
    {
      // Masked or outside the view: nothing in the subtree (nothing to clip below).
      const std::size_t cells = here + countBelow(id);
      why = cells == 0 ? ""
                       : describe(id, n.masked ? "a masked node's subtree has cells"
                                               : "cells in a subtree outside the view");
      return cells;
    }
    std::size_t below = 0;
    std::string childWhy;
    for (vtkIdType c : n.children)
    {
      std::string w;
      below += check(c, w);
      if (childWhy.empty())
      {
        childWhy = w;
      }
    }
    const bool none = here + below == 0;
    const Tri stop = n.leaf ? Tri::Yes : view && lod && !n.absentBelow ? view->stops(n.b) : Tri::No;
    // The outcomes the rules allow: drawn here, descended into, or culled.
    const bool drawn = here == 1 && below == 0 && stop != Tri::No;
    const bool mayDescend = here == 0 && stop != Tri::Yes;
    const bool culled = inView == Tri::Maybe && none;
    if (drawn || culled || (mayDescend && childWhy.empty()))
    {
      why.clear();
    }
    else if (mayDescend)
    {
      why = childWhy;
    }
    else
    {
      why = describe(id, std::string(here ? "drawn" : "not drawn") + " (" + std::to_string(below) +
                             " cells below it); in view: " + triName(inView) +
                             ", stops: " + triName(stop));
    }
    return here + below;
  }

  std::size_t countBelow(vtkIdType id) const
  {
    std::size_t cells = 0;
    for (vtkIdType c : g.at(id).children)
    {
      const auto found = emitted.find(c);
      cells +=
          (found == emitted.end() ? 0 : static_cast<std::size_t>(found->second)) + countBelow(c);
    }
    return cells;
  }

  std::string describe(vtkIdType id, const std::string& what) const
  {
    const NodeTruth& n = g.at(id);
    return "node " + std::to_string(id) + " (level " + std::to_string(n.level) + ", " +
           (n.leaf ? "leaf" : "coarse") + ", box " + boxStr(n.b) + "): " + what;
  }
};

void checkPlanarSurface(const GridTruth& g, vtkPolyData* surface, const View* view, bool cull,
                        bool lod, const std::string& what)
{
  PlanarCheck check{g, view, cull, lod, {}};
  for (const SurfaceCell& cell : surfaceCells(g.htg, surface, g.dimension, what))
  {
    g.at(cell.id);
    if (++check.emitted[cell.id] > 1)
    {
      fail(what + ": node " + std::to_string(cell.id) + " emitted twice");
    }
    checkPlanarCellGeometry(g, cell, what);
  }
  std::size_t total = 0;
  for (vtkIdType root : g.roots)
  {
    std::string why;
    total += check.check(root, why);
    if (!why.empty())
    {
      fail(what + ": " + why);
    }
  }
  if (total != check.emitted.size())
  {
    fail(what + ": cells of nodes that are in no tree");
  }
}

// ---- 3D surfaces ----

std::vector<Quad> quadsOfCells(const std::vector<SurfaceCell>& cells)
{
  std::vector<Quad> quads;
  for (const SurfaceCell& c : cells)
  {
    quads.push_back(quadOf({{c.points[0], c.points[1], c.points[2], c.points[3]}}));
  }
  return quads;
}

/// VoxelBoundary.h's expectExactBoundary without GoogleTest: the quads cover exactly
/// the boundary of the voxels' union (per-axis area, each quad with an occupied voxel
/// behind it and an empty one in front, the closed-surface volume identity).
void checkVoxelBoundary(const GridTruth& g, const Voxels& voxels, const std::vector<Quad>& quads,
                        const std::vector<SurfaceCell>& cells, const std::string& what)
{
  std::array<double, 3> expectedArea;
  double expectedVolume = 0;
  voxels.boundary(expectedArea, expectedVolume);
  const double eps = 1e-3 * voxels.smallestVoxel();
  std::array<double, 3> area{{0, 0, 0}};
  std::array<double, 3> volume{{0, 0, 0}};
  // What rounding may change: corners are off by a few ulps of the coordinates, so each
  // quad's area by that times its perimeter (far from the origin, far above 1e-9).
  const double ulps = 8 * 2.3e-16 * g.scale;
  std::array<double, 3> areaBudget{{0, 0, 0}};
  std::array<double, 3> volumeBudget{{0, 0, 0}};
  for (std::size_t i = 0; i < quads.size(); ++i)
  {
    const Quad& q = quads[i];
    area[q.axis] += q.area;
    // Relative to the domain's corner: far from the origin the identity keeps its digits.
    const double x = q.p[0][q.axis] - g.bounds[2 * q.axis];
    volume[q.axis] += q.sign * x * q.area;
    double perimeter = 0;
    for (int k = 0; k < 4; ++k)
    {
      for (int a = 0; a < 3; ++a)
      {
        perimeter += std::abs(q.p[(k + 1) % 4][a] - q.p[k][a]);
      }
    }
    areaBudget[q.axis] += ulps * perimeter;
    volumeBudget[q.axis] += ulps * (q.area + std::abs(x) * perimeter);
    const QuadSides sides = sidesOf(voxels, q, eps);
    const Point& centre = sides.centre;
    const bool behind = sides.behind;
    const bool front = sides.front;
    if (!behind || front)
    {
      const NodeTruth& n = g.at(cells[i].id);
      fail(what + ": quad " + std::to_string(i) + " of node " + std::to_string(cells[i].id) +
           " (level " + std::to_string(n.level) + ", box " + boxStr(n.b) + "; normal " +
           (q.sign > 0 ? "+" : "-") + "xyz"[q.axis] + " at " + str(q.p[0][q.axis]) + ", centre (" +
           str(centre[0]) + ", " + str(centre[1]) + ", " + str(centre[2]) +
           ")) is not on the boundary: the oracle's solid is " + (behind ? "" : "not ") +
           "behind it and " + (front ? "" : "not ") + "in front of it");
    }
  }
  for (int a = 0; a < 3; ++a)
  {
    if (std::abs(area[a] - expectedArea[a]) > 1e-9 * expectedArea[a] + areaBudget[a])
    {
      fail(what + ": area normal to " + "xyz"[a] + " is " + str(area[a]) + ", the boundary's " +
           str(expectedArea[a]) + " (a face missing, twice, or inside)");
    }
    if (std::abs(volume[a] - expectedVolume) > 1e-9 * expectedVolume + volumeBudget[a])
    {
      fail(what + ": the volume identity along " + "xyz"[a] + " gives " + str(volume[a]) +
           ", the voxels' volume is " + str(expectedVolume));
    }
  }
}

/// A quad lies on a face of its node's box, facing out of it, at its level.
void checkQuadOnItsNode(const GridTruth& g, const SurfaceCell& cell, const Quad& q,
                        const std::string& what)
{
  const NodeTruth& n = g.at(cell.id);
  if (cell.level != n.level)
  {
    fail(what + ": quad of node " + std::to_string(cell.id) + " has Level " +
         std::to_string(cell.level) + ", the node is at level " + std::to_string(n.level));
  }
  const double tol = std::max(g.tol, 1e-12 * g.scale);
  const double face = n.b[2 * q.axis + (q.sign > 0 ? 1 : 0)];
  bool ok = true;
  for (const Point& p : q.p)
  {
    ok = ok && std::abs(p[q.axis] - face) <= tol;
    for (int a = 0; a < 3; ++a)
    {
      ok = ok && p[a] >= n.b[2 * a] - tol && p[a] <= n.b[2 * a + 1] + tol;
    }
  }
  if (!ok || !(q.area > 0))
  {
    fail(what + ": a quad of node " + std::to_string(cell.id) + " (normal " +
         (q.sign > 0 ? "+" : "-") + "xyz"[q.axis] + " at " + str(q.p[0][q.axis]) +
         ") is not on the node's outward face of its box " + boxStr(n.b));
  }
}

/// Relative to the domain, so that grids far from the origin keep their digits.
QuadKey quadKey(const GridTruth& g, const std::vector<Point>& points)
{
  return ::canopy::testing::quadKey(points, Point{{g.bounds[0], g.bounds[2], g.bounds[4]}},
                                    g.extent);
}

/// The nodes containing a point, from its root down (for messages).
std::vector<vtkIdType> chainAt(const GridTruth& g, const Point& p)
{
  std::vector<vtkIdType> chain;
  for (vtkIdType root : g.roots)
  {
    vtkIdType id = root;
    auto inside = [&](vtkIdType n)
    {
      for (int a : g.active)
      {
        if (p[a] < g.at(n).b[2 * a] || p[a] > g.at(n).b[2 * a + 1])
        {
          return false;
        }
      }
      return true;
    };
    if (!inside(id))
    {
      continue;
    }
    while (true)
    {
      chain.push_back(id);
      const auto& children = g.at(id).children;
      const auto next = std::find_if(children.begin(), children.end(), inside);
      if (next == children.end())
      {
        return chain;
      }
      id = *next;
    }
  }
  return chain;
}

/// Every visible node's level-of-detail stop, top-down and without culling: the
/// nodes where descent stops. False when a decision is within rounding.
bool stopNodes(const GridTruth& g, const View& view, std::vector<char>& stopped)
{
  stopped.assign(g.nodes.size(), 0);
  std::vector<vtkIdType> stack(g.roots.rbegin(), g.roots.rend());
  while (!stack.empty())
  {
    const vtkIdType id = stack.back();
    stack.pop_back();
    const NodeTruth& n = g.at(id);
    if (n.masked)
    {
      continue;
    }
    const Tri stop = n.leaf ? Tri::Yes : n.absentBelow ? Tri::No : view.stops(n.b);
    if (stop == Tri::Maybe)
    {
      return false;
    }
    if (stop == Tri::Yes)
    {
      stopped[static_cast<std::size_t>(id)] = 1;
      continue;
    }
    stack.insert(stack.end(), n.children.rbegin(), n.children.rend());
  }
  return true;
}

/// The grid pruned where descent stops: those nodes become leaves (solid), masked
/// nodes stay masked leaves. Its voxels are what a surface with level of detail bounds.
struct PrunedGrid
{
  std::array<std::vector<double>, 3> coords;
  std::vector<std::vector<std::uint8_t>> refinement;
  std::vector<std::vector<std::uint8_t>> masked;
  ForestDescription description;
  vtkSmartPointer<vtkHyperTreeGrid> htg;

  PrunedGrid(const GridTruth& g, const std::vector<char>& stopped, int branchFactor)
  {
    coords = g.coords;
    description.dimension = g.dimension;
    description.branchFactor = branchFactor;
    int deepest = 0;
    for (const NodeTruth& n : g.nodes)
    {
      deepest = std::max(deepest, n.level);
    }
    description.maxLevels = deepest + 1;
    description.rootGrid = {coords[0].data(), coords[1].data(), coords[2].data(),
                            coords[0].size(), coords[1].size(), coords[2].size()};
    for (const auto& [rootIndex, root] : g.rootOf)
    {
      std::vector<std::uint8_t> refine;
      std::vector<std::uint8_t> mask;
      std::vector<vtkIdType> queue{root};
      for (std::size_t i = 0; i < queue.size(); ++i)
      {
        const NodeTruth& n = g.at(queue[i]);
        const bool descend = !n.leaf && !n.masked && !stopped[static_cast<std::size_t>(queue[i])];
        refine.push_back(descend ? 1 : 0);
        mask.push_back(n.masked ? 1 : 0);
        if (descend)
        {
          queue.insert(queue.end(), n.children.begin(), n.children.end());
        }
      }
      refinement.push_back(std::move(refine));
      masked.push_back(std::move(mask));
      TreeDescription tree;
      tree.rootIndex = rootIndex;
      description.trees.push_back(tree);
    }
    for (std::size_t t = 0; t < description.trees.size(); ++t)
    {
      description.trees[t].refinement = refinement[t].data();
      description.trees[t].numberOfNodes = refinement[t].size();
      description.trees[t].masked = masked[t].data();
    }
    htg = buildHyperTreeGrid(description);
  }
};

struct SurfaceResult
{
  std::vector<std::pair<long, long>> planarWhole; ///< 1D/2D: emitted cells' whole nodes
  std::multiset<QuadKey> quads;                   ///< 3D: the quads, by their corners
};

SurfaceResult resultOf(const GridTruth& g, const std::vector<SurfaceCell>& cells)
{
  SurfaceResult r;
  for (const SurfaceCell& c : cells)
  {
    if (g.dimension == 3)
    {
      r.quads.insert(quadKey(g, c.points));
    }
    else
    {
      r.planarWhole.push_back(g.at(c.id).whole);
    }
  }
  return r;
}

/// Every surface check on one grid; what the ranks compare is returned.
struct SurfaceRuns
{
  SurfaceResult full;
  SurfaceResult culled;
  std::vector<std::pair<long, long>> lod; ///< 1D/2D with level of detail
};

SurfaceRuns checkSurfaces(const GridTruth& g, const View& view, int branchFactor, bool wholeGrid,
                          const std::string& label)
{
  SurfaceRuns runs;
  vtkNew<vtkCanopyAdaptiveSurface> filter;
  ErrorWatch errors(filter);
  filter->SetInputData(g.htg);
  // `exact`: the vertices on each flat piece's edges must be exactly the other
  // pieces' corners there (a 1D or 2D surface with every neighbour drawn), else
  // at least those (culling leaves a piece the corners of neighbours culled
  // away; 3D faces take the bounds of every cell around an edge). Split grids:
  // another rank's pieces are not here, so the check is on the whole grid only.
  auto run = [&](const std::string& what, bool exact)
  {
    Stage = label + ", " + what;
    filter->Update();
    errors.check(Stage);
    auto cells = surfaceCells(g.htg, filter->GetPolyDataOutput(), g.dimension, Stage);
    if (wholeGrid && g.dimension >= 2)
    {
      std::vector<std::vector<Point>> pieces;
      for (const SurfaceCell& c : cells)
      {
        pieces.push_back(c.polygon);
      }
      std::size_t found = 0;
      const std::string problem = edgeVertexProblem(pieces, exact, found);
      if (!problem.empty())
      {
        fail(Stage + ": the corners of the pieces meeting an edge: " + problem);
      }
    }
    return cells;
  };

  // The full surface.
  filter->ViewDependentOff();
  const auto full = run("surface without a view", g.dimension == 2);
  runs.full = resultOf(g, full);
  std::vector<Quad> fullQuads;
  if (g.dimension == 3)
  {
    fullQuads = quadsOfCells(full);
    for (std::size_t i = 0; i < full.size(); ++i)
    {
      checkQuadOnItsNode(g, full[i], fullQuads[i], Stage);
      if (!g.at(full[i].id).leaf || !g.visible(full[i].id))
      {
        fail(Stage + ": a quad of node " + std::to_string(full[i].id) +
             ", which is not a visible leaf");
      }
    }
    // Split grids: another rank's part is solid, only the ranks together are exact.
    if (wholeGrid)
    {
      checkVoxelBoundary(g, Voxels(g.htg), fullQuads, full, Stage);
    }
  }
  else
  {
    checkPlanarSurface(g, filter->GetPolyDataOutput(), nullptr, false, false, Stage);
  }

  // Culled, without level of detail.
  filter->ViewDependentOn();
  view.configure(filter);
  filter->LevelOfDetailOff();
  filter->ViewCullingOn();
  const auto culled = run("culled surface", false);
  runs.culled = resultOf(g, culled);
  if (g.dimension == 3)
  {
    // Exactly the full surface's faces that overlap the view with positive area.
    std::map<QuadKey, Tri> expected;
    for (std::size_t i = 0; i < full.size(); ++i)
    {
      const std::vector<ClipPoint> polygon(fullQuads[i].p.begin(), fullQuads[i].p.end());
      const double area = polygonArea(polygon);
      const Tri t = triOf(clippedArea(polygon, view.inner) > 1e-12 * area,
                          !(clippedArea(polygon, view.outer) > 0));
      Ambiguous += t == Tri::Maybe;
      expected[quadKey(g, full[i].points)] = t;
    }
    std::set<QuadKey> seen;
    for (const SurfaceCell& c : culled)
    {
      const QuadKey key = quadKey(g, c.points);
      const auto e = expected.find(key);
      const bool fresh = seen.insert(key).second;
      if (!fresh || e == expected.end() || e->second == Tri::No)
      {
        const Quad q = quadOf({{c.points[0], c.points[1], c.points[2], c.points[3]}});
        const std::vector<ClipPoint> polygon(q.p.begin(), q.p.end());
        fail(Stage + ": a quad of node " + std::to_string(c.id) + " (normal " +
             (q.sign > 0 ? "+" : "-") + "xyz"[q.axis] + ", corners (" + str(q.p[0][0]) + ", " +
             str(q.p[0][1]) + ", " + str(q.p[0][2]) + ") to (" + str(q.p[2][0]) + ", " +
             str(q.p[2][1]) + ", " + str(q.p[2][2]) + ")) " +
             (e == expected.end() ? "that the full surface does not have"
              : !fresh
                  ? "twice"
                  : "outside the view: its area in the view (VTK's frustum planes moved out by "
                    "the slack) is " +
                        str(clippedArea(polygon, view.outer)) + " of " + str(q.area)));
      }
    }
    for (const auto& [key, t] : expected)
    {
      if (t == Tri::Yes && !seen.count(key))
      {
        fail(Stage + ": a face of the full surface inside the view is missing");
      }
    }
    // Back faces skipped: the faces turned towards the camera, no others.
    filter->SkipBackFacesOn();
    const auto front = run("culled surface without back faces", false);
    filter->SkipBackFacesOff();
    const double* position = view.camera->GetPosition();
    double dop[3];
    view.camera->GetDirectionOfProjection(dop);
    std::set<QuadKey> kept;
    for (const SurfaceCell& c : front)
    {
      kept.insert(quadKey(g, c.points));
      if (!seen.count(quadKey(g, c.points)))
      {
        fail(Stage + ": a quad that the culled surface does not have");
      }
    }
    if (kept.size() != front.size())
    {
      fail(Stage + ": a quad twice");
    }
    for (const SurfaceCell& c : culled)
    {
      const Quad q = quadOf({{c.points[0], c.points[1], c.points[2], c.points[3]}});
      const double x = q.p[0][q.axis];
      const double facing = view.camera->GetParallelProjection() ? q.sign * dop[q.axis]
                                                                 : q.sign * (x - position[q.axis]);
      const double tol = view.camera->GetParallelProjection()
                             ? 1e-12
                             : 1e-12 * (std::abs(x) + std::abs(position[q.axis]));
      const Tri towards = triOf(facing<-tol, facing> tol);
      Ambiguous += towards == Tri::Maybe;
      const bool has = kept.count(quadKey(g, c.points)) > 0;
      if ((towards == Tri::Yes && !has) || (towards == Tri::No && has))
      {
        fail(Stage + ": the face of node " + std::to_string(c.id) + " turned " +
             (towards == Tri::Yes ? "towards" : "away from") + " the camera is " +
             (has ? "kept" : "skipped"));
      }
    }
  }
  else
  {
    checkPlanarSurface(g, filter->GetPolyDataOutput(), &view, true, false, Stage);
  }

  // With level of detail.
  filter->LevelOfDetailOn();
  const auto lod = run("surface with level of detail", false);
  if (g.dimension < 3)
  {
    checkPlanarSurface(g, filter->GetPolyDataOutput(), &view, true, true, Stage);
    for (const SurfaceCell& c : lod)
    {
      runs.lod.push_back(g.at(c.id).whole);
    }
  }
  else
  {
    // Each quad's node is where the walk may stop: in the view, visible, a leaf or
    // small enough with no absent part below, no ancestor small enough.
    const auto quads = quadsOfCells(lod);
    for (std::size_t i = 0; i < lod.size(); ++i)
    {
      checkQuadOnItsNode(g, lod[i], quads[i], Stage);
      const vtkIdType id = lod[i].id;
      const NodeTruth& n = g.at(id);
      if (!g.visible(id))
      {
        fail(Stage + ": a quad of node " + std::to_string(id) + ", which is not visible");
      }
      const Tri stop = n.leaf ? Tri::Yes : n.absentBelow ? Tri::No : view.stops(n.b);
      const Tri inView = view.overlaps(g, n.b);
      if (stop == Tri::No || inView == Tri::No)
      {
        fail(Stage + ": a quad of node " + std::to_string(id) + " (box " + boxStr(n.b) +
             ") where descent does not stop, or outside the view");
      }
      for (vtkIdType a = n.parent; a >= 0; a = g.at(a).parent)
      {
        if (!g.at(a).absentBelow && view.stops(g.at(a).b) == Tri::Yes)
        {
          fail(Stage + ": a quad of node " + std::to_string(id) + " below node " +
               std::to_string(a) + ", where descent stops");
        }
      }
    }
  }

  // Level of detail without culling: 3D, exactly the boundary of the stop nodes.
  filter->ViewCullingOff();
  const auto unculled = run("surface with level of detail, without culling", false);
  if (g.dimension < 3)
  {
    checkPlanarSurface(g, filter->GetPolyDataOutput(), &view, false, true, Stage);
  }
  else if (wholeGrid)
  {
    std::vector<char> stopped;
    if (stopNodes(g, view, stopped))
    {
      const auto quads = quadsOfCells(unculled);
      for (std::size_t i = 0; i < unculled.size(); ++i)
      {
        checkQuadOnItsNode(g, unculled[i], quads[i], Stage);
        if (!stopped[static_cast<std::size_t>(unculled[i].id)])
        {
          fail(Stage + ": a quad of node " + std::to_string(unculled[i].id) +
               ", where descent does not stop");
        }
      }
      // Each quad with nothing solid in front of it: no stop node on the way there.
      std::vector<Quad> exposed;
      std::vector<SurfaceCell> exposedCells;
      for (std::size_t i = 0; i < unculled.size(); ++i)
      {
        const Quad& q = quads[i];
        const NodeTruth& drawer = g.at(unculled[i].id);
        Point front{{0, 0, 0}};
        for (const Point& p : q.p)
          for (int a = 0; a < 3; ++a)
            front[a] += p[a] / 4;
        front[q.axis] += q.sign * 1e-6 * g.extent;
        std::string path;
        bool solid = false; ///< a stop node in front
        for (vtkIdType id : chainAt(g, front))
        {
          const NodeTruth& n = g.at(id);
          path += " " + std::to_string(id) + " (level " + std::to_string(n.level) +
                  (n.masked ? ", masked" : "") +
                  (stopped[static_cast<std::size_t>(id)] ? ", stops" : "") +
                  (n.leaf ? ", leaf" : "") + ")";
          if (n.masked)
          {
            break;
          }
          solid = solid || stopped[static_cast<std::size_t>(id)];
        }
        if (!solid)
        {
          exposed.push_back(q);
          exposedCells.push_back(unculled[i]);
        }
        else
        {
          fail(Stage + ": node " + std::to_string(unculled[i].id) + " (level " +
               std::to_string(drawer.level) + ", box " + boxStr(drawer.b) +
               ") draws its face normal to " + (q.sign > 0 ? "+" : "-") + "xyz"[q.axis] + " at " +
               str(q.p[0][q.axis]) +
               ", inside the drawn solid: in front of it, from the root:" + path);
        }
      }
      const PrunedGrid pruned(g, stopped, branchFactor);
      checkVoxelBoundary(g, Voxels(pruned.htg), exposed, exposedCells, Stage);
    }
  }
  return runs;
}

// ---- Selections ----

enum Mode
{
  Locations,
  Ids,
  ValueRange,
  Box,
  FrustumMode
};
const char* const ModeNames[] = {"locations", "ids", "value range", "box", "frustum"};

struct SelectionSpec
{
  int mode = Locations;
  bool invert = false;
  bool allowMasked = false;
  bool viaSelection = false;
  bool inverseKey = false;
  bool indices = false;
  std::vector<Point> points;
  std::vector<vtkIdType> ids;
  std::string field = "node";
  int component = 0;
  double range[2] = {0, 0};
  double box[6] = {0, 0, 0, 0, 0, 0};
  int frustumSource = 0; ///< 0 planes, 1 corners (properties), 2 corners (vtkSelection)
  std::vector<ClipPlane> planes;
  std::array<ClipPoint, 8> corners;
  std::string describe;
};

/// The value a range selection compares for the whole forest's node (t, n): the
/// fields every grid carries (wholeValue, wholeHash; RankPart.h), and "pair"
/// (unsplit forests): (hash or NaN, value / 1000), compared by component or magnitude.
double fieldValue(const std::string& field, int component, std::pair<long, long> whole)
{
  const auto t = static_cast<std::size_t>(whole.first);
  const auto n = static_cast<std::size_t>(whole.second);
  if (field == "node")
  {
    return wholeValue(t, n);
  }
  if (field == "hash")
  {
    return wholeHash(t, n);
  }
  const double h = wholeHash(t, n);
  const double pair[2] = {h < 0.03 ? std::nan("") : h, wholeValue(t, n) / 1000};
  if (component >= 0)
  {
    return pair[component];
  }
  double sum = 0;
  for (double x : pair)
  {
    sum += x * x;
  }
  return std::sqrt(sum);
}

SelectionSpec decodeSelection(Input& in, const GridTruth& g, const View& view, bool split)
{
  SelectionSpec s;
  const std::uint8_t flags = in.byte();
  s.mode = (flags & 7) % 5;
  s.invert = flags & 8;
  s.allowMasked = flags & 16;
  s.viaSelection = (flags & 32) && s.mode != Box;
  s.inverseKey = s.viaSelection && (flags & 64);
  s.indices = flags & 128;
  std::vector<vtkIdType> leaves;
  for (vtkIdType id = 0; id < static_cast<vtkIdType>(g.nodes.size()); ++id)
  {
    if (g.nodes[static_cast<std::size_t>(id)].leaf)
    {
      leaves.push_back(id);
    }
  }
  const double* d = g.bounds;
  std::ostringstream describe;
  describe.precision(17);
  describe << ModeNames[s.mode];
  if (s.mode == Locations)
  {
    const int count = 1 + in.byte() % 24;
    for (int i = 0; i < count; ++i)
    {
      const std::uint8_t kind = in.byte() % 8;
      const std::uint8_t pick = in.byte();
      const std::uint8_t detail = in.byte();
      const NodeTruth& leaf = g.at(leaves[pick % leaves.size()]);
      Point p;
      for (int a = 0; a < 3; ++a)
      {
        const double lo = leaf.b[2 * a];
        const double hi = leaf.b[2 * a + 1];
        const int bits = detail >> (2 * a) & 3;
        switch (kind)
        {
        case 0: // a leaf's centre
          p[a] = 0.5 * (lo + hi);
          break;
        case 1: // its lower corner
          p[a] = lo;
          break;
        case 2: // its upper corner
          p[a] = hi;
          break;
        case 3: // its faces and edges
          p[a] = bits == 0 ? lo : bits == 1 ? hi : 0.5 * (lo + hi);
          break;
        case 4: // the domain's upper faces, edges, corner
          p[a] = bits == 0 ? d[2 * a + 1] : bits == 1 ? d[2 * a] : 0.5 * (d[2 * a] + d[2 * a + 1]);
          break;
        case 5: // just outside the domain, or on its faces
          p[a] = bits == 0   ? d[2 * a] - 1e-9 * g.scale
                 : bits == 1 ? d[2 * a + 1] + 0.5
                             : d[2 * a + (bits & 1)];
          break;
        case 6: // on a lattice of the domain: dyadic fractions
          p[a] = d[2 * a] + (d[2 * a + 1] - d[2 * a]) * ((pick + 37 * a + detail) % 65) / 64.0;
          break;
        default: // a leaf's centre, moved off a 2D or 1D grid along its flat axes
          p[a] = 0.5 * (lo + hi) + (lo == hi ? 0.5 + detail : 0.0);
          break;
        }
      }
      s.points.push_back(p);
    }
    describe << ", " << s.points.size() << " points";
  }
  else if (s.mode == Ids)
  {
    const int count = 1 + in.byte() % 32;
    const auto cells = static_cast<long>(g.nodes.size());
    for (int i = 0; i < count; ++i)
    {
      s.ids.push_back(static_cast<vtkIdType>(static_cast<long>(in.word()) % (cells + 4) - 2));
    }
    describe << ", " << s.ids.size() << " ids" << (s.indices ? " (INDICES)" : "");
  }
  else if (s.mode == ValueRange)
  {
    const std::uint8_t f = in.byte();
    s.field = f % 3 == 0 ? "node" : f % 3 == 1 || split ? "hash" : "pair";
    s.component = s.field == "pair" ? static_cast<int>(f / 3 % 3) - 1 : 0;
    double lo = 1e300;
    double hi = -1e300;
    for (const NodeTruth& n : g.nodes)
    {
      const double v = fieldValue(s.field, s.component, n.whole);
      if (!std::isnan(v))
      {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    }
    for (double& bound : s.range)
    {
      const unsigned w = in.word();
      if (w & 0x8000)
      {
        // A node's exact value: the bounds are inclusive.
        bound = fieldValue(s.field, s.component, g.nodes[(w & 0x7fff) % g.nodes.size()].whole);
      }
      else
      {
        bound = lo + (hi - lo) * (-0.1 + 1.2 * (w & 0x7fff) / 32767.0);
      }
    }
    describe << " of " << s.field << " component " << s.component << " in [" << s.range[0] << ", "
             << s.range[1] << "]";
  }
  else if (s.mode == Box)
  {
    for (int a = 0; a < 3; ++a)
    {
      double bound[2];
      for (double& x : bound)
      {
        const std::uint8_t v = in.byte();
        const double size = std::max(d[2 * a + 1] - d[2 * a], 1.0);
        if (v == 0x7f || v == 0xff)
        {
          x = v == 0x7f ? -INFINITY : INFINITY;
        }
        else if (v & 0x80)
        {
          const NodeTruth& leaf = g.at(leaves[(v & 0x3f) % leaves.size()]);
          x = leaf.b[2 * a + ((v >> 6) & 1)];
        }
        else
        {
          x = d[2 * a] - 0.2 * size + 1.4 * size * v / 126.0;
        }
      }
      s.box[2 * a] = std::min(bound[0], bound[1]);
      s.box[2 * a + 1] = std::max(bound[0], bound[1]);
    }
    describe << " " << boxStr(s.box);
  }
  else
  {
    const std::uint8_t source = in.byte() % 4;
    const double nearFraction = 0.02 + 0.93 * in.fraction();
    const double farFraction = 1.02 + 2.0 * in.fraction();
    const double aspect = 0.5 + 1.5 * in.fraction();
    if (source <= 1)
    {
      // The frustum of the view's camera, near and far planes through the grid.
      vtkNew<vtkCamera> camera;
      camera->DeepCopy(view.camera);
      const double distance = camera->GetDistance();
      camera->SetClippingRange(distance * nearFraction, distance * farFraction);
      double planes[24];
      camera->GetFrustumPlanes(aspect, planes);
      for (int p = 0; p < 6; ++p)
      {
        s.planes.push_back(
            {{planes[4 * p], planes[4 * p + 1], planes[4 * p + 2], planes[4 * p + 3]}});
      }
      if (source == 1 || s.viaSelection)
      {
        // The corners of the same frustum (SelectionRegionsTest.cxx's way).
        vtkNew<vtkMatrix4x4> inverse;
        vtkMatrix4x4::Invert(camera->GetCompositeProjectionTransformMatrix(aspect, -1, 1), inverse);
        for (int c = 0; c < 8; ++c)
        {
          const double ndc[4] = {(c & 4) ? 1.0 : -1.0, (c & 2) ? 1.0 : -1.0, (c & 1) ? 1.0 : -1.0,
                                 1};
          double world[4];
          inverse->MultiplyPoint(ndc, world);
          s.corners[c] = {{world[0] / world[3], world[1] / world[3], world[2] / world[3]}};
        }
        s.frustumSource = s.viaSelection ? 2 : 1;
      }
      describe << ", the camera's frustum (near " << nearFraction << ", far " << farFraction
               << " of the distance, aspect " << aspect << ")"
               << (source == 1 ? " by corners" : "");
    }
    else if (source == 2)
    {
      // Six axis-aligned planes, each through a leaf's bound or a fraction of the domain.
      for (int a = 0; a < 3; ++a)
      {
        double bound[2];
        for (double& x : bound)
        {
          const std::uint8_t v = in.byte();
          const double size = std::max(d[2 * a + 1] - d[2 * a], 1.0);
          x = (v & 0x80) ? g.at(leaves[(v & 0x3f) % leaves.size()]).b[2 * a + ((v >> 6) & 1)]
                         : d[2 * a] - 0.2 * size + 1.4 * size * v / 126.0;
        }
        ClipPlane low{{0, 0, 0, -std::min(bound[0], bound[1])}};
        low[a] = 1;
        ClipPlane high{{0, 0, 0, std::max(bound[0], bound[1])}};
        high[a] = -1;
        s.planes.push_back(low);
        s.planes.push_back(high);
      }
      describe << ", six axis-aligned planes";
      s.viaSelection = s.inverseKey = false;
    }
    else
    {
      // Six planes in any direction through the domain (the region may be unbounded).
      const double centre[3] = {0.5 * (d[0] + d[1]), 0.5 * (d[2] + d[3]), 0.5 * (d[4] + d[5])};
      for (int p = 0; p < 6; ++p)
      {
        const double azimuth = in.fraction() * 2 * M_PI;
        const double elevation = (in.fraction() - 0.5) * M_PI;
        const double offset = (in.fraction() - 0.3) * g.extent;
        const double n[3] = {std::cos(elevation) * std::cos(azimuth),
                             std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
        s.planes.push_back({{n[0], n[1], n[2],
                             offset - (n[0] * centre[0] + n[1] * centre[1] + n[2] * centre[2])}});
      }
      describe << ", six random planes";
      s.viaSelection = s.inverseKey = false;
    }
  }
  describe << (s.invert ? ", inverted" : "") << (s.allowMasked ? ", masked cells allowed" : "")
           << (s.viaSelection ? ", a vtkSelection" : "") << (s.inverseKey ? " with INVERSE" : "");
  s.describe = describe.str();
  return s;
}

/// What the filter does with a selection, per node: whether it is selected.
struct SelectionTruth
{
  std::vector<Tri> selected; ///< by global id
  bool exactCounts = true;   ///< no decision within rounding: the counters must match
  std::size_t outside = 0;
  std::size_t masked = 0;
  std::size_t outOfRange = 0;
  std::size_t duplicates = 0;
};

/// The leaf a point selects (docs/filters.md's rule on VTK's cursors' bounds), every
/// candidate where bounds are within rounding of the point. -1: outside, -2: masked.
void locate(const GridTruth& g, vtkIdType id, const Point& p, bool allowMasked,
            std::set<vtkIdType>& outcomes)
{
  const NodeTruth& n = g.at(id);
  if (n.absent || (!allowMasked && n.masked))
  {
    outcomes.insert(-2);
    return;
  }
  if (n.leaf)
  {
    outcomes.insert(id);
    return;
  }
  bool any = false;
  for (vtkIdType c : n.children)
  {
    const NodeTruth& child = g.at(c);
    Tri contains = Tri::Yes;
    for (int a : g.active)
    {
      const double lo = child.b[2 * a];
      const double hi = child.b[2 * a + 1];
      // The last child along an axis owns the rest of its parent.
      const bool last = std::abs(hi - n.b[2 * a + 1]) <= 1e-9 * (hi - lo);
      Tri lower = triOf(p[a] > lo + g.tol || (g.tol == 0 && p[a] >= lo), p[a] < lo - g.tol);
      Tri upper = last ? Tri::Yes
                       : triOf(p[a] < hi - g.tol || (g.tol == 0 && p[a] < hi),
                               p[a] > hi + g.tol || (g.tol == 0 && p[a] >= hi));
      contains = both(contains, both(lower, upper));
    }
    if (contains != Tri::No)
    {
      any = true;
      Ambiguous += contains == Tri::Maybe;
      locate(g, c, p, allowMasked, outcomes);
    }
  }
  if (!any)
  {
    fail("oracle: no child of node " + std::to_string(id) + " contains a point inside it");
  }
}

SelectionTruth selectionTruth(const GridTruth& g, const SelectionSpec& s)
{
  SelectionTruth t;
  t.selected.assign(g.nodes.size(), Tri::No);
  std::vector<vtkIdType> candidates; ///< selectable leaves
  for (vtkIdType id = 0; id < static_cast<vtkIdType>(g.nodes.size()); ++id)
  {
    if (g.at(id).leaf && g.selectable(id, s.allowMasked))
    {
      candidates.push_back(id);
    }
  }
  auto& sel = t.selected;
  if (s.mode == Locations)
  {
    std::set<vtkIdType> taken;
    for (const Point& p : s.points)
    {
      // The root cell: lo <= p < hi along each active axis, the last cell owning the
      // domain's upper bound; outside the domain or without a tree: outside.
      long index = 0;
      long stride = 1;
      bool inside = true;
      for (int a = 0; a < 3; ++a)
      {
        const auto& c = g.coords[a];
        const long cells = std::max<long>(1, static_cast<long>(c.size()) - 1);
        long i = 0;
        if (c.size() > 1)
        {
          if (!(p[a] >= c.front() && p[a] <= c.back()))
          {
            inside = false;
          }
          while (i + 1 < cells && p[a] >= c[static_cast<std::size_t>(i + 1)])
          {
            ++i;
          }
        }
        index += i * stride;
        stride *= cells;
      }
      const auto root = g.rootOf.find(index);
      std::set<vtkIdType> outcomes;
      if (!inside || root == g.rootOf.end())
      {
        outcomes.insert(-1);
      }
      else
      {
        locate(g, root->second, p, s.allowMasked, outcomes);
      }
      if (outcomes.size() > 1)
      {
        t.exactCounts = false;
        for (vtkIdType o : outcomes)
        {
          if (o >= 0)
          {
            sel[static_cast<std::size_t>(o)] = either(sel[static_cast<std::size_t>(o)], Tri::Maybe);
          }
        }
        continue;
      }
      const vtkIdType o = *outcomes.begin();
      if (o == -1)
      {
        ++t.outside;
      }
      else if (o == -2)
      {
        ++t.masked;
      }
      else if (!taken.insert(o).second)
      {
        ++t.duplicates;
      }
      else
      {
        sel[static_cast<std::size_t>(o)] = Tri::Yes;
      }
    }
  }
  else if (s.mode == Ids)
  {
    std::set<vtkIdType> wanted;
    for (vtkIdType id : s.ids)
    {
      if (id < 0 || id >= static_cast<vtkIdType>(g.nodes.size()))
      {
        ++t.outOfRange;
      }
      else if (!wanted.insert(id).second)
      {
        ++t.duplicates;
      }
    }
    for (vtkIdType id : wanted)
    {
      if (g.selectable(id, s.allowMasked))
      {
        sel[static_cast<std::size_t>(id)] = Tri::Yes;
      }
      else
      {
        ++t.masked;
      }
    }
  }
  else if (s.mode == ValueRange)
  {
    for (vtkIdType id : candidates)
    {
      const double v = fieldValue(s.field, s.component, g.at(id).whole);
      sel[static_cast<std::size_t>(id)] = v >= s.range[0] && v <= s.range[1] ? Tri::Yes : Tri::No;
    }
  }
  else if (s.mode == Box)
  {
    for (vtkIdType id : candidates)
    {
      const double* b = g.at(id).b;
      Tri overlaps = Tri::Yes;
      for (int a : g.active)
      {
        const double shared =
            std::min(b[2 * a + 1], s.box[2 * a + 1]) - std::max(b[2 * a], s.box[2 * a]);
        overlaps = both(overlaps, triOf(shared > 2 * g.tol,
                                        !(shared > -2 * g.tol) || (g.tol == 0 && !(shared > 0))));
      }
      Ambiguous += overlaps == Tri::Maybe;
      sel[static_cast<std::size_t>(id)] = overlaps;
    }
  }
  else
  {
    // Decided in floating point (docs/filters.md): a slack far above rounding.
    const double slack = 1e-9 * g.scale;
    const auto inner = movedPlanes(s.planes, -slack);
    const auto outer = movedPlanes(s.planes, slack);
    for (vtkIdType id : candidates)
    {
      sel[static_cast<std::size_t>(id)] = overlapsPlanes(g, g.at(id).b, inner, outer);
    }
  }
  return t;
}

/// What the output shows, per node: the selection, or (inverted, or as a masked
/// grid) the selectable leaves in or outside the selected subtrees.
std::vector<Tri> expectedOutput(const GridTruth& g, const SelectionSpec& s, const SelectionTruth& t,
                                bool invert, bool preserveTopology)
{
  if (!invert && !preserveTopology)
  {
    return t.selected;
  }
  std::vector<Tri> out(g.nodes.size(), Tri::No);
  for (vtkIdType id = 0; id < static_cast<vtkIdType>(g.nodes.size()); ++id)
  {
    if (!g.at(id).leaf || !g.selectable(id, s.allowMasked))
    {
      continue;
    }
    Tri covered = Tri::No;
    for (vtkIdType a = id; a >= 0; a = g.at(a).parent)
    {
      covered = either(covered, t.selected[static_cast<std::size_t>(a)]);
    }
    out[static_cast<std::size_t>(id)] = invert ? negated(covered) : covered;
  }
  return out;
}

void configureSelection(vtkCanopyExtractSelection* filter, const SelectionSpec& s)
{
  filter->SetInvert(s.invert);
  filter->SetAllowMasked(s.allowMasked);
  if (s.viaSelection)
  {
    vtkNew<vtkSelection> selection;
    vtkNew<vtkSelectionNode> node;
    node->SetFieldType(vtkSelectionNode::CELL);
    vtkSmartPointer<vtkDataArray> list;
    if (s.mode == Locations)
    {
      node->SetContentType(vtkSelectionNode::LOCATIONS);
      auto points = vtkSmartPointer<vtkDoubleArray>::New();
      points->SetNumberOfComponents(3);
      for (const Point& p : s.points)
      {
        points->InsertNextTuple(p.data());
      }
      list = points;
    }
    else if (s.mode == Ids)
    {
      node->SetContentType(s.indices ? vtkSelectionNode::INDICES : vtkSelectionNode::GLOBALIDS);
      auto ids = vtkSmartPointer<vtkIdTypeArray>::New();
      for (vtkIdType id : s.ids)
      {
        ids->InsertNextValue(id);
      }
      list = ids;
    }
    else if (s.mode == ValueRange)
    {
      node->SetContentType(vtkSelectionNode::THRESHOLDS);
      auto range = vtkSmartPointer<vtkDoubleArray>::New();
      range->SetName(s.field.c_str());
      range->SetNumberOfComponents(2);
      range->InsertNextTuple(s.range);
      node->GetProperties()->Set(vtkSelectionNode::COMPONENT_NUMBER(), s.component);
      list = range;
    }
    else
    {
      node->SetContentType(vtkSelectionNode::FRUSTUM);
      auto corners = vtkSmartPointer<vtkDoubleArray>::New();
      corners->SetNumberOfComponents(4);
      for (const ClipPoint& c : s.corners)
      {
        corners->InsertNextTuple4(c[0], c[1], c[2], 1.0);
      }
      list = corners;
    }
    node->SetSelectionList(list);
    if (s.inverseKey)
    {
      node->GetProperties()->Set(vtkSelectionNode::INVERSE(), 1);
    }
    selection->AddNode(node);
    filter->SetInputData(1, selection);
    return;
  }
  filter->SetSelectionMode(s.mode);
  filter->ClearLocations();
  for (const Point& p : s.points)
  {
    filter->AddLocation(p[0], p[1], p[2]);
  }
  filter->ClearIds();
  for (vtkIdType id : s.ids)
  {
    filter->AddId(id);
  }
  filter->SetValueArrayName(s.field.c_str());
  filter->SetValueComponent(s.component);
  filter->SetValueRange(s.range[0], s.range[1]);
  filter->SetBox(s.box[0], s.box[1], s.box[2], s.box[3], s.box[4], s.box[5]);
  double planes[24] = {};
  for (std::size_t p = 0; p < s.planes.size() && p < 6; ++p)
  {
    for (int k = 0; k < 4; ++k)
    {
      planes[4 * p + static_cast<std::size_t>(k)] = s.planes[p][static_cast<std::size_t>(k)];
    }
  }
  filter->SetFrustumPlanes(planes);
  filter->ClearFrustumCorners();
  for (std::size_t c = 0; s.frustumSource == 1 && c < 8; ++c)
  {
    filter->AddFrustumCorner(s.corners[c][0], s.corners[c][1], s.corners[c][2]);
  }
}

void compareSelected(const GridTruth& g, const std::vector<Tri>& expected,
                     const std::set<vtkIdType>& got, const std::string& what)
{
  for (vtkIdType id : got)
  {
    g.at(id);
    if (expected[static_cast<std::size_t>(id)] == Tri::No)
    {
      fail(what + ": node " + std::to_string(id) + " (box " + boxStr(g.at(id).b) +
           ") is selected and should not be");
    }
  }
  for (vtkIdType id = 0; id < static_cast<vtkIdType>(expected.size()); ++id)
  {
    if (expected[static_cast<std::size_t>(id)] == Tri::Yes && !got.count(id))
    {
      fail(what + ": node " + std::to_string(id) + " (box " + boxStr(g.at(id).b) +
           ") is not selected and should be");
    }
  }
}

/// The selection on one grid, both output modes, then the masked grid's surface.
/// Returns the whole-forest nodes selected as cells (for the ranks' comparison).
std::vector<std::pair<long, long>> checkSelection(const GridTruth& g, const SelectionSpec& s,
                                                  bool wholeGrid, const std::string& label,
                                                  bool chained = false)
{
  const SelectionTruth truth = selectionTruth(g, s);
  const bool invert = s.invert != s.inverseKey;
  vtkNew<vtkCanopyExtractSelection> filter;
  ErrorWatch errors(filter);
  filter->SetInputData(0, g.htg);
  configureSelection(filter, s);
  std::vector<std::pair<long, long>> selectedWhole;
  for (bool preserve : {false, true})
  {
    Stage = label + ", selection (" + s.describe + ") as " + (preserve ? "a masked grid" : "cells");
    filter->SetPreserveTopology(preserve);
    filter->Update();
    errors.check(Stage);
    const auto expected = expectedOutput(g, s, truth, invert, preserve);
    std::set<vtkIdType> got;
    std::vector<vtkIdType> shown;
    if (preserve)
    {
      auto* out = vtkHyperTreeGrid::SafeDownCast(filter->GetOutputDataObject(0));
      if (!out)
      {
        fail(Stage + ": the output is not a vtkHyperTreeGrid");
      }
      for (const LeafBox& leaf : visibleLeafBoxes(out))
      {
        got.insert(leaf.global);
        shown.push_back(leaf.global);
      }
    }
    else
    {
      auto* out = vtkUnstructuredGrid::SafeDownCast(filter->GetOutputDataObject(0));
      if (!out)
      {
        fail(Stage + ": the output is not a vtkUnstructuredGrid");
      }
      auto* ids = vtkIdTypeArray::SafeDownCast(out->GetCellData()->GetArray("OriginalCellId"));
      auto* levels = out->GetCellData()->GetArray("Level");
      const vtkIdType cells = out->GetNumberOfCells();
      if (!ids || !levels || ids->GetNumberOfTuples() != cells ||
          levels->GetNumberOfTuples() != cells)
      {
        fail(Stage + ": OriginalCellId or Level missing or not one per cell");
      }
      std::set<std::array<double, 3>> corners;
      for (vtkIdType c = 0; c < cells; ++c)
      {
        const vtkIdType id = ids->GetValue(c);
        const NodeTruth& n = g.at(id);
        if (!got.insert(id).second)
        {
          fail(Stage + ": node " + std::to_string(id) + " is a cell twice");
        }
        shown.push_back(id);
        const int type = g.dimension == 1 ? VTK_LINE : g.dimension == 2 ? VTK_QUAD : VTK_HEXAHEDRON;
        if (out->GetCellType(c) != type || levels->GetTuple1(c) != n.level)
        {
          fail(Stage + ": cell " + std::to_string(c) + " has the wrong type or Level");
        }
        double cb[6];
        out->GetCellBounds(c, cb);
        for (int i = 0; i < 6; ++i)
        {
          if (!g.near(cb[i], n.b[i]))
          {
            fail(Stage + ": cell " + std::to_string(c) + " has bounds " + boxStr(cb) +
                 ", its node " + boxStr(n.b));
          }
        }
        for (int k = 0; k < 8; ++k)
        {
          corners.insert({{n.b[(k & 1) ? 1 : 0], n.b[(k & 2) ? 3 : 2], n.b[(k & 4) ? 5 : 4]}});
        }
        selectedWhole.push_back(n.whole);
      }
      // Points merged by exact value: one per distinct corner (exact bounds only).
      if (g.tol == 0 && static_cast<std::size_t>(out->GetNumberOfPoints()) != corners.size())
      {
        fail(Stage + ": " + std::to_string(out->GetNumberOfPoints()) + " points for " +
             std::to_string(corners.size()) + " distinct corners");
      }
      if (cells > 0)
      {
        checkGatheredField(g.htg, out->GetCellData(), ids, Stage);
      }
    }
    compareSelected(g, expected, got, Stage);
    // The counters, when no decision was within rounding.
    if (truth.exactCounts &&
        (filter->GetLastOutside() != static_cast<vtkIdType>(truth.outside) ||
         filter->GetLastMasked() != static_cast<vtkIdType>(truth.masked) ||
         filter->GetLastOutOfRange() != static_cast<vtkIdType>(truth.outOfRange) ||
         filter->GetLastDuplicates() != static_cast<vtkIdType>(truth.duplicates)))
    {
      fail(Stage + ": counters outside/masked/out of range/duplicates " +
           std::to_string(filter->GetLastOutside()) + "/" +
           std::to_string(filter->GetLastMasked()) + "/" +
           std::to_string(filter->GetLastOutOfRange()) + "/" +
           std::to_string(filter->GetLastDuplicates()) + ", expected " +
           std::to_string(truth.outside) + "/" + std::to_string(truth.masked) + "/" +
           std::to_string(truth.outOfRange) + "/" + std::to_string(truth.duplicates));
    }
    // The selected cells' bounds (what a camera frames): as a masked grid too, a coarse
    // cell selected whole, though what is masked below it stays hidden.
    std::vector<vtkIdType> framed = shown;
    bool sure = true;
    if (preserve && !invert)
    {
      framed.clear();
      for (vtkIdType id = 0; id < static_cast<vtkIdType>(g.nodes.size()); ++id)
      {
        const Tri t = truth.selected[static_cast<std::size_t>(id)];
        sure = sure && t != Tri::Maybe;
        if (t == Tri::Yes)
        {
          framed.push_back(id);
        }
      }
    }
    double expectedBounds[6] = {1e300, -1e300, 1e300, -1e300, 1e300, -1e300};
    for (vtkIdType id : framed)
    {
      for (int a = 0; a < 3; ++a)
      {
        expectedBounds[2 * a] = std::min(expectedBounds[2 * a], g.at(id).b[2 * a]);
        expectedBounds[2 * a + 1] = std::max(expectedBounds[2 * a + 1], g.at(id).b[2 * a + 1]);
      }
    }
    const double* bounds = filter->GetLastSelectedBounds();
    for (int i = 0; i < 6 && sure; ++i)
    {
      if (framed.empty() ? bounds[0] <= bounds[1] : !g.near(bounds[i], expectedBounds[i]))
      {
        fail(Stage + ": LastSelectedBounds " + boxStr(bounds) + ", the selected cells' " +
             boxStr(expectedBounds));
      }
    }
    if (preserve)
    {
      // The masked grid as the pipelines use it: its surface, against its own cursors.
      auto* out = vtkHyperTreeGrid::SafeDownCast(filter->GetOutputDataObject(0));
      GridTruth masked = readGrid(out, g.tol == 0);
      // The same cells (the input's trees and fields, another mask).
      for (std::size_t i = 0; i < masked.nodes.size(); ++i)
      {
        masked.nodes[i].whole = g.nodes[i].whole;
      }
      vtkNew<vtkCanopyAdaptiveSurface> surface;
      ErrorWatch surfaceErrors(surface);
      surface->SetInputData(out);
      surface->ViewDependentOff();
      Stage += ", then its surface";
      surface->Update();
      surfaceErrors.check(Stage);
      if (g.dimension < 3)
      {
        checkPlanarSurface(masked, surface->GetPolyDataOutput(), nullptr, false, false, Stage);
      }
      else if (wholeGrid)
      {
        // A rank's part: other ranks' parts are solid, only the ranks together are exact.
        const auto cells = surfaceCells(out, surface->GetPolyDataOutput(), 3, Stage);
        const auto quads = quadsOfCells(cells);
        for (std::size_t i = 0; i < cells.size(); ++i)
        {
          checkQuadOnItsNode(masked, cells[i], quads[i], Stage);
        }
        checkVoxelBoundary(masked, Voxels(out), quads, cells, Stage);
      }
      if (!chained)
      {
        // Chained as the pipelines chain them (a value range, then a box cut away): the
        // same selection again, inverted, on the masked grid.
        SelectionSpec again = s;
        again.invert = !again.invert;
        again.describe += "; again, inverted, on the masked grid";
        checkSelection(masked, again, wholeGrid, label, true);
      }
    }
  }
  return selectedWhole;
}

// ---- The forest ----

struct ForestSpec
{
  RandomForestOptions options;
  bool dyadic = false;
  int ranks = 1;
  std::string describe;
};

ForestSpec decodeForest(Input& in)
{
  ForestSpec f;
  RandomForestOptions& o = f.options;
  const std::uint8_t shape = in.byte();
  o.dimension = (shape & 3) == 1 ? 1 : (shape & 3) == 2 ? 2 : 3;
  o.branchFactor = (shape & 4) ? 3 : 2;
  o.flatAxis = o.activeAxis = (shape >> 3 & 3) % 3;
  o.order = (shape & 32) ? StorageOrder::DepthFirst : StorageOrder::BreadthFirst;
  f.dyadic = shape & 64;
  o.skipEveryOtherRoot = shape & 128;
  const std::uint8_t roots = in.byte();
  o.rootCells = {{1u + roots % 3u, 1u + roots / 3u % 3u, 1u + roots / 9u % 3u}};
  static const int caps[4][2] = {{0, 0}, {8, 5}, {6, 4}, {4, 3}};
  o.maxLevels = 1 + in.byte() % caps[o.dimension][o.branchFactor - 2];
  o.refineProbability = 0.15 + 0.5 * in.fraction();
  const std::uint8_t mask = in.byte();
  o.maskProbability = mask > 96 ? (mask - 96) / 530.0 : 0.0;
  o.seed = in.word32();
  f.ranks = 1 + in.byte() % 4;
  const double origin = Origins[in.byte() % Origins.size()];
  o.origin = {{origin, -0.5 * origin, origin + 2}};
  if (f.ranks > 1)
  {
    // RankPart takes missing trees for other ranks'.
    o.skipEveryOtherRoot = false;
  }
  std::ostringstream out;
  out << o.dimension << "D";
  if (o.dimension < 3)
  {
    out << (o.dimension == 2 ? " normal to " : " along ") << "xyz"[o.flatAxis];
  }
  out << ", branch factor " << o.branchFactor << ", roots " << o.rootCells[0] << "x"
      << o.rootCells[1] << "x" << o.rootCells[2] << ", maxLevels " << o.maxLevels << ", refine "
      << o.refineProbability << ", mask " << o.maskProbability << ", seed " << o.seed
      << (o.order == StorageOrder::DepthFirst ? ", depth-first" : "")
      << (f.dyadic ? ", dyadic" : ", irregular") << " coordinates from " << origin
      << (o.skipEveryOtherRoot ? ", every other root without a tree" : "") << ", " << f.ranks
      << " rank(s)";
  f.describe = out.str();
  return f;
}

/// The fields every grid carries, by storage slot: "node" (wholeValue), "hash"
/// (wholeHash) and "pair" (fieldValue's).
struct WholeFields
{
  std::vector<double> node;
  std::vector<double> hash;
  std::vector<double> pair;

  WholeFields(RandomForest& forest)
  {
    const std::size_t slots = forest.numberOfNodes();
    node.resize(slots);
    hash.resize(slots);
    pair.resize(2 * slots);
    for (std::size_t t = 0; t < forest.nodes().size(); ++t)
    {
      for (std::size_t n = 0; n < forest.nodes()[t].size(); ++n)
      {
        const auto slot = static_cast<std::size_t>(forest.nodes()[t][n].slot);
        const std::pair<long, long> whole{static_cast<long>(t), static_cast<long>(n)};
        node[slot] = fieldValue("node", 0, whole);
        hash[slot] = fieldValue("hash", 0, whole);
        pair[2 * slot] = fieldValue("pair", 0, whole);
        pair[2 * slot + 1] = fieldValue("pair", 1, whole);
      }
    }
    ForestDescription& d = forest.description();
    d.fields.push_back(FieldDescription::aos("node", node.data(), slots));
    d.fields.push_back(FieldDescription::aos("hash", hash.data(), slots));
    d.fields.push_back(FieldDescription::aos("pair", pair.data(), slots, 2));
  }
};

/// The ranks' surfaces and selections together equal the whole forest's.
void compareRanks(const std::string& what, std::vector<std::pair<long, long>> whole,
                  std::vector<std::pair<long, long>> ranks)
{
  std::sort(whole.begin(), whole.end());
  std::sort(ranks.begin(), ranks.end());
  if (whole != ranks)
  {
    std::vector<std::pair<long, long>> onlyRanks;
    std::vector<std::pair<long, long>> onlyWhole;
    std::set_difference(ranks.begin(), ranks.end(), whole.begin(), whole.end(),
                        std::back_inserter(onlyRanks));
    std::set_difference(whole.begin(), whole.end(), ranks.begin(), ranks.end(),
                        std::back_inserter(onlyWhole));
    const auto example = [](const std::vector<std::pair<long, long>>& v)
    {
      return v.empty() ? std::string()
                       : " (e.g. tree " + std::to_string(v[0].first) + " node " +
                             std::to_string(v[0].second) + ")";
    };
    fail(what + ": the ranks together have " + std::to_string(ranks.size()) +
         " cells, the whole forest " + std::to_string(whole.size()) + "; " +
         std::to_string(onlyRanks.size()) + " only on ranks" + example(onlyRanks) + ", " +
         std::to_string(onlyWhole.size()) + " only in the whole forest" + example(onlyWhole));
  }
}

/// Level of detail on split trees: no whole-forest node drawn twice or with one of
/// its ancestors (every pixel has one owner), and every leaf surely in view covered.
void checkRanksLod(const GridTruth& whole, const RandomForest& forest, const View& view,
                   const std::vector<std::pair<long, long>>& drawn)
{
  std::set<std::pair<long, long>> set;
  for (const auto& key : drawn)
  {
    if (!set.insert(key).second)
    {
      fail("ranks' surfaces with level of detail: tree " + std::to_string(key.first) + " node " +
           std::to_string(key.second) + " drawn twice");
    }
  }
  const auto& nodes = forest.nodes();
  for (const auto& key : drawn)
  {
    for (long a = nodes[static_cast<std::size_t>(key.first)][static_cast<std::size_t>(key.second)]
                      .parent;
         a >= 0; a = nodes[static_cast<std::size_t>(key.first)][static_cast<std::size_t>(a)].parent)
    {
      if (set.count({key.first, a}))
      {
        fail("ranks' surfaces with level of detail: tree " + std::to_string(key.first) + " node " +
             std::to_string(key.second) + " drawn below its ancestor " + std::to_string(a) +
             " (two ranks draw the same pixels)");
      }
    }
  }
  for (vtkIdType id = 0; id < static_cast<vtkIdType>(whole.nodes.size()); ++id)
  {
    const NodeTruth& n = whole.at(id);
    if (!n.leaf || !whole.visible(id) || view.overlaps(whole, n.b) != Tri::Yes)
    {
      continue;
    }
    bool covered = false;
    for (long a = n.whole.second; a >= 0 && !covered;
         a = nodes[static_cast<std::size_t>(n.whole.first)][static_cast<std::size_t>(a)].parent)
    {
      covered = set.count({n.whole.first, a}) > 0;
    }
    if (!covered)
    {
      fail("ranks' surfaces with level of detail: leaf " + std::to_string(id) + " (box " +
           boxStr(n.b) + ") is in view and no rank draws it");
    }
  }
}

void describe(const ForestSpec& spec, const RandomForest& forest, const View& view,
              const SelectionSpec& selection)
{
  static const bool enabled = std::getenv("CANOPY_FUZZ_DESCRIBE") != nullptr;
  if (enabled)
  {
    std::fprintf(stderr,
                 "canopy filters fuzz input: %s; %zu node(s), %zu leaves; %s; selection: %s; "
                 "%zu decision(s) within rounding; checked\n",
                 spec.describe.c_str(), forest.numberOfNodes(), forest.numberOfLeaves(),
                 viewStr(view).c_str(), selection.describe.c_str(), Ambiguous);
  }
}

/// vtkCanopyContour (2D, 3D) of a linear field f = a . x on the grid, at a value
/// inside its range, in full and with the view's level of detail (no culling):
/// every point farther than half a root cell from the boundary on the plane
/// f = c (to rounding), none strictly inside a hidden (at full resolution)
/// leaf or a root cell without a tree, no cell twice, and, with neither, every
/// triangle edge (3D) or segment end (2D) not on the domain's boundary used
/// exactly twice (watertight: DualTraversal.h's claim, checked on any forest).
void checkContour(const GridTruth& g, const View& view, const std::array<double, 3>& a,
                  double fraction, bool anyHidden, const std::string& label)
{
  if (g.dimension < 2)
  {
    return;
  }
  vtkNew<vtkDoubleArray> linear;
  linear->SetName("fuzz_linear");
  linear->SetNumberOfTuples(g.htg->GetNumberOfCells());
  linear->Fill(0);
  double low = 1e300;
  double high = -1e300;
  for (std::size_t id = 0; id < g.nodes.size(); ++id)
  {
    const NodeTruth& n = g.nodes[id];
    if (!n.reached)
    {
      continue;
    }
    double f = 0;
    for (int k = 0; k < 3; ++k)
    {
      f += a[static_cast<std::size_t>(k)] * 0.5 * (n.b[2 * k] + n.b[2 * k + 1]);
    }
    linear->SetValue(static_cast<vtkIdType>(id), f);
    low = std::min(low, f);
    high = std::max(high, f);
  }
  g.htg->GetCellData()->AddArray(linear);
  const double value = low + (high - low) * fraction;
  const double slope = std::abs(a[0]) + std::abs(a[1]) + std::abs(a[2]);
  // Whether every root cell is the same square or cube.
  bool equalRoots = true;
  double side = -1;
  for (int k : g.active)
  {
    const auto& x = g.coords[static_cast<std::size_t>(k)];
    for (std::size_t i = 1; i < x.size(); ++i)
    {
      side = side < 0 ? x[i] - x[i - 1] : side;
      equalRoots = equalRoots && x[i] - x[i - 1] == side;
    }
  }
  double rootHalf = 0;
  for (int k : g.active)
  {
    const auto& x = g.coords[static_cast<std::size_t>(k)];
    for (std::size_t i = 1; i < x.size(); ++i)
    {
      rootHalf = std::max(rootHalf, 0.5 * (x[i] - x[i - 1]) * (1 + 1e-9));
    }
  }
  vtkNew<vtkCanopyContour> filter;
  ErrorWatch errors(filter);
  filter->SetController(nullptr);
  filter->SetInputData(g.htg);
  filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "fuzz_linear");
  filter->SetValue(0, value);
  auto run = [&](const std::string& what, bool fullResolution)
  {
    Stage = label + ", contour " + what;
    filter->Update();
    errors.check(Stage);
    vtkPolyData* out = filter->GetOutput();
    for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
    {
      double x[3];
      out->GetPoint(p, x);
      // Within half a root cell of the boundary a point may come from a boundary
      // vertex, whose value is extrapolated with a fitted gradient: constant where
      // a leaf's neighbours do not span the dimension (masks, a root one cell
      // thick; docs/filters.md). Farther in, every dual edge joins leaf centres.
      bool inner = true;
      for (int k : g.active)
      {
        inner = inner && x[k] - g.bounds[2 * k] > rootHalf && g.bounds[2 * k + 1] - x[k] > rootHalf;
      }
      const double f = a[0] * x[0] + a[1] * x[1] + a[2] * x[2];
      if (inner && std::abs(f - value) > 1e-9 * slope * g.scale)
      {
        fail(Stage + ": a point off the plane: f = " + str(f) + ", the value " + str(value));
      }
      // With level of detail a node of a pixel or less holding masked cells is
      // contoured as one coarse leaf, and where root cells of other shapes meet an
      // edge between two leaves' centres can cut the corner of a third leaf
      // (docs/filters.md): full resolution over equal cubic roots only.
      for (std::size_t id = 0; fullResolution && equalRoots && id < g.nodes.size(); ++id)
      {
        const NodeTruth& n = g.nodes[id];
        if (!n.reached || !n.masked)
        {
          continue;
        }
        bool inside = true;
        for (int k : g.active)
        {
          inside = inside && x[k] > n.b[2 * k] + g.tol && x[k] < n.b[2 * k + 1] - g.tol;
        }
        if (inside)
        {
          fail(Stage + ": a point inside masked cell " + std::to_string(id));
        }
      }
    }
    std::map<std::vector<vtkIdType>, int> cells;
    std::map<std::vector<vtkIdType>, int> uses;
    vtkCellArray* drawn = g.dimension == 2 ? out->GetLines() : out->GetPolys();
    vtkNew<vtkIdList> ids;
    drawn->InitTraversal();
    while (drawn->GetNextCell(ids))
    {
      std::vector<vtkIdType> c(ids->GetPointer(0), ids->GetPointer(0) + ids->GetNumberOfIds());
      std::sort(c.begin(), c.end());
      if (++cells[c] > 1)
      {
        fail(Stage + ": a cell drawn twice");
      }
      for (std::size_t i = 0; i < c.size(); ++i)
      {
        if (g.dimension == 2)
        {
          ++uses[{c[i]}];
        }
        for (std::size_t j = i + 1; g.dimension == 3 && j < c.size(); ++j)
        {
          ++uses[{c[i], c[j]}];
        }
      }
    }
    if (anyHidden)
    {
      return;
    }
    for (const auto& [key, count] : uses)
    {
      // Along the boundary: every end on one side of the domain's box (boundary
      // vertices lie exactly on it).
      bool boundary = false;
      for (int k : g.active)
      {
        for (int side = 0; side < 2; ++side)
        {
          bool all = true;
          for (vtkIdType id : key)
          {
            all = all && out->GetPoint(id)[k] == g.bounds[2 * k + side];
          }
          boundary = boundary || all;
        }
      }
      if (!boundary && count != 2)
      {
        fail(Stage + ": " + (g.dimension == 2 ? "a segment end" : "a triangle edge") + " used by " +
             std::to_string(count) + " cells (a crack)");
      }
    }
  };
  filter->ViewDependentOff();
  run("without a view", true);
  filter->ViewDependentOn();
  filter->SetViewCulling(false);
  filter->SetLevelOfDetail(true);
  view.configure(filter);
  run("with level of detail", false);
  g.htg->GetCellData()->RemoveArray("fuzz_linear");
}

} // namespace
} // namespace canopy::testing

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
  // Failures are reported through ErrorWatch, not printed by VTK.
  vtkObject::GlobalWarningDisplayOff();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  using namespace canopy::testing;
  Input in(data, size);
  Ambiguous = 0;
  Stage = "decoding";
  const ForestSpec spec = decodeForest(in);
  Decoded = spec.describe;
  RandomForest forest(spec.options);
  if (forest.numberOfNodes() > NodeBudget ||
      std::any_of(forest.nodes().begin(), forest.nodes().end(),
                  [](const auto& tree) { return tree.size() > TreeNodeBudget; }) ||
      forest.description().trees.empty())
  {
    return -1; // too large for milliseconds, or nothing to look at: not kept
  }
  if (spec.dyadic)
  {
    // Bounds exact in binary (SelectionRegionsTest.cxx's coordinates).
    auto& coords = const_cast<std::array<std::vector<double>, 3>&>(forest.coordinates());
    for (int a = 0; a < 3; ++a)
    {
      for (std::size_t i = 0; i < coords[a].size(); ++i)
      {
        coords[a][i] =
            spec.options.origin[a] + 0.75 * static_cast<double>(i) + (i % 2 ? 0.25 : 0.0);
      }
    }
  }
  const WholeFields fields(forest);
  const bool exact = spec.dyadic && spec.options.branchFactor == 2;
  auto htg = canopy::buildHyperTreeGrid(forest.description());
  GridTruth whole = readGrid(htg, exact);
  mapWhole(whole, forest);
  View view = decodeView(in, whole.bounds, std::max(whole.extent, 1.0));
  view.prepare(whole);
  const SelectionSpec selection = decodeSelection(in, whole, view, spec.ranks > 1);
  Decoded += "; " + viewStr(view) + "; selection: " + selection.describe;

  const int f = spec.options.branchFactor;
  // The contour's field and value (bytes after the selection: older inputs read 0s).
  std::array<double, 3> gradient{{1 + in.byte() / 64.0, in.byte() / 64.0 - 2, in.byte() / 80.0}};
  const double fraction = 0.05 + 0.9 * in.byte() / 255.0;
  const SurfaceRuns surfaces = checkSurfaces(whole, view, f, true, "whole forest");
  checkContour(whole, view, gradient, fraction,
               spec.options.maskProbability > 0 || spec.options.skipEveryOtherRoot, "whole forest");
  const auto selected = checkSelection(whole, selection, true, "whole forest");
  if (spec.ranks > 1)
  {
    const bool masked = spec.options.maskProbability > 0;
    SurfaceResult full;
    SurfaceResult culled;
    std::vector<std::pair<long, long>> lod;
    std::vector<std::pair<long, long>> selectedOnRanks;
    for (int rank = 0; rank < spec.ranks; ++rank)
    {
      RankPart part(forest.description(), rank, spec.ranks, rank % 2 == 1);
      // RankPart describes no mask: each rank masks what the whole forest masks.
      std::vector<std::vector<std::uint8_t>> masks;
      for (const PartitionedTree& tree : part.trees)
      {
        const auto& wholeMask = forest.masked()[tree.wholeTree];
        std::vector<std::uint8_t> mask;
        for (std::size_t n : tree.wholeNode)
        {
          mask.push_back(wholeMask.empty() ? 0 : wholeMask[n]);
        }
        masks.push_back(std::move(mask));
      }
      for (std::size_t t = 0; masked && t < part.trees.size(); ++t)
      {
        part.description.trees[t].masked = masks[t].data();
      }
      auto rankHtg = canopy::buildHyperTreeGrid(part.description);
      GridTruth g = readGrid(rankHtg, exact);
      mapRank(g, part, forest.childrenPerNode());
      View rankView = view;
      rankView.prepare(g);
      const std::string label =
          "rank " + std::to_string(rank) + " of " + std::to_string(spec.ranks);
      const SurfaceRuns runs = checkSurfaces(g, rankView, f, false, label);
      full.planarWhole.insert(full.planarWhole.end(), runs.full.planarWhole.begin(),
                              runs.full.planarWhole.end());
      culled.planarWhole.insert(culled.planarWhole.end(), runs.culled.planarWhole.begin(),
                                runs.culled.planarWhole.end());
      full.quads.insert(runs.full.quads.begin(), runs.full.quads.end());
      culled.quads.insert(runs.culled.quads.begin(), runs.culled.quads.end());
      lod.insert(lod.end(), runs.lod.begin(), runs.lod.end());
      // Ids are each grid's own: the ranks' ids name other cells.
      if (selection.mode != Ids)
      {
        const auto mine = checkSelection(g, selection, false, label);
        selectedOnRanks.insert(selectedOnRanks.end(), mine.begin(), mine.end());
      }
    }
    Stage = "the ranks together";
    if (whole.dimension == 3)
    {
      // With a mask, faces between ranks' parts need the ranks' exchange (MPI: tests/mpi).
      if (!masked && (full.quads != surfaces.full.quads || culled.quads != surfaces.culled.quads))
      {
        fail("the ranks' 3D faces together are not the whole forest's (full: " +
             std::to_string(full.quads.size()) + " and " +
             std::to_string(surfaces.full.quads.size()) +
             ", culled: " + std::to_string(culled.quads.size()) + " and " +
             std::to_string(surfaces.culled.quads.size()) + ")");
      }
    }
    else
    {
      compareRanks("full surfaces", surfaces.full.planarWhole, full.planarWhole);
      compareRanks("culled surfaces", surfaces.culled.planarWhole, culled.planarWhole);
      checkRanksLod(whole, forest, view, lod);
    }
    if (selection.mode != Ids)
    {
      compareRanks("selections", selected, selectedOnRanks);
    }
  }
  describe(spec, forest, view, selection);
  return 0;
}
