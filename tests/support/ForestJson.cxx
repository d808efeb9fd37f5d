#include "ForestJson.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <limits>
#include <sstream>

namespace canopy::testing
{
namespace
{

int childrenPerNode(const ForestDescription& f)
{
  int children = 1;
  for (int axis = 0; axis < f.dimension; ++axis)
  {
    children *= f.branchFactor;
  }
  return children;
}

/// Component c of tuple i of a field, as double (exact for the types used in tests).
double valueAt(const FieldDescription& field, std::size_t i, int c)
{
  const std::size_t size = sizeOf(field.type);
  const auto cc = static_cast<std::size_t>(c);
  const char* address = nullptr;
  switch (field.layout)
  {
  case Layout::AoS:
    address = static_cast<const char*>(field.data) +
              (i * static_cast<std::size_t>(field.components) + cc) * size;
    break;
  case Layout::Strided:
    address = static_cast<const char*>(field.data) + i * field.tupleStrideBytes + cc * size;
    break;
  case Layout::SoA:
    address = static_cast<const char*>(field.componentData[cc]) + i * size;
    break;
  case Layout::Indirect:
    address = static_cast<const char*>(field.tupleAddresses[i]) + cc * size;
    break;
  case Layout::Blocks:
    throw std::invalid_argument("ForestJson: block fields have no tuple order");
  }
  switch (field.type)
  {
  case ValueType::Float32:
  {
    float v;
    std::memcpy(&v, address, sizeof(v));
    return v;
  }
  case ValueType::Float64:
  {
    double v;
    std::memcpy(&v, address, sizeof(v));
    return v;
  }
  case ValueType::Int32:
  {
    std::int32_t v;
    std::memcpy(&v, address, sizeof(v));
    return v;
  }
  case ValueType::Int64:
  {
    std::int64_t v;
    std::memcpy(&v, address, sizeof(v));
    return static_cast<double>(v);
  }
  }
  return 0.0;
}

/// The forest's per-tree structure: slots, first child of each node, leaf tuples.
struct Structure
{
  std::vector<std::vector<std::int64_t>> slot;       // [tree][node]
  std::vector<std::vector<std::int64_t>> firstChild; // [tree][node], -1 for leaves
  std::vector<std::int64_t> leafTupleOfSlot;         // -1 for coarse slots
};

Structure structureOf(const ForestDescription& f)
{
  Structure s;
  std::int64_t next = 0;
  for (const auto& tree : f.trees)
  {
    std::vector<std::int64_t> slots(tree.numberOfNodes), first(tree.numberOfNodes, -1);
    std::int64_t child = 1;
    for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
    {
      slots[n] = tree.storageSlots ? tree.storageSlots[n] : next + static_cast<std::int64_t>(n);
      if (tree.refinement[n])
      {
        first[n] = child;
        child += childrenPerNode(f);
      }
    }
    next += static_cast<std::int64_t>(tree.numberOfNodes);
    s.slot.push_back(std::move(slots));
    s.firstChild.push_back(std::move(first));
  }
  std::vector<char> isLeaf(static_cast<std::size_t>(next), 0);
  for (std::size_t t = 0; t < f.trees.size(); ++t)
    for (std::size_t n = 0; n < f.trees[t].numberOfNodes; ++n)
      isLeaf[static_cast<std::size_t>(s.slot[t][n])] = f.trees[t].refinement[n] ? 0 : 1;
  s.leafTupleOfSlot.assign(isLeaf.size(), -1);
  std::int64_t leaf = 0;
  for (std::size_t i = 0; i < isLeaf.size(); ++i)
    if (isLeaf[i])
      s.leafTupleOfSlot[i] = leaf++;
  return s;
}

/// Component c of a field at node n of tree t, coarse values of leaves-only fields
/// restricted as Canopy does.
double fieldAt(const ForestDescription& f, const Structure& s, const FieldDescription& field,
               std::size_t t, std::size_t n, int c)
{
  const std::int64_t slot = s.slot[t][n];
  if (field.centering == Centering::EveryNode)
    return valueAt(field, static_cast<std::size_t>(slot), c);
  if (!f.trees[t].refinement[n])
    return valueAt(field,
                   static_cast<std::size_t>(s.leafTupleOfSlot[static_cast<std::size_t>(slot)]), c);
  const std::uint8_t* mask = f.trees[t].masked;
  const int children = childrenPerNode(f);
  for (int pass = 0; pass < 2; ++pass)
  {
    double sum = 0.0;
    int used = 0;
    for (int k = 0; k < children; ++k)
    {
      const auto child = static_cast<std::size_t>(s.firstChild[t][n] + k);
      if (pass == 0 && mask && mask[child])
        continue;
      sum += fieldAt(f, s, field, t, child, c);
      ++used;
    }
    if (used > 0)
      return sum / used;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

} // namespace

void writeForestJsonHeader(std::ostream& json, const ForestDescription& whole, int step,
                           double time, int ranks)
{
  const auto precision = json.precision(17);
  json << "{\"step\": " << step << ", \"time\": " << time << ", \"ranks\": " << ranks
       << ", \"dimension\": " << whole.dimension << ", \"branch_factor\": " << whole.branchFactor
       << ", \"coordinates\": [";
  const double* axes[3] = {whole.rootGrid.x, whole.rootGrid.y, whole.rootGrid.z};
  const std::size_t points[3] = {whole.rootGrid.pointsX, whole.rootGrid.pointsY,
                                 whole.rootGrid.pointsZ};
  for (int a = 0; a < 3; ++a)
  {
    json << (a ? ", [" : "[");
    for (std::size_t i = 0; i < points[a]; ++i)
      json << (i ? ", " : "") << axes[a][i];
    json << "]";
  }
  json << "]";
  json.precision(precision);
}

std::string forestJson(const ForestDescription& whole, const std::vector<int>& owners, int step,
                       double time, int ranks, int samples)
{
  std::ostringstream json;
  json << std::setprecision(17);
  writeForestJsonHeader(json, whole, step, time, ranks);
  json << ", \"fields\": {";
  for (std::size_t i = 0; i < whole.fields.size(); ++i)
  {
    const auto& field = whole.fields[i];
    json << (i ? ", " : "") << "\"" << field.name << "\": {\"components\": " << field.components
         << ", \"leaves_only\": " << (field.centering == Centering::LeavesOnly ? "true" : "false")
         << "}";
  }
  json << "}, \"trees\": [";
  std::size_t totalNodes = 0;
  for (std::size_t t = 0; t < whole.trees.size(); ++t)
  {
    const auto& tree = whole.trees[t];
    totalNodes += tree.numberOfNodes;
    std::string refinement(tree.numberOfNodes, '0'), mask;
    for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
      refinement[n] = tree.refinement[n] ? '1' : '0';
    if (tree.masked)
    {
      mask.assign(tree.numberOfNodes, '0');
      for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
        mask[n] = tree.masked[n] ? '1' : '0';
    }
    json << (t ? ",\n  " : "\n  ") << "{\"root\": " << tree.rootIndex
         << ", \"rank\": " << (t < owners.size() ? owners[t] : -1) << ", \"refinement\": \""
         << refinement << "\", \"mask\": \"" << mask << "\"}";
  }
  json << "],\n \"samples\": [";
  const Structure structure = structureOf(whole);
  bool first = true;
  for (int k = 0; k < samples && totalNodes > 0; ++k)
  {
    // Spread over the forest's cells, tree by tree.
    std::size_t index =
        static_cast<std::size_t>(k) * totalNodes / static_cast<std::size_t>(samples);
    std::size_t t = 0;
    while (index >= whole.trees[t].numberOfNodes)
      index -= whole.trees[t++].numberOfNodes;
    json << (first ? "\n  " : ",\n  ") << "{\"root\": " << whole.trees[t].rootIndex
         << ", \"node\": " << index << ", \"values\": {";
    first = false;
    for (std::size_t i = 0; i < whole.fields.size(); ++i)
    {
      const auto& field = whole.fields[i];
      json << (i ? ", " : "") << "\"" << field.name << "\": [";
      for (int c = 0; c < field.components; ++c)
        json << (c ? ", " : "") << fieldAt(whole, structure, field, t, index, c);
      json << "]";
    }
    json << "}}";
  }
  json << "]}\n";
  return json.str();
}

} // namespace canopy::testing
