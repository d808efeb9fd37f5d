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
// up along a grid axis (parallel or perspective projection); other quads are
// left as they are. A quad holding several pixel centres keeps its colour (it
// is one colour in all of them). Each rank filters its own quads: a pixel
// shared with another rank's quads averages this rank's part of it.
// Tested by ImageAccuracy.* (tests/render/ImageAccuracyTest.cxx) against the
// exact image.
#pragma once

#include <vtkType.h>

namespace canopy
{

class ViewVolume;

struct PixelBoxFilterCounts
{
  vtkIdType faceOn = 0;     ///< quads seen face-on (filtered or not)
  vtkIdType recoloured = 0; ///< quads that hold exactly one pixel centre
};

/// `points`: the quads' corners, 4 consecutive points (x, y, z) per quad, in
/// order around the quad (corners 0 and 2 opposite); borrowed for the call.
/// `colors`: RGB per quad, rewritten in place for the quads that hold exactly
/// one pixel centre of `view`'s viewport.
PixelBoxFilterCounts boxFilterOnPixels(const ViewVolume& view, const double* points,
                                       vtkIdType quads, unsigned char* colors);

} // namespace canopy
