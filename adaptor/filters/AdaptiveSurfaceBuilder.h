// The geometry of Canopy's adaptive surface, independent of VTK's pipeline.
//
// 2D: one quad per visible node where descent stops. 3D: the exposed faces
// (and exposed parts of faces) of the union of unmasked nodes where descent
// stops. Descent into a subtree happens only if its box overlaps the view with
// positive area (2D) or volume (3D), and stops at leaves or, with level of
// detail on, at nodes whose projection is at most `pixelThreshold` pixels.
//
// Level of detail with parallel projection. Let the domain be 1 wide with s
// root cells across, shown zoomed by z (the view is 1/z wide) in w pixels: a
// pixel is 1/(z w) wide and a node at level l is 1/(s f^l) wide (f the branch
// factor). Descent stops at the first level where the node is at most one
// pixel: f^l >= w z / s, i.e. l = (log(w z) - log s) / log f, the paper's
// delta_max. The code does not assume uniform roots: it projects each node's
// corners and compares the screen extent with the threshold t, which for
// parallel projection gives l = ceil(log(S / (t p)) / log f) with S the root
// cell's largest side and p the pixel size (checked by
// AdaptiveSurface2D.LevelOfDetailMatchesTheClosedForm).
#pragma once

#include "HyperTreeAccess.h"
#include "ViewVolume.h"

#include <vtkType.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace canopy
{

struct SurfaceOptions
{
  /// The view; nullptr: no culling and no level of detail (the full surface).
  const ViewVolume* view = nullptr;
  bool cullOutsideView = true;
  bool levelOfDetail = true;
  double pixelThreshold = 1.0;
  bool skipBackFaces = false; ///< 3D only
};

/// Output buffers: 12 doubles (4 points) per quad, one cell id and one level.
struct SurfaceArrays
{
  double* points;
  vtkIdType* cellIds;
  unsigned char* levels;
};

/// Two passes over the trees (in parallel with vtkSMPTools): count, then write
/// each tree's quads at its offset. The output is allocated once, in its final
/// place; its order is the tree order for any number of threads.
class GridSection;

class AdaptiveSurfaceBuilder
{
public:
  AdaptiveSurfaceBuilder(const HyperTreeAccess& grid, const SurfaceOptions& options);
  ~AdaptiveSurfaceBuilder();
  AdaptiveSurfaceBuilder(const AdaptiveSurfaceBuilder&) = delete;
  AdaptiveSurfaceBuilder& operator=(const AdaptiveSurfaceBuilder&) = delete;
  /// Number of quads; call before write().
  std::size_t count();
  /// Fills arrays sized for count() quads.
  void write(const SurfaceArrays& arrays) const;

private:
  const HyperTreeAccess& Grid;
  SurfaceOptions Options;
  std::unique_ptr<GridSection> Region; ///< 2D culling region, built once for both passes
  std::vector<std::size_t> Offsets;
};

} // namespace canopy
