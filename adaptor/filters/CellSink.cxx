#include "CellSink.h"

namespace canopy
{

void CellSink::emit(const Vec3* points, std::size_t count, vtkIdType cellId, int level,
                    const Rgb* color)
{
  if (keep)
  {
    for (std::size_t k = 0; k < count; ++k)
    {
      keep->points.insert(keep->points.end(), points[k].begin(), points[k].end());
    }
    keep->sizes.push_back(static_cast<std::uint32_t>(count));
    keep->cellIds.push_back(cellId);
    keep->levels.push_back(static_cast<unsigned char>(level));
    if (color)
    {
      keep->colors.insert(keep->colors.end(),
                          {colorByte((*color)[0]), colorByte((*color)[1]), colorByte((*color)[2])});
    }
  }
  else if (!counting && next < limit && nextPoint + count <= pointLimit)
  {
    double* p = arrays.points + 3 * nextPoint;
    for (std::size_t k = 0; k < count; ++k)
    {
      *p++ = points[k][0];
      *p++ = points[k][1];
      *p++ = points[k][2];
    }
    arrays.offsets[next] = static_cast<vtkIdType>(pointBase + nextPoint);
    arrays.cellIds[next] = cellId;
    arrays.levels[next] = static_cast<unsigned char>(level);
    if (color && arrays.colors)
    {
      unsigned char* rgb = arrays.colors + 3 * next;
      for (int k = 0; k < 3; ++k)
      {
        rgb[k] = colorByte((*color)[k]);
      }
    }
  }
  ++next;
  nextPoint += count;
}

} // namespace canopy
