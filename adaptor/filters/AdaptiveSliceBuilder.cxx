#include "AdaptiveSliceBuilder.h"

#include "EdgeVertices.h"
#include "TreeProgress.h"
#include "TreeTraversal.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace canopy
{

std::string AdaptiveSliceBuilder::validate(const HyperTreeAccess& grid,
                                           const std::vector<SlicePlane>& planes)
{
  std::ostringstream out;
  if (grid.dimension() != 3)
  {
    out << "slices need a 3D grid, this one is " << grid.dimension() << "D";
    return out.str();
  }
  for (std::size_t i = 0; i < planes.size(); ++i)
  {
    if (planes[i].axis < 0 || planes[i].axis > 2)
    {
      out << (out.tellp() > 0 ? "; " : "") << "plane " << i << ": axis " << planes[i].axis
          << " is not 0 (x), 1 (y) or 2 (z)";
    }
    else if (!std::isfinite(planes[i].position))
    {
      out << (out.tellp() > 0 ? "; " : "") << "plane " << i << ": position " << planes[i].position
          << " is not finite";
    }
  }
  return out.str();
}

AdaptiveSliceBuilder::AdaptiveSliceBuilder(const HyperTreeAccess& grid,
                                           std::vector<SlicePlane> planes,
                                           const SliceOptions& options,
                                           const ProgressShare& progress)
    : Grid(grid), Planes(std::move(planes)), Options(options), Progress(progress)
{
}

std::size_t AdaptiveSliceBuilder::count()
{
  // The trees each plane cuts: the root cells of one layer of the root grid.
  Pieces.clear();
  for (std::size_t p = 0; p < Planes.size(); ++p)
  {
    const int axis = Planes[p].axis;
    const double position = Planes[p].position;
    const std::vector<double>& coordinates = Grid.coordinates(axis);
    if (position < coordinates.front() || position > coordinates.back())
    {
      continue; // outside the grid
    }
    // Half-open root cells, the last one closed (the face rule).
    const long layer = std::min<long>(
        static_cast<long>(std::upper_bound(coordinates.begin(), coordinates.end(), position) -
                          coordinates.begin()) -
            1,
        static_cast<long>(coordinates.size()) - 2);
    const int b = (axis + 1) % 3;
    const int c = (axis + 2) % 3;
    const auto& roots = Grid.rootCells();
    for (long j = 0; j < static_cast<long>(roots[c]); ++j)
    {
      for (long i = 0; i < static_cast<long>(roots[b]); ++i)
      {
        std::array<long, 3> ijk{{0, 0, 0}};
        ijk[axis] = layer;
        ijk[b] = i;
        ijk[c] = j;
        if (const TreeAccess* tree = Grid.treeAt(ijk[0], ijk[1], ijk[2]))
        {
          Pieces.push_back({tree, p});
        }
      }
    }
  }
  Kept.assign(Pieces.size(), TreeCells());
  std::vector<std::size_t> visited(Pieces.size(), 0);
  forEachTree(Progress, static_cast<vtkIdType>(Pieces.size()),
              [&](vtkIdType i)
              {
                const auto k = static_cast<std::size_t>(i);
                slice(Pieces[k], Kept[k], visited[k]);
              });
  Offsets.assign(Pieces.size() + 1, 0);
  PointOffsets.assign(Pieces.size() + 1, 0);
  Visited = 0;
  for (std::size_t k = 0; k < Pieces.size(); ++k)
  {
    Offsets[k + 1] = Offsets[k] + Kept[k].cellIds.size();
    PointOffsets[k + 1] = PointOffsets[k] + Kept[k].points.size() / 3;
    Visited += visited[k];
  }
  return Offsets.back();
}

void AdaptiveSliceBuilder::slice(const Piece& piece, TreeCells& cells, std::size_t& visited) const
{
  const TreeAccess& tree = *piece.tree;
  const int axis = Planes[piece.plane].axis;
  const double position = Planes[piece.plane].position;
  const int f = Grid.branchFactor();
  const ViewVolume* view = Options.view;
  const bool cull = view && Options.cullOutsideView;
  const bool lod = view && Options.levelOfDetail;
  const int b = (axis + 1) % 3;
  const int c = (axis + 2) % 3;
  // Child digit along the axis at each level (the children the plane cuts):
  // the number of inner boundaries between the node's children at or below the
  // plane. Every node the walk enters at a level has the same index along the
  // axis, and so has every tree of the plane's layer of roots (the same
  // coordinates along the axis): one digit per level, for all of them.
  std::vector<int> digit(static_cast<std::size_t>(Grid.maxLevel()) + 1, 0);
  std::int64_t index = 0;
  for (int level = 1; level <= Grid.maxLevel(); ++level)
  {
    const std::int64_t first = index * f;
    int d = 0;
    while (d + 1 < f && Grid.nodeLower(tree, level, axis, first + d + 1) <= position)
    {
      ++d;
    }
    digit[static_cast<std::size_t>(level)] = d;
    index = first + d;
  }

  // The children the plane cuts.
  auto cutChildren = [&](const WalkNode& parent, int child)
  { return Grid.childDigits(child)[axis] == digit[static_cast<std::size_t>(parent.level) + 1]; };
  // Whether a cell the plane cuts below `start` (in tree t) is masked.
  auto cutCellMaskedBelow = [&](const TreeAccess& t, const WalkNode& start, std::size_t& count)
  {
    bool masked = false;
    walkSubtree(
        Grid, t, start,
        [&](WalkNode& m)
        {
          ++count;
          if (m.node != start.node && Grid.isMasked(t.globalIndex(m.node)))
          {
            masked = true;
            return WalkStep::Stop;
          }
          return WalkStep::Descend;
        },
        cutChildren);
    return masked;
  };
  // Level of detail stops at an unmasked node (of tree t, its cross-section
  // [lo, hi]) with neither another rank's parts nor masked cells on the plane
  // below it: either would draw what is not this rank's or not there. Masks are
  // looked for only under a node it would stop at, only among the cells the
  // plane cuts (no pass over the grid).
  auto lodStops = [&](const TreeAccess& t, const WalkNode& n, const Vec3& lo, const Vec3& hi,
                      std::size_t& count)
  {
    return lod && !t.hasAbsentDescendant(n.node) &&
           view->footprintInPixels(rectangleCorners(lo, hi, b, c)) <= Options.pixelThreshold &&
           !(Grid.hasMask() && cutCellMaskedBelow(t, n, count));
  };
  // The same rule for the nodes across a drawn quad's edges (EdgeVertices.h),
  // culling aside: a culled neighbour draws nothing to meet.
  std::size_t ignored = 0;
  auto role = [&](const TreeAccess& t, const WalkNode& n)
  {
    const vtkIdType global = t.globalIndex(n.node);
    if (Grid.hasMask() && Grid.isMasked(global))
    {
      return Grid.isAbsent(global) ? EdgeRole::Remote : EdgeRole::Hidden;
    }
    if (t.isLeaf(n.node))
    {
      return EdgeRole::Drawn;
    }
    if (!lod)
    {
      return EdgeRole::Descend;
    }
    Vec3 nlo;
    Vec3 nhi;
    Grid.nodeBounds(t, n.level, n.ijk, nlo, nhi);
    nlo[axis] = nhi[axis] = position;
    return lodStops(t, n, nlo, nhi, ignored) ? EdgeRole::Drawn : EdgeRole::Descend;
  };
  // The vertices on a drawn quad's four edges (EdgeVertices.h).
  std::array<std::vector<double>, 4> onEdge;
  std::vector<Vec3> polygon;
  PlaneNeighbours plane(Grid, tree, b, c);
  EdgeScratch scratch;

  Vec3 lo{{0, 0, 0}};
  Vec3 hi{{0, 0, 0}};
  walkTree(
      Grid, tree,
      [&](WalkNode& n)
      {
        ++visited;
        plane.enter(n);
        vtkIdType global = -1;
        if (Grid.hasMask())
        {
          global = tree.globalIndex(n.node);
          if (Grid.isMasked(global))
          {
            return WalkStep::Skip; // masked, or another rank's part
          }
        }
        Grid.nodeBounds(tree, n.level, n.ijk, lo, hi);
        lo[axis] = hi[axis] = position; // the cross-section
        if (cull && !n.inherited)
        {
          switch (view->classifyBox(lo, hi))
          {
          case ViewVolume::BoxSide::Outside:
            return WalkStep::Skip;
          case ViewVolume::BoxSide::Inside:
            n.inherited = true; // so is every cut below it
            break;
          default:
            if (!view->overlapsBox(lo, hi))
            {
              return WalkStep::Skip;
            }
          }
        }
        const bool stop = tree.isLeaf(n.node) || lodStops(tree, n, lo, hi, visited);
        if (!stop)
        {
          return WalkStep::Descend;
        }
        if (global < 0)
        {
          global = tree.globalIndex(n.node);
        }
        // Counter-clockwise seen from +axis: the polygon's normal is +axis.
        const unsigned remote = rectangleEdgeVertices(Grid, n, plane.at(n.level), b, c, lo, hi,
                                                      axis, &digit, role, onEdge, scratch);
        if (remote)
        {
          // Along another rank's part: that rank's cuts put their corners there.
          for (int e = 0; e < 4; ++e)
          {
            if (remote & (1u << e))
            {
              cells.shared.push_back(sharedEdgeOf(e, b, c, lo, hi));
            }
          }
          cells.sharedCells.push_back(static_cast<std::uint32_t>(cells.cellIds.size()));
        }
        polygonAround(rectangleCorners(lo, hi, b, c), b, c, hi,
                      {{&onEdge[0], &onEdge[1], &onEdge[2], &onEdge[3]}}, polygon);
        for (const Vec3& p : polygon)
        {
          cells.points.insert(cells.points.end(), p.begin(), p.end());
        }
        cells.sizes.push_back(static_cast<std::uint32_t>(polygon.size()));
        cells.cellIds.push_back(global);
        cells.levels.push_back(static_cast<unsigned char>(n.level));
        if (Options.colors)
        {
          // A node drawn for level of detail: the average of the cut leaves below it.
          const Rgb color = tree.isLeaf(n.node)
                                ? Options.colors->mapCell(global)
                                : averageColor(Grid, tree, n, 2, *Options.colors, cutChildren);
          for (double channel : color)
          {
            cells.colors.push_back(colorByte(channel));
          }
        }
        return WalkStep::Skip;
      },
      cutChildren);
}

std::vector<SharedEdge> AdaptiveSliceBuilder::sharedEdges() const
{
  std::vector<SharedEdge> edges;
  for (const TreeCells& cells : Kept)
  {
    edges.insert(edges.end(), cells.shared.begin(), cells.shared.end());
  }
  return edges;
}

void AdaptiveSliceBuilder::addSharedVertices(const SharedVertices& shared)
{
  for (std::size_t k = 0; k < Kept.size(); ++k)
  {
    insertSharedVertices(Kept[k], Kept[k].sharedCells, shared);
    PointOffsets[k + 1] = PointOffsets[k] + Kept[k].points.size() / 3;
  }
}

void AdaptiveSliceBuilder::write(const SurfaceArrays& arrays) const
{
  copyKeptCells(Kept, Offsets, PointOffsets, arrays);
}

} // namespace canopy
