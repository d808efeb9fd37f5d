#include "ContourBuilder.h"

#include "DualCellContour.h"

#include <algorithm>
#include <memory>

namespace canopy
{

namespace
{

/// Tasks per chunk: a fixed split (not per thread), so that the output order is
/// the same on any number of threads.
constexpr vtkIdType ChunkTasks = 16;

} // namespace

ContourBuilder::ContourBuilder(const HyperTreeAccess& grid, const ContourField& field,
                               const std::vector<double>& values, int maximumLevel,
                               const ViewOptions& view)
    : Grid(grid), Field(field), Values(values),
      Dual(grid, maximumLevel, view.view, view.levelOfDetail, view.pixelThreshold),
      Cull(view.view && view.cullOutsideView)
{
}

std::shared_ptr<const NodeRanges> ContourBuilder::ranges(const ProgressShare& progress) const
{
  if (Dual.ghosts())
  {
    // Other ranks' leaves, as the view made them (ContourGhosts::collect):
    // over the traversal's own forest, ghosts included, never kept.
    return std::make_shared<const NodeRanges>(Grid, Dual, Field, progress);
  }
  // Over the forest without the view: the same ranges for every camera
  // (DualCellContour::enter widens what a view's coarse leaves change).
  const DualTraversal withoutView(Grid, Dual.maximumLevel());
  return std::make_shared<const NodeRanges>(Grid, withoutView, Field, progress);
}

bool ContourBuilder::run(const ProgressShare& walk, const NodeRanges* ranges)
{
  const vtkIdType tasks = Dual.numberOfTasks();
  const vtkIdType chunks = (tasks + ChunkTasks - 1) / ChunkTasks;
  Pieces.assign(static_cast<std::size_t>(chunks), ContourPiece{});
  for (std::size_t c = 0; c < Pieces.size(); ++c)
  {
    Pieces[c].id = static_cast<std::uint32_t>(c);
  }
  std::vector<std::size_t> visited(static_cast<std::size_t>(chunks), 0);
  std::vector<std::size_t> cells(static_cast<std::size_t>(chunks), 0);
  std::vector<std::size_t> pruned(static_cast<std::size_t>(chunks), 0);
  std::vector<std::size_t> culled(static_cast<std::size_t>(chunks), 0);
  const bool done =
      forEachTree(walk, chunks,
                  [&](vtkIdType chunk)
                  {
                    const std::size_t c = static_cast<std::size_t>(chunk);
                    DualCellContour contour(Grid, Dual, Field, Values, Pieces[c], ranges, Cull);
                    const vtkIdType end = std::min(tasks, (chunk + 1) * ChunkTasks);
                    for (vtkIdType t = chunk * ChunkTasks; t < end; ++t)
                    {
                      Dual.runTask(t, contour);
                    }
                    visited[c] = contour.visited();
                    cells[c] = contour.dualCells();
                    pruned[c] = contour.pruned();
                    culled[c] = contour.culled();
                  });
  Visited = 0;
  Pruned = 0;
  Culled = 0;
  DualCells = 0;
  for (std::size_t c = 0; c < visited.size(); ++c)
  {
    Visited += visited[c];
    Pruned += pruned[c];
    Culled += culled[c];
    DualCells += cells[c];
  }
  return done;
}

ContourResult ContourBuilder::merge() const
{
  ContourResult result;
  result.verticesPerCell = Dual.dimension() == 2 ? 2 : 3;
  std::size_t points = 0;
  std::size_t cells = 0;
  for (const ContourPiece& piece : Pieces)
  {
    points += piece.points.size();
    cells += piece.cells.size();
  }
  // Points on dual edges near a chunk's border are made by both chunks: one
  // map over their keys (no geometric search) merges them; a chunk's own
  // points (ContourPiece.h) are not looked up.
  std::size_t shared = 0;
  for (const ContourPiece& piece : Pieces)
  {
    shared += static_cast<std::size_t>(std::count(piece.shared.begin(), piece.shared.end(), 1));
  }
  ContourPointIndex merged;
  merged.reserve(shared);
  result.points.reserve(points);
  result.contours.reserve(points);
  result.leaves.reserve(points);
  result.weights.reserve(points);
  result.cells.reserve(cells);
  std::vector<vtkIdType> local;
  for (const ContourPiece& piece : Pieces)
  {
    const vtkIdType centroidOffset = static_cast<vtkIdType>(result.centroids.size());
    result.centroids.insert(result.centroids.end(), piece.centroids.begin(), piece.centroids.end());
    local.resize(piece.points.size());
    for (std::size_t p = 0; p < piece.points.size(); ++p)
    {
      const auto inserted =
          piece.shared[p]
              ? merged.emplace(piece.keys[p], static_cast<vtkIdType>(result.points.size()))
              : std::make_pair(static_cast<vtkIdType>(result.points.size()), true);
      local[p] = inserted.first;
      if (inserted.second)
      {
        result.points.push_back(piece.points[p]);
        result.contours.push_back(piece.keys[p].contour);
        auto leaves = piece.leaves[p];
        for (vtkIdType& leaf : leaves)
        {
          leaf = leaf < 0 ? leaf - centroidOffset : leaf;
        }
        result.leaves.push_back(leaves);
        result.weights.push_back(piece.weights[p]);
      }
    }
    for (vtkIdType id : piece.cells)
    {
      result.cells.push_back(local[static_cast<std::size_t>(id)]);
    }
    result.cellNormals.insert(result.cellNormals.end(), piece.cellNormals.begin(),
                              piece.cellNormals.end());
    result.foreign.insert(result.foreign.end(), piece.foreign.begin(), piece.foreign.end());
  }
  return result;
}

} // namespace canopy
