// A fingerprint of a forest description (see ForestFingerprint.h).
#include "ForestFingerprint.h"

#include <cstdio>

namespace canopy::tools
{
namespace
{

/// FNV-1a over bytes, chained: slow next to ByteHash.h's, but the benchmarks
/// print it once per input and it needs nothing from the library's internals.
struct Hash
{
  std::uint64_t value = 0xCBF29CE484222325ull;
  void add(const void* data, std::size_t bytes)
  {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i)
    {
      value = (value ^ p[i]) * 0x100000001B3ull;
    }
  }
  template <typename T>
  void add(const T& plain)
  {
    this->add(&plain, sizeof(T));
  }
};

std::size_t valueBytes(ValueType type)
{
  return type == ValueType::Float32 || type == ValueType::Int32 ? 4 : 8;
}

void addArray(Hash& h, const void* data, std::size_t bytes)
{
  h.add(static_cast<std::uint64_t>(data ? bytes : 0));
  if (data)
  {
    h.add(data, bytes);
  }
}

void addField(Hash& h, const FieldDescription& field, int blockCells, int dimension)
{
  h.add(field.name.data(), field.name.size());
  h.add(static_cast<int>(field.type));
  h.add(field.components);
  h.add(static_cast<int>(field.centering));
  const std::size_t size = valueBytes(field.type);
  const std::size_t tuple = size * static_cast<std::size_t>(field.components);
  // Tuple by tuple, components in order, whatever the layout: the same values
  // read from another layout give the same fingerprint.
  if (field.layout != Layout::Blocks)
  {
    h.add(static_cast<std::uint64_t>(field.numberOfTuples));
  }
  switch (field.layout)
  {
  case Layout::AoS:
    if (field.data)
    {
      h.add(field.data, tuple * field.numberOfTuples);
    }
    break;
  case Layout::SoA:
    for (std::size_t t = 0; t < field.numberOfTuples; ++t)
    {
      for (const void* component : field.componentData)
      {
        h.add(static_cast<const char*>(component) + t * size, size);
      }
    }
    break;
  case Layout::Strided:
    for (std::size_t t = 0; field.data && t < field.numberOfTuples; ++t)
    {
      h.add(static_cast<const char*>(field.data) + t * field.tupleStrideBytes, tuple);
    }
    break;
  case Layout::Indirect:
    for (std::size_t t = 0; field.tupleAddresses && t < field.numberOfTuples; ++t)
    {
      h.add(field.tupleAddresses[t], tuple);
    }
    break;
  case Layout::Blocks:
  {
    const BlockStrides& s = field.blockStrides;
    const int nk = dimension > 2 ? blockCells : 1;
    const int nj = dimension > 1 ? blockCells : 1;
    for (std::size_t b = 0; b < field.numberOfBlocks; ++b)
    {
      for (int c = 0; c < field.components; ++c)
      {
        const char* base =
            field.componentBlockAddresses.empty()
                ? (field.blockAddresses ? static_cast<const char*>(field.blockAddresses[b])
                                        : nullptr)
                : static_cast<const char*>(
                      field.componentBlockAddresses[static_cast<std::size_t>(c)][b]);
        if (base == nullptr)
        {
          continue;
        }
        if (field.componentBlockAddresses.empty())
        {
          base += static_cast<std::size_t>(c) * s.componentBytes;
        }
        for (int k = 0; k < nk; ++k)
          for (int j = 0; j < nj; ++j)
            for (int i = 0; i < blockCells; ++i)
            {
              h.add(base + static_cast<std::size_t>(i + s.ghostCells[0]) * s.cellBytes[0] +
                        static_cast<std::size_t>(j + s.ghostCells[1]) * s.cellBytes[1] +
                        static_cast<std::size_t>(k + s.ghostCells[2]) * s.cellBytes[2],
                    size);
            }
      }
    }
    break;
  }
  }
}

} // namespace

std::uint64_t forestFingerprint(const ForestDescription& forest)
{
  Hash h;
  h.add(forest.dimension);
  h.add(forest.branchFactor);
  h.add(forest.blockCellsPerSide);
  addArray(h, forest.rootGrid.x, sizeof(double) * forest.rootGrid.pointsX);
  addArray(h, forest.rootGrid.y, sizeof(double) * forest.rootGrid.pointsY);
  addArray(h, forest.rootGrid.z, sizeof(double) * forest.rootGrid.pointsZ);
  for (const TreeDescription& tree : forest.trees)
  {
    const std::size_t n = tree.numberOfNodes;
    h.add(tree.rootIndex);
    addArray(h, tree.refinement, n);
    addArray(h, tree.masked, n);
    addArray(h, tree.absent, n);
    addArray(h, tree.storageSlots, sizeof(std::int64_t) * n);
    addArray(h, tree.blockIndex, sizeof(std::int64_t) * n);
  }
  for (const FieldDescription& field : forest.fields)
  {
    addField(h, field, forest.blockCellsPerSide, forest.dimension);
  }
  return h.value;
}

std::string describeInput(const std::string& label, const ForestDescription& forest)
{
  std::size_t nodes = 0;
  for (const TreeDescription& tree : forest.trees)
  {
    nodes += tree.numberOfNodes;
  }
  char text[64];
  std::snprintf(text, sizeof text, "%016llx",
                static_cast<unsigned long long>(forestFingerprint(forest)));
  return "input " + label + ": " + std::to_string(forest.trees.size()) + " trees, " +
         std::to_string(nodes) + " nodes, fingerprint " + text;
}

} // namespace canopy::tools
