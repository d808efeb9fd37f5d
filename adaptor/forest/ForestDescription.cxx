#include "canopy/ForestDescription.h"

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
