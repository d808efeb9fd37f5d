// Uniform view of a borrowed field, whatever its layout.
//
// AoS, SoA and strided layouts all reduce to "component c of tuple i lives at
// componentBase[c] + i * strideBytes"; the indirect layout (records scattered in
// memory) to "at tupleAddress[i] + c * valueSize". Code that reads simulation
// fields (restriction of leaf values, borrowing arrays) uses this one form.
#pragma once

#include <canopy/ForestDescription.h>

#include <cstddef>
#include <cstring>
#include <vector>

namespace canopy
{

struct FieldView
{
  std::vector<const unsigned char*> componentBase; ///< strided forms
  std::size_t strideBytes = 0;
  const void* const* tupleAddress = nullptr; ///< indirect form
  std::size_t valueSize = 0;

  static FieldView of(const FieldDescription& field)
  {
    FieldView view;
    const auto nc = static_cast<std::size_t>(field.components);
    view.valueSize = sizeOf(field.type);
    // A rank without trees may pass null with zero tuples: no pointer arithmetic on null.
    const auto offset = [](const void* base, std::size_t bytes)
    { return base ? static_cast<const unsigned char*>(base) + bytes : nullptr; };
    switch (field.layout)
    {
    case Layout::AoS:
    case Layout::Strided:
      for (std::size_t c = 0; c < nc; ++c)
      {
        view.componentBase.push_back(offset(field.data, c * view.valueSize));
      }
      view.strideBytes = field.layout == Layout::AoS ? nc * view.valueSize : field.tupleStrideBytes;
      break;
    case Layout::SoA:
      for (const void* component : field.componentData)
      {
        view.componentBase.push_back(static_cast<const unsigned char*>(component));
      }
      view.strideBytes = view.valueSize;
      break;
    case Layout::Indirect:
      view.tupleAddress = field.tupleAddresses;
      break;
    case Layout::Blocks: // read through BlockField, never a view
      break;
    }
    return view;
  }

  const unsigned char* address(std::size_t tuple, std::size_t component) const
  {
    return tupleAddress
               ? static_cast<const unsigned char*>(tupleAddress[tuple]) + component * valueSize
               : componentBase[component] + tuple * strideBytes;
  }

  template <typename T>
  T at(std::size_t tuple, std::size_t component) const
  {
    T value;
    std::memcpy(&value, address(tuple, component), sizeof(T));
    return value;
  }
};

} // namespace canopy
