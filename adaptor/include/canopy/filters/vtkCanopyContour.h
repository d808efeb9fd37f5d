/**
 * @class vtkCanopyContour
 * @brief Isolines (2D) and isosurfaces (3D) of a cell field of a
 * vtkHyperTreeGrid, crack-free across refinement levels and trees, reaching
 * the domain's boundary.
 *
 * The field's values sit at the leaves' centres (a hypertree grid has no point
 * data). The filter contours the dual of the grid: one dual cell per vertex of
 * the grid, joining the centres of the 2^d leaves around it (fewer, distinct,
 * where levels differ), found by the recursive octree dual traversal across
 * trees, branch factor 2 or 3. Each dual cell is split into triangles (2D) or
 * tetrahedra (3D) through its diagonal from the all-lower to the all-upper leaf,
 * so neighbouring cells split their shared faces alike (a cell where that split
 * would fold: fans of tetrahedra from an inner point, its faces split alike),
 * and contoured by marching triangles or tetrahedra: every contour edge (3D) or
 * point (2D) not on the domain's or a hidden region's boundary is shared by
 * exactly two triangles (segments). Along the domain's boundary the dual is extended by boundary
 * vertices (a leaf's centre projected onto the boundary, its value extrapolated
 * with the leaf's least-squares gradient from its face neighbours), so the
 * contour reaches the boundary and a linear field's contour is exact there too.
 * Points are computed from their dual edge alone, in one order, and shared
 * through the edge's key: no geometric point locator.
 *
 * Masked cells and root cells without a tree are hidden: a dual cell touching
 * one is not contoured, so the contour stops (open) at a hidden region. Grids
 * split between processes (other processes' parts absent, or their trees
 * elsewhere): with a Controller of several processes, every execution is
 * collective over it. Each process sends its border leaves (those sharing a
 * vertex with another's part, with their face neighbours and ancestors) to all
 * in one AllGatherV and sees the others' parts through them; a dual cell is
 * drawn by the process owning its lowest slot's leaf. The processes' contours
 * together are the one-process contour, to the bit (docs/filters.md). A node
 * with several processes' leaves below is never contoured as a coarse leaf.
 * Without a controller a part is contoured alone, open along its borders.
 *
 * Field: the cell array selected with SetInputArrayToProcess(0, 0, 0,
 * vtkDataObject::FIELD_ASSOCIATION_CELLS, name) (default: the cell data's
 * active scalars), component ArrayComponent. Values: as vtkContourFilter's
 * (SetValue, SetNumberOfContours, GenerateValues).
 *
 * Output: vtkPolyData of double-precision points; 2D: VTK_LINE segments (higher
 * values on their left in the grid's plane), 3D: triangles whose normals point
 * towards lower values. Point data: the contour value (a double array named
 * after the field; ComputeScalars), "Normals" (3D, ComputeNormals: the
 * area-weighted mean of the adjacent triangles' normals, each against the
 * field's gradient in its tetrahedron), and each field added with
 * AddInterpolatedField, interpolated along the point's dual edge (a boundary
 * vertex takes its leaf's value). Contours in the order of their values'
 * indices within each part of the grid; the same on any number of threads.
 *
 * The view (vtkCanopyViewDependentFilter's camera, renderer or explicit
 * properties): ViewDependent is off by default here, the full contour. On, with
 * LevelOfDetail a node whose box spans at most PixelThreshold pixels is
 * contoured as a leaf holding its own (coarse) value, one answer per node, so
 * the coarser forest is crack-free by the same rule; with ViewCulling a group
 * of nodes whose box misses the view is not descended (the contour is then
 * open at the view's edge). The base's Fields and colours are not used.
 *
 * An execution reports its progress and checks for an abort between parts of
 * the grid; aborted, it leaves an empty output.
 */
#pragma once

#include "CanopyFiltersModule.h"

#include <canopy/filters/vtkCanopyViewDependentFilter.h>

#include <vtkSmartPointer.h>

#include <memory>
#include <string>
#include <vector>

class vtkContourValues;
class vtkPolyData;

class CANOPYFILTERS_EXPORT vtkCanopyContour : public vtkCanopyViewDependentFilter
{
public:
  static vtkCanopyContour* New();
  vtkTypeMacro(vtkCanopyContour, vtkCanopyViewDependentFilter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The output, typed.
  vtkPolyData* GetOutput() { return this->GetPolyDataOutput(); }
  ///@}

  ///@{
  /// Contour values, as vtkContourFilter's.
  void SetValue(int i, double value);
  double GetValue(int i);
  /// The values (owned by the filter, valid until they change).
  double* GetValues();
  void SetNumberOfContours(int number);
  int GetNumberOfContours();
  /// `number` values spread evenly over [range[0], range[1]], both included.
  void GenerateValues(int number, double range[2]);
  void GenerateValues(int number, double first, double last);
  ///@}

  ///@{
  /// The component of the field contoured (default 0).
  vtkSetMacro(ArrayComponent, int);
  vtkGetMacro(ArrayComponent, int);
  ///@}

  ///@{
  /// Other cell fields interpolated onto the contour (point data of the same
  /// name and components, as doubles). `name` is copied; unknown names are an
  /// error when the filter runs.
  void AddInterpolatedField(const char* name);
  void ClearInterpolatedFields();
  ///@}

  ///@{
  /// The deepest level contoured (default -1: every level): a node at this
  /// level is a leaf holding its own (coarse) value, and the coarser forest is
  /// contoured by the same crack-free rule (a preview, or level of detail by
  /// depth). Negative values mean every level.
  vtkSetMacro(MaximumLevel, int);
  vtkGetMacro(MaximumLevel, int);
  ///@}

  ///@{
  /// The contour value as a point array named after the field (default on).
  vtkSetMacro(ComputeScalars, bool);
  vtkGetMacro(ComputeScalars, bool);
  vtkBooleanMacro(ComputeScalars, bool);
  ///@}

  ///@{
  /// "Normals" on 3D contours (default on).
  vtkSetMacro(ComputeNormals, bool);
  vtkGetMacro(ComputeNormals, bool);
  vtkBooleanMacro(ComputeNormals, bool);
  ///@}

  ///@{
  /// Skip the parts of the dual whose nodes' values all lie on one side of
  /// every contour value (default on): one pass over the nodes computes each
  /// node's range of leaf values, then the traversal descends a group of nodes
  /// only when the union of their ranges holds a contour value. The output is
  /// the same; the work follows the contour rather than the forest.
  vtkSetMacro(Pruning, bool);
  vtkGetMacro(Pruning, bool);
  vtkBooleanMacro(Pruning, bool);
  ///@}

  /// Whether the last execution pruned with the value ranges of the execution
  /// before (the same grid topology, the same field array unmodified, the same
  /// component and maximum level: new contour values, a camera move) rather
  /// than a new pass over the nodes. On one process only.
  vtkGetMacro(LastRangesKept, bool);

  /// What the last execution did: groups of nodes the dual traversal descended
  /// into, groups it pruned, and dual cells it met (contoured or not).
  vtkGetMacro(LastVisited, vtkIdType);
  vtkGetMacro(LastPruned, vtkIdType);
  /// Groups the last execution skipped as outside the view (ViewCulling).
  vtkGetMacro(LastCulled, vtkIdType);
  vtkGetMacro(LastDualCells, vtkIdType);
  /// On several processes (Controller): the other ranks' border leaves and
  /// their ancestors the last execution received, and their bytes (the
  /// exchange that makes the ranks' contours meet without a gap).
  vtkGetMacro(LastGhostsReceived, vtkIdType);
  vtkGetMacro(LastGhostBytesReceived, vtkIdType);
  /// The exchange's wall time on this rank (finding the border leaves, the
  /// collective, indexing what came).
  vtkGetMacro(LastGhostSeconds, double);

  /// Includes the contour values' modification time.
  vtkMTimeType GetMTime() override;

protected:
  vtkCanopyContour();
  ~vtkCanopyContour() override;

  int ProcessTrees(vtkHyperTreeGrid* input, vtkDataObject* output) override;
  /// Contours are not face-on quads: no box filter on the pixels.
  bool OneLayerFacing(vtkHyperTreeGrid*, int) const override { return false; }

  vtkSmartPointer<vtkContourValues> ContourValues;
  int ArrayComponent = 0;
  int MaximumLevel = -1;
  bool ComputeScalars = true;
  bool ComputeNormals = true;
  bool Pruning = true;
  std::vector<std::string> InterpolatedFields;
  vtkIdType LastVisited = 0;
  vtkIdType LastPruned = 0;
  vtkIdType LastCulled = 0;
  vtkIdType LastDualCells = 0;
  vtkIdType LastGhostsReceived = 0;
  vtkIdType LastGhostBytesReceived = 0;
  double LastGhostSeconds = 0;
  bool LastRangesKept = false;
  /// The value ranges of the last execution and what they were made of.
  struct KeptRanges;
  std::unique_ptr<KeptRanges> Kept;

private:
  vtkCanopyContour(const vtkCanopyContour&) = delete;
  void operator=(const vtkCanopyContour&) = delete;
};
