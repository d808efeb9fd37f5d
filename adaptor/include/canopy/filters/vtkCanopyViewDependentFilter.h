/**
 * @class vtkCanopyViewDependentFilter
 * @brief What Canopy's view-dependent hypertree-grid filters share: the view
 * (a renderer, a camera or explicit camera properties, and a viewport size),
 * culling and level-of-detail switches, the fields to pass, and the assembly of
 * a polydata output from the cells a builder wrote.
 *
 * Subclasses (vtkCanopyAdaptiveSurface, vtkCanopyAdaptiveSlice) implement
 * ProcessTrees: they read the view with CurrentView(), run their builder into
 * the arrays of NewCellArrays() and hand them to AssembleOutput().
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

#include <vtkSmartPointer.h>
#include <vtkWeakPointer.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

class vtkCamera;
class vtkDataArray;
class vtkDoubleArray;
class vtkIdTypeArray;
class vtkPolyData;
class vtkRenderer;
class vtkScalarsToColors;
class vtkMultiProcessController;
class vtkUnsignedCharArray;
namespace canopy
{
struct CameraParameters;
class ColorTable;
struct SurfaceArrays;
class HyperTreeAccessCache;
class ViewVolume;
struct ViewOptions;
} // namespace canopy

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

  /// The view of this execution (only meaningful with ViewDependent on). False,
  /// with the error reported, when the view or PixelThreshold is unusable.
  bool CurrentView(canopy::CameraParameters& camera);

  /// What the builders' view options point to: the view (none with
  /// ViewDependent off) and the sampled colour map (none without colours).
  struct ViewResources
  {
    std::unique_ptr<canopy::ViewVolume> View;
    std::shared_ptr<canopy::ColorTable> Colors;
    ViewResources();
    ~ViewResources();
    ViewResources(ViewResources&&) noexcept;
  };
  /// Fills the builders' view options from the properties; the resources they
  /// point to must outlive them. Throws std::invalid_argument when ColorField
  /// names no cell field of the input or a component it does not have.
  ViewResources ViewOptionsFor(const canopy::CameraParameters& camera, vtkHyperTreeGrid* input,
                               canopy::ViewOptions& options) const;

  /// The arrays a builder writes: coordinates (3 components), where each cell's
  /// points start, original cell ids and levels, reused from the previous
  /// execution when nothing else holds them. Call after releasing the previous
  /// output (output->Initialize()).
  struct CellArrays
  {
    vtkSmartPointer<vtkDoubleArray> Points;
    vtkSmartPointer<vtkIdTypeArray> Offsets;
    vtkSmartPointer<vtkIdTypeArray> Ids;
    vtkSmartPointer<vtkUnsignedCharArray> Levels;
    vtkSmartPointer<vtkUnsignedCharArray> Colors; ///< null without colours
  };
  CellArrays NewCellArrays();

  /// Sizes `arrays` for `cells` cells of `points` points in all and returns
  /// where a builder writes them.
  canopy::SurfaceArrays SizeCellArrays(const CellArrays& arrays, vtkIdType cells, vtkIdType points);

  /// Makes `output` from `cells` cells written into `arrays` (`segments`: lines
  /// of two points, otherwise polygons), with the input's selected cell fields
  /// gathered at the cells' original ids.
  void AssembleOutput(vtkHyperTreeGrid* input, vtkPolyData* output, const CellArrays& arrays,
                      vtkIdType cells, bool segments);

  /// Gives `output`'s axis-aligned polygons exact cell normals (+-x, +-y, +-z:
  /// the right-handed normal of each polygon's first edge and last edge), so
  /// that their shading does not depend on how the renderer rounds the points
  /// (VTK otherwise derives flat normals from screen-space derivatives of float
  /// positions shifted by each process's own bounds: images of a grid split
  /// between ranks would differ by a few levels).
  void AddAxisNormals(vtkPolyData* output);

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
  /// Internal, shared with the subclasses: what the input's topology costs to
  /// read (index tables, masked-descendant flags), kept while the topology is
  /// unchanged, so that a camera move does not pay it.
  std::unique_ptr<canopy::HyperTreeAccessCache> Topology;

private:
  vtkCanopyViewDependentFilter(const vtkCanopyViewDependentFilter&) = delete;
  void operator=(const vtkCanopyViewDependentFilter&) = delete;

  /// The view CurrentView() last accepted in this execution (none: no view).
  std::unique_ptr<canopy::CameraParameters> ExecutedView;
  /// The colour map as last sampled, reused while it is unchanged.
  mutable std::shared_ptr<canopy::ColorTable> SampledColorMap;

  /// Output arrays of the previous execution, reused when nobody else holds them.
  std::map<std::string, vtkSmartPointer<vtkDataArray>> Reusable;
  template <typename ArrayType>
  vtkSmartPointer<ArrayType> ReusableArray(const std::string& key, int dataType);
  /// The connectivity is an arithmetic sequence (the points are written in
  /// their cells' order: 0, 1, 2, ...), the same at every execution: its reusable
  /// array (ReusableArray) is kept with how many values are already right, so an
  /// execution writes only the values a longer output adds. Trusted only while
  /// the array's modification time is the one it was left with.
  struct KeptSequence
  {
    vtkIdType Step = 0;
    vtkIdType Valid = 0;
    vtkMTimeType Time = 0;
  };
  std::map<std::string, KeptSequence> Sequences;
  vtkSmartPointer<vtkIdTypeArray> ArithmeticIds(const std::string& key, vtkIdType count,
                                                vtkIdType step);
  vtkCamera* LastCamera = nullptr; ///< only compared, to notice a camera swap
  vtkTimeStamp CameraSwapTime;
  int LastRendererSize[2] = {0, 0};
  vtkTimeStamp RendererSizeTime;
};
