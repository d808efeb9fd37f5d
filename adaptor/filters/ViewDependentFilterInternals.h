// What vtkCanopyViewDependentFilter keeps between executions and lends its
// subclasses (vtkCanopyAdaptiveSurface, vtkCanopyAdaptiveSlice): the view of an
// execution, the arrays a builder writes and their reuse from one execution to
// the next, the input's topology as read. Private to Canopy::Filters: the public
// header holds only a pointer to it (vtkCanopyViewDependentFilter::vtkInternals).
//
// A nested class of the filter: it reads the filter's properties and reports
// errors as the filter.
#pragma once

#include <canopy/filters/vtkCanopyViewDependentFilter.h>

#include <vtkSmartPointer.h>
#include <vtkTimeStamp.h>
#include <vtkType.h>

#include <map>
#include <memory>
#include <string>

class vtkCamera;
class vtkDataArray;
class vtkDoubleArray;
class vtkHyperTreeGrid;
class vtkIdTypeArray;
class vtkPolyData;
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

struct vtkCanopyViewDependentFilter::vtkInternals
{
  explicit vtkInternals(vtkCanopyViewDependentFilter& filter);
  ~vtkInternals();
  vtkInternals(const vtkInternals&) = delete;
  vtkInternals& operator=(const vtkInternals&) = delete;

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
    ViewResources& operator=(ViewResources&&) noexcept;
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

  /// What the input's topology costs to read (index tables, masked-descendant
  /// flags), kept while the topology is unchanged, so that a camera move does
  /// not pay it.
  std::unique_ptr<canopy::HyperTreeAccessCache> Topology;

  /// The view CurrentView() last accepted in this execution (none: no view).
  std::unique_ptr<canopy::CameraParameters> ExecutedView;

  /// What GetMTime() compares to notice a camera swap or a resized renderer.
  vtkCamera* LastCamera = nullptr; ///< only compared, to notice a camera swap
  vtkTimeStamp CameraSwapTime;
  int LastRendererSize[2] = {0, 0};
  vtkTimeStamp RendererSizeTime;

private:
  vtkCanopyViewDependentFilter& Filter;

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
};
