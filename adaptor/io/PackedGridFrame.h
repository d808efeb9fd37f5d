// The frame around each rank's piece in vtkCanopyHyperTreeGridPacker's bytes:
// "CNPY", then the .htg text's length (8 bytes, little endian), then the text.
// One home for it: the packer writes frames, the unpacker reads them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace canopy::io::packed
{

inline constexpr char Magic[4] = {'C', 'N', 'P', 'Y'};
inline constexpr std::size_t HeaderBytes = sizeof(Magic) + 8;

/// `text` framed.
inline std::string frame(const std::string& text)
{
  std::string framed(Magic, sizeof(Magic));
  std::uint64_t length = text.size();
  for (int byte = 0; byte < 8; ++byte)
  {
    framed.push_back(static_cast<char>((length >> (8 * byte)) & 0xffu));
  }
  return framed + text;
}

/// The length of the frame's text at `bytes` (HeaderBytes available), or -1
/// when the magic is not there.
inline std::int64_t textLength(const unsigned char* bytes)
{
  for (std::size_t i = 0; i < sizeof(Magic); ++i)
  {
    if (bytes[i] != static_cast<unsigned char>(Magic[i]))
    {
      return -1;
    }
  }
  std::uint64_t length = 0;
  for (int byte = 7; byte >= 0; --byte)
  {
    length = (length << 8) | bytes[sizeof(Magic) + byte];
  }
  return static_cast<std::int64_t>(length);
}

} // namespace canopy::io::packed
