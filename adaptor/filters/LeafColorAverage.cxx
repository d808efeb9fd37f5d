#include "LeafColorAverage.h"

#include <vtkColorTransferFunction.h>
#include <vtkDataArray.h>
#include <vtkDiscretizableColorTransferFunction.h>
#include <vtkScalarsToColors.h>

#include <algorithm>
#include <cmath>

namespace canopy
{

ColorTable::ColorTable(vtkScalarsToColors* map) : Map(map)
{
  constexpr int samples = 1024;
  // A discretized or indexed map builds its table here (ParaView rescales a map
  // without rebuilding it).
  map->Build();
  SampledAt = map->GetMTime();
  const double* range = map->GetRange();
  // A logarithmic map is sampled evenly in log10 of the value.
  Log = map->UsingLogScale() && range[0] > 0 && range[1] > range[0];
  Low = Log ? std::log10(range[0]) : range[0];
  const double high = Log ? std::log10(range[1]) : range[1];
  const double width = high > Low ? high - Low : 1.0;
  Scale = (samples - 1) / width;
  Last = samples - 1;
  Table.resize(samples);
  auto* function = vtkColorTransferFunction::SafeDownCast(map);
  if (function && !vtkDiscretizableColorTransferFunction::SafeDownCast(map) && !Log)
  {
    // One pass over the function's nodes, not one search and conversion per
    // value. (A discretized function, ParaView's, maps through its own table:
    // GetColor is cheap there and GetTable would not discretize.)
    std::vector<double> rgb(3 * samples);
    function->GetTable(Low, Low + width, samples, rgb.data());
    for (int i = 0; i < samples; ++i)
    {
      for (int k = 0; k < 3; ++k)
      {
        Table[static_cast<std::size_t>(i)][k] = 255 * rgb[3 * static_cast<std::size_t>(i) + k];
      }
    }
  }
  else
  {
    for (int i = 0; i < samples; ++i)
    {
      const double at = Low + width * i / (samples - 1);
      double rgb[3];
      map->GetColor(Log ? std::pow(10.0, at) : at, rgb);
      Table[static_cast<std::size_t>(i)] = {{255 * rgb[0], 255 * rgb[1], 255 * rgb[2]}};
    }
  }
  double nan[3];
  map->GetColor(std::nan(""), nan);
  NanColor = {{255 * nan[0], 255 * nan[1], 255 * nan[2]}};
}

bool ColorTable::sampledFrom(vtkScalarsToColors* map) const
{
  return map == Map && map->GetMTime() == SampledAt;
}

void ColorTable::setField(vtkDataArray* values, int component)
{
  Values = values;
  Component = component;
}

double ColorTable::magnitude(vtkIdType global) const
{
  double sum = 0;
  for (int c = 0; c < Values->GetNumberOfComponents(); ++c)
  {
    const double x = Values->GetComponent(global, c);
    sum += x * x;
  }
  return std::sqrt(sum);
}

} // namespace canopy
