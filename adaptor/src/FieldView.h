// Uniform strided view of a borrowed field, whatever its layout.
//
// AoS, SoA and strided layouts all reduce to "component c of tuple i lives at
// base[c] + i * stride bytes". Code that reads simulation fields (restriction of
// leaf values, strided wrapping) uses this one form instead of three.
#pragma once

#include "canopy/ForestDescription.h"

#include <cstddef>
#include <cstring>
#include <vector>

namespace canopy
{

template <typename T>
struct FieldView
{
  std::vector<const T*> bases;
  std::size_t strideBytes = 0;

  static FieldView of(const FieldDescription& field)
  {
    FieldView view;
    const auto nc = static_cast<std::size_t>(field.components);
    switch (field.layout)
    {
    case Layout::AoS:
    case Layout::Strided:
    {
      const T* first = static_cast<const T*>(field.data);
      for (std::size_t c = 0; c < nc; ++c)
      {
        view.bases.push_back(first + c);
      }
      view.strideBytes = field.layout == Layout::AoS ? nc * sizeof(T) : field.tupleStrideBytes;
      break;
    }
    case Layout::SoA:
      for (const void* component : field.componentData)
      {
        view.bases.push_back(static_cast<const T*>(component));
      }
      view.strideBytes = sizeof(T);
      break;
    }
    return view;
  }

  T at(std::size_t tuple, std::size_t component) const
  {
    T value;
    std::memcpy(&value,
                reinterpret_cast<const unsigned char*>(bases[component]) + tuple * strideBytes,
                sizeof(T));
    return value;
  }
};

} // namespace canopy
