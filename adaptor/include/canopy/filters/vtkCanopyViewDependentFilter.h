/**
 * @class vtkCanopyViewDependentFilter
 * @brief What Canopy's view-dependent hypertree-grid filters share: the view
 * (a renderer, a camera or explicit camera properties, and a viewport size),
 * culling and level-of-detail switches, the fields to pass, and the assembly of
 * a polydata output from the cells a builder wrote.
 *
 * Subclasses (vtkCanopyAdaptiveSurface, vtkCanopyAdaptiveSlice) implement
 * ProcessTrees: through the internals this header keeps opaque
 * (adaptor/filters/ViewDependentFilterInternals.h) they read the view, run their
 * builder into the output arrays and have the output assembled from them.
 *
 * The view comes from, in order of precedence: a renderer (camera and viewport
 * size follow it), a camera plus ViewportSize, or the explicit Camera*
 * properties. With ViewDependent off neither culling nor level of detail apply.
 * Re-executes only when the input, the camera, the viewport size or a property
 * changed (GetMTime).
 *
 * An execution reports its progress a few times (UpdateProgress) and, as VTK's
 * hypertree-grid filters do, checks once per tree whether it was aborted
 * (AbortExecute, CheckAbort): aborted, it leaves an empty output, still taking
 * part in the steps collective over the Controller so that no rank waits.
 */
#pragma once

#include "CanopyFiltersModule.h"

#include <vtkHyperTreeGridAlgorithm.h>

#include <vtkWeakPointer.h>

#include <memory>
#include <string>
#include <vector>

class vtkCamera;
class vtkPolyData;
class vtkRenderer;
class vtkScalarsToColors;
class vtkMultiProcessController;

class CANOPYFILTERS_EXPORT vtkCanopyViewDependentFilter : public vtkHyperTreeGridAlgorithm
{
public:
  vtkTypeMacro(vtkCanopyViewDependentFilter, vtkHyperTreeGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Take the view from a renderer (its active camera and its size in pixels).
  /// Held weakly: the renderer usually holds (through its actors) this filter.
  void SetRenderer(vtkRenderer* renderer);
  vtkRenderer* GetRenderer();
  ///@}

  ///@{
  /// Take the view from a camera; the viewport size comes from ViewportSize.
  void SetCamera(vtkCamera* camera);
  vtkGetObjectMacro(Camera, vtkCamera);
  ///@}

  ///@{
  /// Explicit view, used when neither a renderer nor a camera is set.
  vtkSetVector3Macro(CameraPosition, double);
  vtkGetVector3Macro(CameraPosition, double);
  vtkSetVector3Macro(CameraFocalPoint, double);
  vtkGetVector3Macro(CameraFocalPoint, double);
  vtkSetVector3Macro(CameraViewUp, double);
  vtkGetVector3Macro(CameraViewUp, double);
  vtkSetMacro(ParallelProjection, bool);
  vtkGetMacro(ParallelProjection, bool);
  vtkBooleanMacro(ParallelProjection, bool);
  vtkSetMacro(ParallelScale, double);
  vtkGetMacro(ParallelScale, double);
  vtkSetMacro(ViewAngle, double);
  vtkGetMacro(ViewAngle, double);
  ///@}

  ///@{
  /// Viewport size in pixels, used unless a renderer is set.
  vtkSetVector2Macro(ViewportSize, int);
  vtkGetVector2Macro(ViewportSize, int);
  ///@}

  ///@{
  /// Off: ignore the view (no culling, no level of detail).
  vtkSetMacro(ViewDependent, bool);
  vtkGetMacro(ViewDependent, bool);
  vtkBooleanMacro(ViewDependent, bool);
  ///@}

  ///@{
  /// Skip subtrees outside the view (default on).
  vtkSetMacro(ViewCulling, bool);
  vtkGetMacro(ViewCulling, bool);
  vtkBooleanMacro(ViewCulling, bool);
  ///@}

  ///@{
  /// Stop descending at nodes that project to at most PixelThreshold pixels
  /// (default on, threshold 1 pixel).
  vtkSetMacro(LevelOfDetail, bool);
  vtkGetMacro(LevelOfDetail, bool);
  vtkBooleanMacro(LevelOfDetail, bool);
  vtkSetMacro(PixelThreshold, double);
  vtkGetMacro(PixelThreshold, double);
  ///@}

  ///@{
  /// Cell fields to pass. None added: every input cell field.
  void AddField(const char* name);
  void ClearFields();
  ///@}

  ///@{
  /// The colours the cells are drawn with (optional): ColorField (a cell field;
  /// ColorComponent, -1: the magnitude of a vector) through ColorMap. With both
  /// set the output also has "Colors" (RGB, unsigned char per cell), what a
  /// renderer shows directly: a leaf its own mapped colour, a 1D or 2D node (or a
  /// slice's cut) drawn for level of detail the area-weighted average of its
  /// visible leaves' colours, which is what a camera sees of them (closer to the
  /// truth than the node's mapped volume average; docs/benchmarks.md). 3D faces
  /// show their node's mapped value. Re-executes when the map changes.
  void SetColorMap(vtkScalarsToColors* map);
  vtkGetObjectMacro(ColorMap, vtkScalarsToColors);
  vtkSetStdStringFromCharMacro(ColorField);
  vtkGetCharFromStdStringMacro(ColorField);
  vtkSetMacro(ColorComponent, int);
  vtkGetMacro(ColorComponent, int);
  ///@}

  ///@{
  /// With colours, in a view that sees the cells face-on (a 2D grid or an axis
  /// slice seen along its normal, view up along a grid axis): a quad that holds
  /// exactly one pixel centre, and so is drawn in that pixel alone, gets the
  /// area-weighted average colour of every quad overlapping the pixel. The
  /// rendered image is then the box-filtered image of the cells, not a sample of
  /// them (PixelBoxFilter.h). Needs the image drawn at the view's viewport size
  /// (the renderer's, or ViewportSize). Default on.
  vtkSetMacro(FilterColorsOnPixels, bool);
  vtkGetMacro(FilterColorsOnPixels, bool);
  vtkBooleanMacro(FilterColorsOnPixels, bool);
  /// Quads the last execution recoloured that way.
  vtkGetMacro(LastPixelFiltered, vtkIdType);
  ///@}

  /// Whether the last execution read the input's topology as kept from the one
  /// before (trees, mask, ghost marks and coordinates unchanged; a simulation
  /// step that changed only field values keeps it): its per-node passes were
  /// not paid again.
  bool GetLastTopologyKept() const;

  ///@{
  /// The ranks that exchange what their quads add to pixels at the edges of
  /// their parts (the box filter on pixels) and, for grids split between
  /// processes, the faces between their parts (3D surfaces) and the corners of
  /// the pieces along them (2D and 3D surfaces, slices). Default: VTK's global
  /// controller (ParaView and Catalyst set it); none, or one process: no exchange.
  void SetController(vtkMultiProcessController* controller);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  ///@}

  /// The output, typed.
  vtkPolyData* GetPolyDataOutput();

  /// Includes the camera's and the renderer's modification times, and notices a
  /// change of the renderer's size or of its active camera.
  vtkMTimeType GetMTime() override;

protected:
  vtkCanopyViewDependentFilter();
  ~vtkCanopyViewDependentFilter() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;

  /// ProcessTrees (the subclass's work), then, with colours, the box filter on
  /// the pixels (PixelBoxFilter.h): collective over Controller when the view
  /// sees the output face-on, on every rank alike, whether its part succeeded.
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  /// Whether the output's quads facing `axis` lie in a single plane, so that
  /// they do not overlap on screen (a 2D grid's surface; one slice normal to the
  /// axis). Must answer alike on every rank.
  virtual bool OneLayerFacing(vtkHyperTreeGrid* input, int axis) const = 0;

  vtkWeakPointer<vtkRenderer> Renderer;
  vtkCamera* Camera = nullptr;
  double CameraPosition[3] = {0, 0, 1};
  double CameraFocalPoint[3] = {0, 0, 0};
  double CameraViewUp[3] = {0, 1, 0};
  bool ParallelProjection = true;
  double ParallelScale = 1.0;
  double ViewAngle = 30.0;
  int ViewportSize[2] = {512, 512};
  bool ViewDependent = true;
  bool ViewCulling = true;
  bool LevelOfDetail = true;
  double PixelThreshold = 1.0;
  std::vector<std::string> Fields;
  vtkScalarsToColors* ColorMap = nullptr;
  std::string ColorField;
  int ColorComponent = -1;
  bool FilterColorsOnPixels = true;
  vtkMultiProcessController* Controller = nullptr;
  vtkIdType LastPixelFiltered = 0;

  /// What the filter keeps between executions and lends its subclasses: the
  /// view of an execution, the output arrays and their reuse, the input's
  /// topology as read (adaptor/filters/ViewDependentFilterInternals.h).
  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;

private:
  vtkCanopyViewDependentFilter(const vtkCanopyViewDependentFilter&) = delete;
  void operator=(const vtkCanopyViewDependentFilter&) = delete;
};
