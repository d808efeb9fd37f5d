// Colours box-filtered on the pixel grid, for quads seen face-on.
//
// A rasterizer paints a pixel with the colour of the one quad its centre falls
// in: it samples. A quad that holds exactly one pixel centre is therefore
// drawn in that pixel and nowhere else, so giving it the area-weighted average
// of the colours of every quad that overlaps the pixel turns the rasterized
// image into the box-filtered image of the quads: what an ideal camera, each
// pixel integrating light, sees (tests/support/ExactImage.h computes it
// exactly). Level of detail alone (LeafColorAverage.h) averages each drawn
// node over its own leaves; its quads, up to a pixel wide and not aligned with
// the pixels, are still sampled at one point per pixel, which is why drawing
// every leaf could be closer to the truth (docs/benchmarks.md, "Run time
// against image error").
//
// Only quads that project to screen-aligned rectangles are filtered: a 2D
// grid's cells, or an axis slice's cuts, seen along their normal with the view
// up along a grid axis (parallel or perspective projection), all in one plane
// (the caller says so: slices one behind the other overlap on screen). Other
// quads keep their colours, and so does a quad holding several pixel centres
// (it is one colour in all of them).
//
// Ranks: a pixel at the edge of a rank's part is overlapped by other ranks'
// quads too. Each rank lists what its quads add to pixels whose centre none of
// them holds (shares()); every rank adds the shares for the pixels it owns
// (addShares()) before finish(): the colours are then the same on any number of
// ranks. Tested by PixelBoxFilter.* against a brute-force average, ImageAccuracy.*
// against the exact image, and across ranks by SplitColours.* (mpi.split_trees.np*).
#pragma once

#include <vtkType.h>

#include <array>
#include <cstdint>
#include <vector>

namespace canopy
{

class ViewVolume;

struct PixelBoxFilterCounts
{
  vtkIdType faceOn = 0;     ///< quads seen face-on (filtered or not)
  vtkIdType recoloured = 0; ///< quads that hold exactly one pixel centre
};

class PixelBoxFilter
{
public:
  /// The axis `view` looks along when it sees axis-aligned quads as
  /// screen-aligned rectangles (view up along another axis), else -1.
  static int faceOnAxis(const ViewVolume& view);

  /// Precondition: faceOnAxis(view) >= 0. `points`: the quads' points (x, y,
  /// z), quad q's from offsets[q] to offsets[q + 1] - 1: an axis-aligned
  /// rectangle, its corners and any vertices on its edges; `colors`: RGB per
  /// quad. All are read here only (not kept).
  PixelBoxFilter(const ViewVolume& view, const double* points, const vtkIdType* offsets,
                 vtkIdType quads, const unsigned char* colors);

  /// What this rank's quads add to pixels whose centre none of them holds, 5
  /// values each: pixel index, red, green, blue (times area), area.
  const std::vector<double>& shares() const { return Shares; }
  /// Adds shares (5 values each, from every rank; this rank's own are ignored:
  /// they are for pixels it does not own).
  void addShares(const std::vector<double>& shares);
  /// Rewrites the colours of the quads that hold exactly one pixel centre.
  PixelBoxFilterCounts finish(unsigned char* colors) const;

private:
  long Width = 0;
  long Height = 0;
  /// Per pixel: the slot of the quad holding only its centre (>= 0), Several
  /// when a quad holding several centres holds it, None when no quad does.
  std::vector<std::int32_t> Owner;
  static constexpr std::int32_t None = -1;
  static constexpr std::int32_t Several = -2;
  std::vector<vtkIdType> Owners;           ///< per slot: the quad
  std::vector<std::array<double, 4>> Sums; ///< per slot: red, green, blue (x area), area
  std::vector<double> Shares;
  vtkIdType FaceOn = 0;
};

} // namespace canopy
