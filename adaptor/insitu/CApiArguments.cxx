#include "CApiArguments.h"

#include "CApiStatus.h"

#include <cstdint>

namespace canopy::capi
{

bool valueTypeFromC(int code, ValueType& type)
{
  switch (code)
  {
  case CANOPY_FLOAT32:
    type = ValueType::Float32;
    return true;
  case CANOPY_FLOAT64:
    type = ValueType::Float64;
    return true;
  case CANOPY_INT32:
    type = ValueType::Int32;
    return true;
  case CANOPY_INT64:
    type = ValueType::Int64;
    return true;
  default:
    return false;
  }
}

namespace
{

bool centeringFromC(int code, Centering& centering)
{
  if (code == CANOPY_EVERY_NODE || code == CANOPY_LEAVES_ONLY)
  {
    centering = code == CANOPY_EVERY_NODE ? Centering::EveryNode : Centering::LeavesOnly;
    return true;
  }
  return false;
}

} // namespace

bool negativeCount(std::size_t count)
{
  return count > static_cast<std::size_t>(PTRDIFF_MAX);
}

int checkString(const char* function, const char* what, const char* text, bool mayBeEmpty)
{
  if (text == nullptr)
  {
    return fail(CANOPY_INVALID_ARGUMENT, "%s: %s is NULL", function, what);
  }
  if (!mayBeEmpty && *text == '\0')
  {
    return fail(CANOPY_INVALID_ARGUMENT, "%s: %s is empty", function, what);
  }
  return CANOPY_OK;
}

int checkField(const char* function, const char* name, int valueType, int components,
               std::size_t numberOfTuples, int centering, FieldDescription& field)
{
  if (const int status = checkString(function, "the field name", name, false))
  {
    return status;
  }
  if (!valueTypeFromC(valueType, field.type))
  {
    return fail(CANOPY_INVALID_ARGUMENT,
                "%s: field '%s': unknown value type %d (use CANOPY_FLOAT32/FLOAT64/INT32/INT64)",
                function, name, valueType);
  }
  if (!centeringFromC(centering, field.centering))
  {
    return fail(CANOPY_INVALID_ARGUMENT,
                "%s: field '%s': unknown centering %d (use CANOPY_EVERY_NODE or "
                "CANOPY_LEAVES_ONLY)",
                function, name, centering);
  }
  if (components < 1)
  {
    return fail(CANOPY_INVALID_ARGUMENT, "%s: field '%s': components must be at least 1, got %d",
                function, name, components);
  }
  if (negativeCount(numberOfTuples))
  {
    return fail(CANOPY_INVALID_ARGUMENT,
                "%s: field '%s': number_of_tuples %zu is negative or too large", function, name,
                numberOfTuples);
  }
  field.name = name; // may throw bad_alloc: the caller is guarded
  field.components = components;
  field.numberOfTuples = numberOfTuples;
  return CANOPY_OK;
}

int checkAxis(const char* function, char axis, const double* coordinates, std::size_t points)
{
  if (negativeCount(points))
  {
    return fail(CANOPY_INVALID_ARGUMENT, "%s: points_%c %zu is negative or too large", function,
                axis, points);
  }
  if (points == 0)
  {
    return fail(CANOPY_INVALID_ARGUMENT,
                "%s: points_%c is 0 (every axis has at least 1 point; a flat axis exactly 1)",
                function, axis);
  }
  if (coordinates == nullptr)
  {
    return fail(CANOPY_INVALID_ARGUMENT, "%s: %c is NULL but points_%c is %zu", function, axis,
                axis, points);
  }
  return CANOPY_OK;
}

bool misaligned(const void* pointer, std::size_t valueSize)
{
  return reinterpret_cast<std::uintptr_t>(pointer) % valueSize != 0;
}

int checkBlockSize(const char* function, int cellsPerSide, int branchFactor, int maxLevels)
{
  if (cellsPerSide == 0)
  {
    return CANOPY_OK;
  }
  int levels = 0;
  long long side = 1;
  while (side < cellsPerSide)
  {
    side *= branchFactor;
    ++levels;
  }
  if (cellsPerSide < 0 || side != cellsPerSide || levels < 1)
  {
    const int b = branchFactor;
    return fail(CANOPY_INVALID_ARGUMENT,
                "%s: cells_per_side must be 0 (no blocks) or a power of the branch factor %d "
                "(%d, %d, %d, %d, ...), got %d",
                function, b, b, b * b, b * b * b, b * b * b * b, cellsPerSide);
  }
  if (levels + 1 > maxLevels)
  {
    return fail(CANOPY_INVALID_ARGUMENT,
                "%s: blocks of %d cells across add %d levels below each block's root, more than "
                "the max_levels %d of canopy_forest_create allows (it counts them, and the root's)",
                function, cellsPerSide, levels, maxLevels);
  }
  return CANOPY_OK;
}

int checkBlockField(const char* function, const char* name, int valueType, int components,
                    std::size_t numberOfBlocks, const canopy_block_strides* strides, int dimension,
                    bool separateComponents, FieldDescription& field)
{
  if (const int status =
          checkField(function, name, valueType, components, 0, CANOPY_LEAVES_ONLY, field))
  {
    return status;
  }
  if (field.type != ValueType::Float32 && field.type != ValueType::Float64)
  {
    return fail(CANOPY_INVALID_ARGUMENT,
                "%s: field '%s': a block field is CANOPY_FLOAT32 or CANOPY_FLOAT64 (its coarse "
                "cells are volume averages), got value type %d",
                function, name, valueType);
  }
  if (negativeCount(numberOfBlocks))
  {
    return fail(CANOPY_INVALID_ARGUMENT,
                "%s: field '%s': number_of_blocks %zu is negative or too large", function, name,
                numberOfBlocks);
  }
  if (strides == nullptr)
  {
    return fail(CANOPY_INVALID_ARGUMENT, "%s: field '%s': strides is NULL", function, name);
  }
  const std::size_t valueSize = sizeOf(field.type);
  for (int a = 0; a < dimension; ++a)
  {
    const std::size_t stride = strides->cell_bytes[a];
    if (negativeCount(stride) || stride == 0 || stride % valueSize != 0)
    {
      return fail(CANOPY_INVALID_ARGUMENT,
                  "%s: field '%s': strides->cell_bytes[%d] %zu is not a nonzero multiple of the "
                  "value size %zu (or is negative)",
                  function, name, a, stride, valueSize);
    }
    if (strides->ghost_cells[a] < 0)
    {
      return fail(CANOPY_INVALID_ARGUMENT,
                  "%s: field '%s': strides->ghost_cells[%d] %d is negative", function, name, a,
                  strides->ghost_cells[a]);
    }
  }
  const std::size_t componentBytes = strides->component_bytes;
  if (!separateComponents && components > 1 &&
      (negativeCount(componentBytes) || componentBytes == 0 || componentBytes % valueSize != 0))
  {
    return fail(CANOPY_INVALID_ARGUMENT,
                "%s: field '%s': strides->component_bytes %zu is not a nonzero multiple of the "
                "value size %zu (or is negative), with %d components",
                function, name, componentBytes, valueSize, components);
  }
  field.layout = Layout::Blocks;
  field.centering = Centering::LeavesOnly;
  field.numberOfBlocks = numberOfBlocks;
  for (std::size_t a = 0; a < 3; ++a)
  {
    // Axes beyond the dimension are ignored: zeros, whatever the caller left there.
    const bool used = a < static_cast<std::size_t>(dimension);
    field.blockStrides.cellBytes[a] = used ? strides->cell_bytes[a] : 0;
    field.blockStrides.ghostCells[a] = used ? strides->ghost_cells[a] : 0;
  }
  field.blockStrides.componentBytes = separateComponents ? 0 : componentBytes;
  return CANOPY_OK;
}

int checkBlockAddresses(const char* function, const char* name, const char* what,
                        const void* const* table, std::size_t count, std::size_t blocksPerComponent,
                        std::size_t valueSize)
{
  if (table == nullptr)
  {
    return count == 0 ? CANOPY_OK
                      : fail(CANOPY_INVALID_ARGUMENT,
                             "%s: field '%s': %s is NULL but number_of_blocks is %zu", function,
                             name, what, blocksPerComponent);
  }
  for (std::size_t i = 0; i < count; ++i)
  {
    if (table[i] != nullptr && !misaligned(table[i], valueSize))
    {
      continue;
    }
    const char* problem = table[i] == nullptr ? "is NULL" : "is not aligned to the value size";
    if (count == blocksPerComponent)
    {
      return fail(CANOPY_INVALID_ARGUMENT, "%s: field '%s': %s[%zu] (block %zu) %s", function, name,
                  what, i, i, problem);
    }
    return fail(CANOPY_INVALID_ARGUMENT, "%s: field '%s': %s[%zu] (component %zu, block %zu) %s",
                function, name, what, i, i / blocksPerComponent, i % blocksPerComponent, problem);
  }
  return CANOPY_OK;
}

} // namespace canopy::capi
