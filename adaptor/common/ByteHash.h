// A fast 64-bit fingerprint of a byte range, for "did this change since last
// time?" questions (the builder's unchanged trees, the selection mask's kept
// trees). Not cryptographic: a fingerprint collision would keep stale work, so
// callers key on it together with sizes and object identities.
//
// Header-only: the forest library and the filters both use it, and neither
// library links the other.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace canopy
{

/// 64-bit hash of `bytes` bytes at `data`: four independent multiply-xorshift
/// lanes over 32-byte blocks (a fraction of a nanosecond per byte, against tens
/// of nanoseconds per node for the work it lets callers skip).
inline std::uint64_t hashBytes(const void* data, std::size_t bytes, std::uint64_t seed)
{
  constexpr std::uint64_t k = 0x9E3779B97F4A7C15ull;
  std::uint64_t lanes[4] = {seed ^ (bytes * k), seed + k, seed ^ 0xD6E8FEB86659FD93ull, seed - k};
  const auto* p = static_cast<const unsigned char*>(data);
  std::size_t i = 0;
  for (; i + 32 <= bytes; i += 32)
  {
    for (int l = 0; l < 4; ++l)
    {
      std::uint64_t word;
      std::memcpy(&word, p + i + 8 * l, 8);
      lanes[l] = (lanes[l] ^ word) * k;
      lanes[l] ^= lanes[l] >> 29;
    }
  }
  std::uint64_t h = lanes[0] ^ (lanes[1] * 3) ^ (lanes[2] * 5) ^ (lanes[3] * 7);
  for (; i < bytes; ++i)
  {
    h = (h ^ p[i]) * k;
  }
  h ^= h >> 32;
  return h * 0xD6E8FEB86659FD93ull;
}

/// Folds one more value into a running fingerprint.
inline std::uint64_t hashCombine(std::uint64_t h, std::uint64_t value)
{
  return hashBytes(&value, sizeof value, h);
}

} // namespace canopy
