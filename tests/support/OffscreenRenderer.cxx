#include "OffscreenRenderer.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkColorTransferFunction.h>
#include <vtkImageData.h>
#include <vtkLookupTable.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace canopy::testing
{

OffscreenRenderer::OffscreenRenderer(int width, int height)
{
  Window->SetOffScreenRendering(1);
  Window->SetMultiSamples(0);
  Window->AddRenderer(Renderer);
  Window->SetSize(width, height);
  Renderer->SetBackground(0, 0, 0);
  Actor->SetMapper(Mapper);
  Renderer->AddActor(Actor);
}

OffscreenRenderer::~OffscreenRenderer() = default;

vtkCamera* OffscreenRenderer::camera()
{
  return Renderer->GetActiveCamera();
}

vtkRenderer* OffscreenRenderer::renderer()
{
  return Renderer;
}

void OffscreenRenderer::resize(int width, int height)
{
  Window->SetSize(width, height);
}

vtkScalarsToColors* OffscreenRenderer::colorMap(double low, double high)
{
  if (Map->GetSize() != 2 || Map->GetRange()[0] != low || Map->GetRange()[1] != high)
  {
    Map->RemoveAllPoints();
    Map->SetColorSpaceToDiverging();
    Map->AddRGBPoint(low, 0.230, 0.299, 0.754);
    Map->AddRGBPoint(high, 0.706, 0.016, 0.150);
  }
  return Map;
}

Image OffscreenRenderer::render(vtkPolyData* surface, const std::string& field, double low,
                                double high, bool lighting, bool edges, double* seconds)
{
  Mapper->SetInputData(surface);
  Mapper->SetScalarModeToUseCellFieldData();
  Mapper->SelectColorArray(field.c_str());
  Mapper->SetLookupTable(colorMap(low, high));
  Mapper->UseLookupTableScalarRangeOn();
  Mapper->ScalarVisibilityOn();
  Mapper->SetColorModeToMapScalars();
  Actor->GetProperty()->SetLighting(lighting);
  Actor->GetProperty()->SetEdgeVisibility(edges);
  Actor->GetProperty()->SetEdgeColor(0.1, 0.1, 0.1);
  return capture(seconds);
}

Image OffscreenRenderer::renderColors(vtkPolyData* surface, const std::string& field,
                                      double* seconds)
{
  Mapper->SetInputData(surface);
  Mapper->SetScalarModeToUseCellFieldData();
  Mapper->SelectColorArray(field.c_str());
  Mapper->ScalarVisibilityOn();
  Mapper->SetColorModeToDirectScalars();
  Actor->GetProperty()->SetLighting(false);
  Actor->GetProperty()->SetEdgeVisibility(false);
  return capture(seconds);
}

Image OffscreenRenderer::capture(double* seconds)
{
  // The camera drives the clipping range; keep all geometry.
  Renderer->ResetCameraClippingRange();
  const auto start = std::chrono::steady_clock::now();
  Window->Render();
  if (seconds)
  {
    *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(Window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkImageData* data = grab->GetOutput();
  Image image;
  int dims[3];
  data->GetDimensions(dims);
  image.width = dims[0];
  image.height = dims[1];
  auto* pixels = vtkUnsignedCharArray::SafeDownCast(data->GetPointData()->GetScalars());
  image.rgb.assign(pixels->GetPointer(0), pixels->GetPointer(0) + 3 * dims[0] * dims[1]);
  return image;
}

Image downsample(const Image& image, int factor)
{
  Image out;
  out.width = image.width / factor;
  out.height = image.height / factor;
  out.rgb.resize(static_cast<std::size_t>(3 * out.width * out.height));
  for (int y = 0; y < out.height; ++y)
  {
    for (int x = 0; x < out.width; ++x)
    {
      for (int c = 0; c < 3; ++c)
      {
        int sum = 0;
        for (int dy = 0; dy < factor; ++dy)
        {
          for (int dx = 0; dx < factor; ++dx)
          {
            sum += image.rgb[static_cast<std::size_t>(
                3 * ((y * factor + dy) * image.width + x * factor + dx) + c)];
          }
        }
        out.rgb[static_cast<std::size_t>(3 * (y * out.width + x) + c)] =
            static_cast<unsigned char>((sum + factor * factor / 2) / (factor * factor));
      }
    }
  }
  return out;
}

ImageError compare(const Image& a, const Image& b, int tolerance)
{
  ImageError e;
  if (a.width != b.width || a.height != b.height)
  {
    e.rmse = std::numeric_limits<double>::infinity();
    e.shareOff = 1;
    return e;
  }
  double squared = 0;
  const std::size_t pixels = static_cast<std::size_t>(a.width) * a.height;
  for (std::size_t p = 0; p < pixels; ++p)
  {
    bool off = false;
    for (int c = 0; c < 3; ++c)
    {
      const int d = int(a.rgb[3 * p + c]) - int(b.rgb[3 * p + c]);
      squared += double(d) * d;
      off = off || std::abs(d) > tolerance;
    }
    e.pixelsOff += off;
  }
  e.rmse = std::sqrt(squared / (3.0 * pixels));
  e.psnr = e.rmse > 0 ? 20 * std::log10(255.0 / e.rmse) : std::numeric_limits<double>::infinity();
  e.shareOff = double(e.pixelsOff) / pixels;
  return e;
}

void writePng(const Image& image, const std::string& path)
{
  vtkNew<vtkImageData> data;
  data->SetDimensions(image.width, image.height, 1);
  data->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* out = static_cast<unsigned char*>(data->GetScalarPointer());
  std::copy(image.rgb.begin(), image.rgb.end(), out);
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputData(data);
  writer->SetFileName(path.c_str());
  writer->Write();
}

Image difference(const Image& a, const Image& b, int gain)
{
  Image d = a;
  for (std::size_t i = 0; i < d.rgb.size() && i < b.rgb.size(); ++i)
  {
    d.rgb[i] =
        static_cast<unsigned char>(std::min(255, gain * std::abs(int(a.rgb[i]) - int(b.rgb[i]))));
  }
  return d;
}

} // namespace canopy::testing
