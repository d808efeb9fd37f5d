// Renders a surface off screen (under Xvfb here) into an RGB image, and the
// image-error metrics the tests and benchmarks report.
#pragma once

#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include <array>
#include <string>
#include <vector>

class vtkCamera;
class vtkPolyData;
class vtkRenderWindow;
class vtkRenderer;
class vtkPolyDataMapper;
class vtkActor;
class vtkColorTransferFunction;
class vtkScalarsToColors;

namespace canopy::testing
{

struct Image
{
  int width = 0;
  int height = 0;
  std::vector<unsigned char> rgb; ///< row-major from the bottom row, 3 bytes per pixel
};

class OffscreenRenderer
{
public:
  OffscreenRenderer(int width, int height);
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  vtkCamera* camera();
  vtkRenderer* renderer();
  void resize(int width, int height);

  /// Colors cells by `field` (component 0) over [low, high] with colorMap(low,
  /// high), flat, unlit unless `lighting`; returns the image and the render time.
  Image render(vtkPolyData* surface, const std::string& field, double low, double high,
               bool lighting = false, bool edges = false, double* seconds = nullptr);
  /// Colors cells with an RGB cell array as it is (e.g. "Colors" from Canopy's
  /// filters with a colour map), flat and unlit.
  Image renderColors(vtkPolyData* surface, const std::string& field, double* seconds = nullptr);
  /// The colour map render() uses over [low, high]: cool to warm, smooth (a
  /// vtkColorTransferFunction), so that sampling it and mapping through it agree.
  vtkScalarsToColors* colorMap(double low, double high);

private:
  vtkNew<vtkRenderWindow> Window;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkPolyDataMapper> Mapper;
  vtkNew<vtkActor> Actor;
  vtkNew<vtkColorTransferFunction> Map;
  Image capture(double* seconds);
};

/// Averages factor x factor blocks (a supersampled reference down to size).
Image downsample(const Image& image, int factor);

struct ImageError
{
  double rmse = 0;     ///< over all channels, in 0..255 units
  double psnr = 0;     ///< dB; infinity when identical
  double shareOff = 0; ///< share of pixels differing in any channel by more than `tolerance`
  std::size_t pixelsOff = 0;
};

ImageError compare(const Image& a, const Image& b, int tolerance = 0);

/// Writes an RGB image as PNG.
void writePng(const Image& image, const std::string& path);

/// |a - b| amplified, for difference figures.
Image difference(const Image& a, const Image& b, int gain = 4);

} // namespace canopy::testing
