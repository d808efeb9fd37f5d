#include <canopy/ForestDescription.h>

namespace canopy
{

std::size_t sizeOf(ValueType type)
{
  switch (type)
  {
  case ValueType::Float32:
  case ValueType::Int32:
    return 4;
  case ValueType::Float64:
  case ValueType::Int64:
    return 8;
  }
  return 0;
}

} // namespace canopy

namespace canopy
{

BlockStrides BlockStrides::packed(int dimension, int cellsPerSide, int ghostCells, int components,
                                  std::size_t valueSize, bool variableOutermost)
{
  // Axes beyond the dimension are flat: one cell, no ghosts, stride unused.
  const auto extent = static_cast<std::size_t>(cellsPerSide + 2 * ghostCells);
  const std::size_t cellBytes =
      variableOutermost ? valueSize : valueSize * static_cast<std::size_t>(components);
  BlockStrides strides;
  std::size_t stride = cellBytes;
  for (int axis = 0; axis < dimension && axis < 3; ++axis)
  {
    strides.cellBytes[static_cast<std::size_t>(axis)] = stride;
    strides.ghostCells[static_cast<std::size_t>(axis)] = ghostCells;
    stride *= extent;
  }
  // Outermost: a component is one whole block array; innermost: the next value.
  strides.componentBytes = variableOutermost ? stride : valueSize;
  return strides;
}

} // namespace canopy
