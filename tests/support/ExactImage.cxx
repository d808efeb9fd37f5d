#include "ExactImage.h"

#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPolyData.h>
#include <vtkScalarsToColors.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace canopy::testing
{

PixelWindow parallelWindow(vtkCamera* camera, int width, int height, int right, int up)
{
  if (!camera->GetParallelProjection())
  {
    throw std::invalid_argument("parallelWindow: the camera is not a parallel projection");
  }
  const double pixel = 2 * camera->GetParallelScale() / height;
  const double* focal = camera->GetFocalPoint();
  return {focal[right] - 0.5 * width * pixel, focal[up] - 0.5 * height * pixel, pixel, width,
          height};
}

std::vector<ColoredRect> coloredRects(vtkPolyData* surface, const std::string& field,
                                      vtkScalarsToColors* map, int right, int up)
{
  vtkDataArray* values = surface->GetCellData()->GetArray(field.c_str());
  if (!values)
  {
    throw std::invalid_argument("coloredRects: no cell field '" + field + "'");
  }
  std::vector<ColoredRect> rects;
  rects.reserve(surface->GetNumberOfCells());
  double bounds[6];
  double rgb[3];
  for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
  {
    surface->GetCellBounds(c, bounds);
    map->GetColor(values->GetComponent(c, 0), rgb);
    rects.push_back({{bounds[2 * right], bounds[2 * up]},
                     {bounds[2 * right + 1], bounds[2 * up + 1]},
                     {{255 * rgb[0], 255 * rgb[1], 255 * rgb[2]}}});
  }
  return rects;
}

Image exactImage(const std::vector<ColoredRect>& cells, const PixelWindow& window,
                 const std::array<double, 3>& background)
{
  const auto pixels = static_cast<std::size_t>(window.width) * window.height;
  std::vector<double> sum(3 * pixels, 0.0);
  std::vector<double> covered(pixels, 0.0);
  for (const ColoredRect& cell : cells)
  {
    // In pixel units: pixel (i, j) is [i, i + 1) x [j, j + 1).
    const double x0 = (cell.lo[0] - window.left) / window.pixel;
    const double x1 = (cell.hi[0] - window.left) / window.pixel;
    const double y0 = (cell.lo[1] - window.bottom) / window.pixel;
    const double y1 = (cell.hi[1] - window.bottom) / window.pixel;
    const int i0 = std::max(0, static_cast<int>(std::floor(x0)));
    const int i1 = std::min(window.width - 1, static_cast<int>(std::ceil(x1)) - 1);
    const int j0 = std::max(0, static_cast<int>(std::floor(y0)));
    const int j1 = std::min(window.height - 1, static_cast<int>(std::ceil(y1)) - 1);
    for (int j = j0; j <= j1; ++j)
    {
      const double h = std::min(y1, j + 1.0) - std::max(y0, static_cast<double>(j));
      if (h <= 0)
      {
        continue;
      }
      for (int i = i0; i <= i1; ++i)
      {
        const double w = std::min(x1, i + 1.0) - std::max(x0, static_cast<double>(i));
        if (w <= 0)
        {
          continue;
        }
        const auto p = static_cast<std::size_t>(j) * window.width + i;
        const double a = w * h;
        covered[p] += a;
        for (int c = 0; c < 3; ++c)
        {
          sum[3 * p + c] += a * cell.rgb[c];
        }
      }
    }
  }
  Image image;
  image.width = window.width;
  image.height = window.height;
  image.rgb.resize(3 * pixels);
  for (std::size_t p = 0; p < pixels; ++p)
  {
    const double rest = std::max(0.0, 1.0 - covered[p]);
    for (int c = 0; c < 3; ++c)
    {
      const double v = sum[3 * p + c] + rest * background[c];
      image.rgb[3 * p + c] = static_cast<unsigned char>(std::lround(std::clamp(v, 0.0, 255.0)));
    }
  }
  return image;
}

} // namespace canopy::testing
