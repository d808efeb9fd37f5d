// Small pieces every validation stage uses (ForestValidation, BlockValidation):
// how a tree is named in a message, counting set bytes, pointer alignment.
#pragma once

#include <canopy/ForestDescription.h>

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

namespace canopy
{

/// "tree 3 (root 17)": how every message names a tree.
inline std::string treeName(std::size_t t, const TreeDescription& tree)
{
  std::ostringstream out;
  out << "tree " << t << " (root " << tree.rootIndex << ")";
  return out.str();
}

/// Nonzero bytes among `n` (refined, absent or masked nodes).
inline std::size_t countNonZero(const std::uint8_t* bytes, std::size_t n)
{
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    count += bytes[i] != 0;
  }
  return count;
}

/// A pointer values of `valueSize` bytes cannot be read through as T (null is not).
inline bool misaligned(const void* pointer, std::size_t valueSize)
{
  return pointer != nullptr && reinterpret_cast<std::uintptr_t>(pointer) % valueSize != 0;
}

} // namespace canopy
