/**
 * @class vtkCanopyAdaptiveSurface
 * @brief View-dependent surface of a vtkHyperTreeGrid: exact view culling and
 * sub-pixel level of detail, 1D, 2D and 3D.
 *
 * 1D grids (a line of roots along any axis): one segment (a VTK_LINE cell) per
 * node where descent stops; the view culls by its section with the line.
 * 2D grids (in any axis-aligned plane): one quad per node where descent stops.
 * 3D grids: the exposed part of the boundary of the union of unmasked nodes
 * where descent stops, with no interior face, gap or duplicate. A subtree is
 * descended only if its box overlaps the view volume (exact separating-axis
 * test); descent stops at leaves or, with LevelOfDetail on, at nodes whose
 * projection spans at most PixelThreshold pixels, which then show their own
 * cell values.
 *
 * The view and the shared properties: vtkCanopyViewDependentFilter. With
 * ViewDependent off the output is the full surface.
 *
 * Grids split between processes (absent cells, or trees on other ranks): in
 * 3D with a mask on any rank, a face between this rank's part and another's is
 * drawn where the other rank masks its side, which only that rank knows: the
 * ranks exchange those faces through the Controller (RemoteFaceExchange.h).
 * Without any mask other ranks' parts are solid and no face is exchanged. In 2D
 * and 3D the ranks also put the corners of their pieces on the edges of the
 * pieces meeting them across their parts (EdgeVertexExchange.h). With more than
 * one process in the Controller the execution is collective, as VTK's parallel
 * filters are.
 *
 * Output: vtkPolyData of flat pieces (lines in 1D): each an axis-aligned
 * rectangle, a quad or a polygon that also carries, in order along its edges,
 * the corners of the smaller pieces meeting them, so that neighbours share their
 * edges and no rasterizer leaves a pixel between them (T-junctions,
 * EdgeVertices.h). Double-precision points, the selected input
 * cell fields (all by default), "OriginalCellId" (the input's global cell index)
 * and "Level"; in 3D also exact cell "Normals" (outward), for shading that does
 * not depend on how the grid is split between processes. Re-executes only when the input, the
 * camera, the viewport size or a property changed.
 */
#pragma once

#include "CanopyFiltersModule.h"
#include <canopy/filters/vtkCanopyViewDependentFilter.h>

#include <memory>

class CANOPYFILTERS_EXPORT vtkCanopyAdaptiveSurface : public vtkCanopyViewDependentFilter
{
public:
  static vtkCanopyAdaptiveSurface* New();
  vtkTypeMacro(vtkCanopyAdaptiveSurface, vtkCanopyViewDependentFilter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// 3D: skip faces turned away from the camera (default off).
  vtkSetMacro(SkipBackFaces, bool);
  vtkGetMacro(SkipBackFaces, bool);
  vtkBooleanMacro(SkipBackFaces, bool);
  ///@}

protected:
  vtkCanopyAdaptiveSurface();
  ~vtkCanopyAdaptiveSurface() override;

  int ProcessTrees(vtkHyperTreeGrid* input, vtkDataObject* output) override;
  /// A 2D grid's surface is one layer; a 3D surface's faces overlap on screen.
  bool OneLayerFacing(vtkHyperTreeGrid* input, int axis) const override;

  bool SkipBackFaces = false;

private:
  vtkCanopyAdaptiveSurface(const vtkCanopyAdaptiveSurface&) = delete;
  void operator=(const vtkCanopyAdaptiveSurface&) = delete;

  /// What the surface keeps between executions (its builder's buffers).
  struct vtkSurfaceInternals;
  std::unique_ptr<vtkSurfaceInternals> SurfaceInternals;
};
