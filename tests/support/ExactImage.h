// The truth a rendered image is measured against: what an ideal camera sees of
// flat coloured rectangles (a 2D grid's cells, a slice's cuts) seen face-on
// with a parallel projection: every pixel the area-weighted average of the
// colours of the cells it covers (colour-mapped first, then averaged), the
// background over what no cell covers. Computed exactly (overlap areas), not by
// supersampling.
#pragma once

#include "OffscreenRenderer.h"

#include <array>
#include <string>
#include <vector>

class vtkCamera;
class vtkPolyData;
class vtkScalarsToColors;

namespace canopy::testing
{

/// A rectangle of the view plane ([lo, hi] along the screen's x and y, in world
/// units) and its colour (0..255 per channel).
struct ColoredRect
{
  double lo[2];
  double hi[2];
  std::array<double, 3> rgb;
};

/// The window: world x and y of the image's lower-left corner, and one pixel's
/// side in world units (a parallel view: 2 parallel scale / height).
struct PixelWindow
{
  double left;
  double bottom;
  double pixel;
  int width;
  int height;
};

/// The window a parallel camera sees, `right` and `up` the world axes along the
/// screen's x and y (the camera looks along the third, face-on).
PixelWindow parallelWindow(vtkCamera* camera, int width, int height, int right = 0, int up = 1);

/// The cells of a flat axis-aligned surface (a 2D grid's surface, an axis
/// slice) as rectangles on the `right` and `up` axes, coloured by `map` applied
/// to `field` (component 0) in full precision: what the cells' mapped colours are.
std::vector<ColoredRect> coloredRects(vtkPolyData* surface, const std::string& field,
                                      vtkScalarsToColors* map, int right = 0, int up = 1);

/// Rows from the bottom, as OffscreenRenderer's images. Rectangles may overlap
/// the window's edge or lie outside it.
Image exactImage(const std::vector<ColoredRect>& cells, const PixelWindow& window,
                 const std::array<double, 3>& background);

} // namespace canopy::testing
