#include "LeafColorAverage.h"

#include <vtkDataArray.h>
#include <vtkScalarsToColors.h>

#include <algorithm>

namespace canopy
{

ColorTable::ColorTable(vtkScalarsToColors* map, vtkDataArray* values, int component)
    : Values(values), Component(component)
{
  constexpr int samples = 1024;
  const double* range = map->GetRange();
  Low = range[0];
  const double width = range[1] > range[0] ? range[1] - range[0] : 1.0;
  Scale = (samples - 1) / width;
  Table.resize(samples);
  for (int i = 0; i < samples; ++i)
  {
    const double value = Low + width * i / (samples - 1);
    double rgb[3];
    map->GetColor(value, rgb);
    Table[static_cast<std::size_t>(i)] = {{255 * rgb[0], 255 * rgb[1], 255 * rgb[2]}};
  }
  double nan[3];
  map->GetColor(std::nan(""), nan);
  NanColor = {{255 * nan[0], 255 * nan[1], 255 * nan[2]}};
}

Rgb ColorTable::mapValue(double value) const
{
  if (std::isnan(value))
  {
    return NanColor;
  }
  const double x = std::clamp((value - Low) * Scale, 0.0, static_cast<double>(Table.size() - 1));
  const auto i = std::min(static_cast<std::size_t>(x), Table.size() - 2);
  const double t = x - static_cast<double>(i);
  Rgb c;
  for (int k = 0; k < 3; ++k)
  {
    c[k] = (1 - t) * Table[i][k] + t * Table[i + 1][k];
  }
  return c;
}

Rgb ColorTable::mapCell(vtkIdType global) const
{
  if (Component >= 0)
  {
    return mapValue(Values->GetComponent(global, Component));
  }
  double sum = 0;
  for (int c = 0; c < Values->GetNumberOfComponents(); ++c)
  {
    const double x = Values->GetComponent(global, c);
    sum += x * x;
  }
  return mapValue(std::sqrt(sum));
}

} // namespace canopy
