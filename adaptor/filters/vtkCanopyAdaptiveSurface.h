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
 * The view comes from, in order of precedence: a renderer (camera and viewport
 * size follow it), a camera plus ViewportSize, or the explicit Camera*
 * properties. With ViewDependent off the output is the full surface.
 *
 * Output: vtkPolyData of quads (lines in 1D) with double-precision points, the selected input
 * cell fields (all by default), "OriginalCellId" (the input's global cell index)
 * and "Level". Re-executes only when the input, the camera, the viewport size
 * or a property changed.
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
class vtkIdTypeArray;
class vtkPolyData;
class vtkRenderer;
namespace canopy
{
class HyperTreeAccessCache;
}

class CANOPYFILTERS_EXPORT vtkCanopyAdaptiveSurface : public vtkHyperTreeGridAlgorithm
{
public:
  static vtkCanopyAdaptiveSurface* New();
  vtkTypeMacro(vtkCanopyAdaptiveSurface, vtkHyperTreeGridAlgorithm);
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
  /// Off: ignore the view and emit the full surface.
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
  /// 3D: skip faces turned away from the camera (default off).
  vtkSetMacro(SkipBackFaces, bool);
  vtkGetMacro(SkipBackFaces, bool);
  vtkBooleanMacro(SkipBackFaces, bool);
  ///@}

  ///@{
  /// Cell fields to pass. None added: every input cell field.
  void AddField(const char* name);
  void ClearFields();
  ///@}

  /// The output, typed.
  vtkPolyData* GetPolyDataOutput();

  /// Includes the camera's and the renderer's modification times, and notices a
  /// change of the renderer's size or of its active camera.
  vtkMTimeType GetMTime() override;

protected:
  vtkCanopyAdaptiveSurface();
  ~vtkCanopyAdaptiveSurface() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int ProcessTrees(vtkHyperTreeGrid* input, vtkDataObject* output) override;

private:
  vtkCanopyAdaptiveSurface(const vtkCanopyAdaptiveSurface&) = delete;
  void operator=(const vtkCanopyAdaptiveSurface&) = delete;

  vtkWeakPointer<vtkRenderer> Renderer;
  vtkCamera* LastCamera = nullptr; ///< only compared, to notice a camera swap
  vtkTimeStamp CameraSwapTime;
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
  bool SkipBackFaces = false;
  std::vector<std::string> Fields;
  /// Output arrays of the previous execution, reused when nobody else holds them.
  std::map<std::string, vtkSmartPointer<vtkDataArray>> Reusable;
  template <typename ArrayType>
  vtkSmartPointer<ArrayType> ReusableArray(const std::string& key, int dataType);
  /// Offsets and connectivity are arithmetic sequences (cell q's points are
  /// perCell q, perCell q + 1, ...), the same at every execution: their reusable
  /// arrays (ReusableArray) are kept with how many values are already right, so an
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
  /// What the input's topology costs to read (index tables, masked-descendant
  /// flags), kept while the topology is unchanged: a camera move does not pay it.
  std::unique_ptr<canopy::HyperTreeAccessCache> Topology;
  int LastRendererSize[2] = {0, 0};
  vtkTimeStamp RendererSizeTime;
};
