// The adaptive surface's passes over the trees (AdaptiveSurfaceBuilder.h):
// count, exchange with other ranks, write. Each tree is walked by the walk of
// its grid's dimension (SurfaceWalk.h).
#include "AdaptiveSurfaceBuilder.h"

#include "CellSink.h"
#include "EdgeVertices.h"
#include "FaceSide.h"
#include "FullSurfaceWalk.h"
#include "GridSection.h"
#include "PlanarSurfaceWalk.h"
#include "SolidSurfaceWalk.h"
#include "TreeProgress.h"

#include <vtkSMPTools.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <stdexcept>

namespace canopy
{

namespace
{

/// One tree's surface into `sink`, by the walk of the grid's dimension.
void walkSurface(const HyperTreeAccess& grid, const TreeAccess& tree, const SurfaceOptions& options,
                 const GridSection* region, CellSink& sink)
{
  if (grid.dimension() == 3)
  {
    SolidSurfaceWalk(grid, tree, options, sink).walk();
  }
  else
  {
    PlanarSurfaceWalk(grid, tree, options, region, sink).walk();
  }
}

} // namespace

void copyKeptCells(const std::vector<TreeCells>& kept, const std::vector<std::size_t>& cellOffsets,
                   const std::vector<std::size_t>& pointOffsets, const SurfaceArrays& arrays)
{
  // A copy: not worth reporting progress or stopping.
  vtkSMPTools::For(
      0, static_cast<vtkIdType>(kept.size()),
      [&](vtkIdType begin, vtkIdType end)
      {
        for (vtkIdType i = begin; i < end; ++i)
        {
          const TreeCells& cells = kept[static_cast<std::size_t>(i)];
          const std::size_t first = cellOffsets[static_cast<std::size_t>(i)];
          std::size_t point = pointOffsets[static_cast<std::size_t>(i)];
          std::copy(cells.points.begin(), cells.points.end(), arrays.points + 3 * point);
          vtkIdType* offset = arrays.offsets + first;
          for (std::uint32_t size : cells.sizes)
          {
            *offset++ = static_cast<vtkIdType>(point);
            point += size;
          }
          std::copy(cells.cellIds.begin(), cells.cellIds.end(), arrays.cellIds + first);
          std::copy(cells.levels.begin(), cells.levels.end(), arrays.levels + first);
          if (arrays.colors)
          {
            std::copy(cells.colors.begin(), cells.colors.end(), arrays.colors + 3 * first);
          }
        }
      });
  arrays.offsets[cellOffsets.empty() ? 0 : cellOffsets.back()] =
      static_cast<vtkIdType>(pointOffsets.empty() ? 0 : pointOffsets.back());
}

AdaptiveSurfaceBuilder::AdaptiveSurfaceBuilder(const HyperTreeAccess& grid,
                                               const SurfaceOptions& options,
                                               std::vector<TreeCells>* buffers,
                                               const ProgressShare& progress)
    : Grid(grid), Options(options), Progress(progress), Lent(buffers)
{
  if (Lent)
  {
    Kept.swap(*Lent);
  }
  if (Grid.dimension() < 3 && Options.view && Options.cullOutsideView)
  {
    Region =
        std::make_unique<GridSection>(Grid, Options.view->halfSpaces(), Options.view->anchor());
  }
}

AdaptiveSurfaceBuilder::~AdaptiveSurfaceBuilder()
{
  if (Lent)
  {
    Lent->swap(Kept);
  }
}

bool AdaptiveSurfaceBuilder::fullPlanarSurface() const
{
  return Grid.dimension() < 3 && Grid.branchFactor() <= 3 &&
         (!Options.view || (!Options.cullOutsideView && !Options.levelOfDetail));
}

std::size_t AdaptiveSurfaceBuilder::count()
{
  const auto& trees = Grid.trees();
  std::vector<std::size_t> counts(trees.size(), 0);
  std::vector<std::size_t> pointCounts(trees.size(), 0);
  // A full 1D/2D surface has one cell per visible leaf: a kept access knows how
  // many per tree, so one walk (the writing one) suffices.
  const bool known = std::all_of(trees.begin(), trees.end(),
                                 [](const TreeAccess& t) { return t.visibleLeaves >= 0; });
  CountWalked = false;
  // Cells are kept to be copied when that is cheaper than a second walk (3D; 2D
  // with level of detail: the output is bounded by the view's pixels, and the
  // writing walk would repeat every decision and edge search), or to take the
  // vertices other ranks put on their edges (2D, split grids).
  const bool levelOfDetail = Options.view && Options.levelOfDetail;
  const bool keep = Grid.dimension() == 3 ||
                    (Grid.dimension() == 2 && (Options.sharedVertices || levelOfDetail));
  if (!keep)
  {
    Kept.clear(); // buffers lent from an execution that kept its cells: not used here
  }
  if (fullPlanarSurface() && known && !keep)
  {
    std::transform(trees.begin(), trees.end(), counts.begin(),
                   [](const TreeAccess& t) { return static_cast<std::size_t>(t.visibleLeaves); });
    // Their points, once per topology: a walk that writes nothing.
    CountWalked = std::any_of(trees.begin(), trees.end(),
                              [](const TreeAccess& t) { return t.fullSurfacePoints < 0; });
    forEachTree(CountWalked ? Progress.part(0, 0.5) : ProgressShare{},
                static_cast<vtkIdType>(trees.size()),
                [&](vtkIdType t)
                {
                  const TreeAccess& tree = trees[static_cast<std::size_t>(t)];
                  if (tree.fullSurfacePoints < 0)
                  {
                    const SurfaceArrays none{nullptr, nullptr, nullptr, nullptr};
                    tree.fullSurfacePoints =
                        static_cast<vtkIdType>(writeFullSurface(Grid, tree, none, 0, 0, 0).points);
                  }
                  pointCounts[static_cast<std::size_t>(t)] =
                      static_cast<std::size_t>(tree.fullSurfacePoints);
                });
  }
  else
  {
    if (keep)
    {
      // Cleared, not freed: lent buffers keep their capacity.
      Kept.resize(trees.size());
      for (TreeCells& cells : Kept)
      {
        cells.points.clear();
        cells.sizes.clear();
        cells.cellIds.clear();
        cells.levels.clear();
        cells.colors.clear();
        cells.asked.clear();
        cells.shared.clear();
        cells.sharedCells.clear();
      }
    }
    // Kept cells (3D) are only copied afterwards: then this walk is all the work.
    CountWalked = true;
    forEachTree(
        Kept.empty() ? Progress.part(0, 0.5) : Progress, static_cast<vtkIdType>(trees.size()),
        [&](vtkIdType t)
        {
          CellSink sink;
          sink.keep = Kept.empty() ? nullptr : &Kept[static_cast<std::size_t>(t)];
          walkSurface(Grid, trees[static_cast<std::size_t>(t)], Options, Region.get(), sink);
          counts[static_cast<std::size_t>(t)] = sink.next;
          pointCounts[static_cast<std::size_t>(t)] = sink.nextPoint;
        });
  }
  AskedAt.clear();
  for (std::size_t t = 0; t < Kept.size(); ++t)
  {
    for (std::size_t k = 0; k < Kept[t].asked.size(); ++k)
    {
      AskedAt.emplace_back(t, k);
    }
  }
  computeOffsets(counts, pointCounts);
  return Offsets.back();
}

void AdaptiveSurfaceBuilder::computeOffsets(const std::vector<std::size_t>& counts,
                                            const std::vector<std::size_t>& pointCounts)
{
  // Trees write at prefix-sum offsets: the output order is the tree order, the
  // same for any number of threads.
  Offsets.assign(counts.size() + 1, 0);
  PointOffsets.assign(counts.size() + 1, 0);
  for (std::size_t t = 0; t < counts.size(); ++t)
  {
    Offsets[t + 1] = Offsets[t] + counts[t];
    PointOffsets[t + 1] = PointOffsets[t] + pointCounts[t];
  }
}

std::vector<RemoteFace> AdaptiveSurfaceBuilder::remoteFaces() const
{
  std::vector<RemoteFace> faces;
  faces.reserve(AskedAt.size());
  for (const auto& [t, k] : AskedAt)
  {
    faces.push_back(Kept[t].asked[k].face);
  }
  return faces;
}

std::vector<RemotePiece>
AdaptiveSurfaceBuilder::answerRemoteFaces(const std::vector<RemoteFace>& faces) const
{
  // The other side of each face, in the trees this rank has: what it masks
  // there shows; what it does not have (absent, or no tree) another rank answers.
  std::vector<RemotePiece> pieces;
  const FaceSide side{Grid, Options};
  for (std::size_t q = 0; q < faces.size(); ++q)
  {
    const RemoteFace& f = faces[q];
    const FacePosition n{{{static_cast<long>(f.root[0]), static_cast<long>(f.root[1]),
                           static_cast<long>(f.root[2])}},
                         static_cast<int>(f.level),
                         f.ijk};
    const int axis = static_cast<int>(f.axis);
    const int towards = static_cast<int>(f.side);
    if (axis < 0 || axis > 2 || f.level < 0 || f.level > Grid.maxLevel())
    {
      continue; // not a face of a grid like this one: nothing of it is here
    }
    Index3 position;
    const SolidNeighbours::Neighbour across = side.across(n, axis, towards, position);
    if (!across.tree)
    {
      continue; // no tree here on the other side
    }
    const FaceState state = side.stateOf(across);
    if ((state == FaceState::Whole || state == FaceState::Parts) &&
        side.coarserStopCovers(n, axis, towards))
    {
      continue; // this rank draws a coarser node there whole: the face is inside it
    }
    if (state == FaceState::Whole)
    {
      pieces.push_back({q, true, {{0, 0, 0}}, {{0, 0, 0}}});
    }
    else if (state == FaceState::Parts)
    {
      side.exposedParts(
          *across.tree, WalkNode{across.node, n.level, position}, axis, towards,
          [&](const WalkNode& child)
          {
            RemotePiece piece{q, false, {{0, 0, 0}}, {{0, 0, 0}}, child.level, child.ijk};
            Grid.nodeBounds(*across.tree, child.level, child.ijk, piece.lo, piece.hi);
            pieces.push_back(piece);
          },
          [](const WalkNode&) {});
    }
  }
  return pieces;
}

void AdaptiveSurfaceBuilder::addRemotePieces(const std::vector<RemotePiece>& pieces)
{
  const auto& trees = Grid.trees();
  for (const RemotePiece& piece : pieces)
  {
    if (piece.face >= AskedAt.size())
    {
      throw std::invalid_argument("a remote piece answers a face that was not asked");
    }
    const auto [t, k] = AskedAt[piece.face];
    const AskedFace& asked = Kept[t].asked[k];
    CellSink sink;
    sink.keep = &Kept[t];
    SolidSurfaceWalk walk(Grid, trees[t], Options, sink);
    // The node whose face it is, entered as the walk entered it.
    const WalkNode n = walk.enterPath(static_cast<int>(asked.face.level), asked.face.ijk);
    const int axis = static_cast<int>(asked.face.axis);
    const int side = static_cast<int>(asked.face.side);
    Vec3 lo;
    Vec3 hi;
    Grid.nodeBounds(trees[t], n.level, n.ijk, lo, hi);
    // The piece's cell on this side: n, or the cell of n facing the owner's hole.
    Index3 cell = n.ijk;
    int level = n.level;
    if (!piece.whole)
    {
      if (piece.level < n.level || piece.level > Grid.maxLevel())
      {
        throw std::invalid_argument("a remote piece is coarser than its face, or too deep");
      }
      level = static_cast<int>(piece.level);
      const std::int64_t scale = Grid.cellsPerRootAt(level - n.level);
      cell = piece.ijk;
      cell[axis] = side ? (n.ijk[axis] + 1) * scale - 1 : n.ijk[axis] * scale;
    }
    walk.emitFace(axis, side, n, lo, hi, piece.whole ? lo : piece.lo, piece.whole ? hi : piece.hi,
                  level, cell, asked.global, asked.inside);
  }
  std::vector<std::size_t> counts(Kept.size());
  std::vector<std::size_t> pointCounts(Kept.size());
  for (std::size_t t = 0; t < Kept.size(); ++t)
  {
    counts[t] = Kept[t].cellIds.size();
    pointCounts[t] = Kept[t].points.size() / 3;
  }
  computeOffsets(counts, pointCounts);
}

std::vector<SharedEdge> AdaptiveSurfaceBuilder::sharedEdges() const
{
  std::vector<SharedEdge> edges;
  for (const TreeCells& cells : Kept)
  {
    edges.insert(edges.end(), cells.shared.begin(), cells.shared.end());
  }
  return edges;
}

void AdaptiveSurfaceBuilder::addSharedVertices(const SharedVertices& shared)
{
  std::vector<std::size_t> counts(Kept.size());
  std::vector<std::size_t> pointCounts(Kept.size());
  vtkSMPTools::For(0, static_cast<vtkIdType>(Kept.size()),
                   [&](vtkIdType begin, vtkIdType end)
                   {
                     for (vtkIdType t = begin; t < end; ++t)
                     {
                       TreeCells& cells = Kept[static_cast<std::size_t>(t)];
                       insertSharedVertices(cells, cells.sharedCells, shared);
                       counts[static_cast<std::size_t>(t)] = cells.cellIds.size();
                       pointCounts[static_cast<std::size_t>(t)] = cells.points.size() / 3;
                     }
                   });
  computeOffsets(counts, pointCounts);
}

void AdaptiveSurfaceBuilder::write(const SurfaceArrays& arrays) const
{
  const auto& trees = Grid.trees();
  if (!Kept.empty())
  {
    copyKeptCells(Kept, Offsets, PointOffsets, arrays);
    return;
  }
  const bool full = fullPlanarSurface();
  std::atomic<bool> mismatch{false};
  // The second half of the work, or all of it when count() did not walk.
  forEachTree(
      CountWalked ? Progress.part(0.5, 1) : Progress, static_cast<vtkIdType>(trees.size()),
      [&](vtkIdType t)
      {
        const std::size_t first = Offsets[static_cast<std::size_t>(t)];
        const std::size_t firstPoint = PointOffsets[static_cast<std::size_t>(t)];
        CellSink sink;
        sink.counting = false;
        sink.limit = Offsets[static_cast<std::size_t>(t) + 1] - first;
        sink.pointLimit = PointOffsets[static_cast<std::size_t>(t) + 1] - firstPoint;
        sink.pointBase = firstPoint;
        sink.arrays = {arrays.points + 3 * firstPoint, arrays.offsets + first,
                       arrays.cellIds + first, arrays.levels + first,
                       arrays.colors ? arrays.colors + 3 * first : nullptr};
        const TreeAccess& tree = trees[static_cast<std::size_t>(t)];
        if (full)
        {
          const FullSurfaceCount written =
              writeFullSurface(Grid, tree, sink.arrays, sink.limit, sink.pointLimit, firstPoint);
          sink.next = written.cells;
          sink.nextPoint = written.points;
          // Every cell of a full surface is a leaf: its own colour.
          for (std::size_t i = 0;
               Options.colors && sink.arrays.colors && i < std::min(sink.next, sink.limit); ++i)
          {
            const Rgb c = Options.colors->mapCell(sink.arrays.cellIds[i]);
            for (int k = 0; k < 3; ++k)
            {
              sink.arrays.colors[3 * i + k] = colorByte(c[k]);
            }
          }
        }
        else
        {
          walkSurface(Grid, tree, Options, Region.get(), sink);
        }
        if (sink.next != sink.limit || sink.nextPoint != sink.pointLimit)
        {
          mismatch = true; // never expected: counts come from the same topology
        }
      });
  if (mismatch)
  {
    throw std::logic_error("the surface's cell count changed between counting and writing");
  }
  arrays.offsets[cells()] = static_cast<vtkIdType>(points());
}

} // namespace canopy
