#include "CApiArguments.h"

#include "CApiStatus.h"

#include <cstdint>

namespace canopy::capi
{
namespace
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

} // namespace canopy::capi
