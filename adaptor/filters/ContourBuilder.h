// A contour of a grid: the dual traversal's tasks run in parallel in fixed
// chunks (DualTraversal.h, DualCellContour.h), each into its own ContourPiece,
// and the pieces merged by their points' keys into one output, in chunk order:
// the output does not depend on the number of threads.
#pragma once

#include "ContourField.h"
#include "ContourPiece.h"
#include "DualTraversal.h"
#include "NodeRanges.h"
#include "TreeProgress.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace canopy
{

/// The merged contour: points, cells, and what the output's arrays are made of.
struct ContourResult
{
  std::vector<std::array<double, 3>> points;
  std::vector<std::uint32_t> contours; ///< per point: the index of its contour value
  /// Per point: its edge's leaves (a centroid: -(k + 1), k in `centroids`).
  std::vector<std::array<vtkIdType, 2>> leaves;
  std::vector<ContourPiece::Centroid> centroids; ///< per centroid: its leaves
  std::vector<double> weights;                   ///< per point: the second leaf's weight
  int verticesPerCell = 2;                       ///< 2: segments (2D), 3: triangles (3D)
  std::vector<vtkIdType> cells;
  std::vector<std::array<double, 3>> cellNormals; ///< 3D: per triangle (ContourPiece)
  std::vector<unsigned char> foreign;             ///< 3D: per triangle (ContourPiece)
};

class ContourBuilder
{
public:
  /// Everything is borrowed and must outlive the builder. `maximumLevel`:
  /// DualTraversal's (-1: every level).
  ContourBuilder(const HyperTreeAccess& grid, const ContourField& field,
                 const std::vector<double>& values, int maximumLevel = -1,
                 const ViewOptions& view = {});

  /// Other ranks' border leaves (borrowed for the builder's life, or nullptr):
  /// their parts of the grid are seen through them (ContourGhosts.h). Before
  /// ranges() and run().
  void setGhosts(const ContourGhosts* ghosts) { Dual.setGhosts(ghosts); }

  /// The nodes' value ranges pruning needs (NodeRanges.h), for run(); a
  /// caller may keep them while the grid's topology and the field hold.
  std::shared_ptr<const NodeRanges> ranges(const ProgressShare& progress) const;

  /// Runs the traversal (false: stopped by `progress`; the result is then
  /// partial). With `ranges` (borrowed for the call), only the groups whose
  /// ranges hold a contour value are descended: the same output, less work.
  bool run(const ProgressShare& progress, const NodeRanges* ranges = nullptr);
  /// The pieces merged (after run).
  ContourResult merge() const;

  /// Groups descended, groups pruned and dual cells met by the last run.
  std::size_t visited() const { return Visited; }
  std::size_t pruned() const { return Pruned; }
  std::size_t culled() const { return Culled; }
  std::size_t dualCells() const { return DualCells; }

private:
  const HyperTreeAccess& Grid;
  const ContourField& Field;
  const std::vector<double>& Values;
  DualTraversal Dual;
  bool Cull = false;
  std::vector<ContourPiece> Pieces;
  std::size_t Visited = 0;
  std::size_t Pruned = 0;
  std::size_t Culled = 0;
  std::size_t DualCells = 0;
};

} // namespace canopy
