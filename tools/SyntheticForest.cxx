#include "SyntheticForest.h"

#include <algorithm>
#include <cmath>

namespace canopy::tools
{
namespace
{

constexpr double FrontWidth = 0.04;

struct Box
{
  std::array<double, 3> low;
  std::array<double, 3> high;
};

double distanceToCentre(const std::array<double, 3>& p)
{
  return std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
}

/// True when the box straddles the front (sphere of frontRadius, +/- its width).
bool crossesFront(const Box& box, double frontRadius)
{
  std::array<double, 3> nearest;
  std::array<double, 3> farthest;
  for (int a = 0; a < 3; ++a)
  {
    nearest[a] = std::clamp(0.0, box.low[a], box.high[a]);
    farthest[a] = std::abs(box.low[a]) > std::abs(box.high[a]) ? box.low[a] : box.high[a];
  }
  return distanceToCentre(nearest) <= frontRadius + FrontWidth &&
         distanceToCentre(farthest) >= frontRadius - FrontWidth;
}

std::array<double, 3> centre(const Box& box)
{
  return {{0.5 * (box.low[0] + box.high[0]), 0.5 * (box.low[1] + box.high[1]),
           0.5 * (box.low[2] + box.high[2])}};
}

} // namespace

SyntheticForest::SyntheticForest(const SyntheticForestOptions& o)
{
  const int n = o.rootsPerAxis;
  for (int a = 0; a < 3; ++a)
  {
    const bool flat = o.dimension == 2 && a == 2;
    if (flat)
    {
      Coordinates[a] = {0.0};
      continue;
    }
    // Slightly stretched towards the boundary, as simulations often are.
    for (int i = 0; i <= n; ++i)
    {
      const double s = -1.0 + 2.0 * i / n;
      Coordinates[a].push_back(s * (0.85 + 0.15 * s * s));
    }
  }
  const std::size_t rootsZ = o.dimension == 3 ? static_cast<std::size_t>(n) : 1;
  const std::size_t children =
      static_cast<std::size_t>(o.dimension == 3 ? o.branchFactor * o.branchFactor * o.branchFactor
                                                : o.branchFactor * o.branchFactor);

  Description.dimension = o.dimension;
  Description.branchFactor = o.branchFactor;
  Description.maxLevels = o.maxLevels;
  Description.rootGrid = {Coordinates[0].data(), Coordinates[1].data(), Coordinates[2].data(),
                          Coordinates[0].size(), Coordinates[1].size(), Coordinates[2].size()};

  std::size_t slotOffset = 0;
  const auto roots = static_cast<std::size_t>(n) * static_cast<std::size_t>(n) * rootsZ;
  for (std::size_t root = 0; root < roots; ++root)
  {
    const std::size_t i = root % n, j = (root / n) % n,
                      k = root / (static_cast<std::size_t>(n) * n);
    Box rootBox{
        {{Coordinates[0][i], Coordinates[1][j], o.dimension == 3 ? Coordinates[2][k] : 0.0}},
        {{Coordinates[0][i + 1], Coordinates[1][j + 1],
          o.dimension == 3 ? Coordinates[2][k + 1] : 0.0}}};
    // Breadth-first refinement, as the description wants it.
    std::vector<std::uint8_t> refinement{0};
    std::vector<Box> boxes{rootBox};
    std::vector<int> levels{0};
    std::vector<std::size_t> firstChild{0};
    for (std::size_t node = 0; node < boxes.size(); ++node)
    {
      if (levels[node] + 1 >= o.maxLevels || !crossesFront(boxes[node], o.frontRadius))
      {
        continue;
      }
      refinement[node] = 1;
      firstChild[node] = boxes.size();
      const Box parent = boxes[node];
      for (std::size_t c = 0; c < children; ++c)
      {
        Box child = parent;
        std::size_t rest = c;
        for (int a = 0; a < o.dimension; ++a)
        {
          const std::size_t position = rest % o.branchFactor;
          rest /= o.branchFactor;
          const double size = (parent.high[a] - parent.low[a]) / o.branchFactor;
          child.low[a] = parent.low[a] + position * size;
          child.high[a] = child.low[a] + size;
        }
        boxes.push_back(child);
        refinement.push_back(0);
        levels.push_back(levels[node] + 1);
        firstChild.push_back(0);
      }
    }
    // The simulation's own order: depth-first (pre-order), or breadth-first.
    std::vector<std::int64_t> slots(boxes.size());
    for (std::size_t node = 0; node < boxes.size(); ++node)
    {
      slots[node] = static_cast<std::int64_t>(slotOffset + node);
    }
    std::vector<std::size_t> stack;
    if (o.depthFirstStorage)
    {
      stack.push_back(0);
    }
    std::size_t next = slotOffset;
    while (!stack.empty())
    {
      const std::size_t node = stack.back();
      stack.pop_back();
      slots[node] = static_cast<std::int64_t>(next++);
      if (refinement[node])
      {
        for (std::size_t c = children; c-- > 0;)
        {
          stack.push_back(firstChild[node] + c);
        }
      }
    }
    Cells.resize(slotOffset + boxes.size());
    std::vector<std::uint8_t> masked(boxes.size(), 0);
    for (std::size_t node = 0; node < boxes.size(); ++node)
    {
      const auto p = centre(boxes[node]);
      const double r = distanceToCentre(p);
      const double front = std::exp(-std::pow((r - o.frontRadius) / FrontWidth, 2));
      CellRecord& cell = Cells[static_cast<std::size_t>(slots[node])];
      cell.density = 1.0 + 3.0 * front;
      for (int a = 0; a < 3; ++a)
      {
        cell.velocity[a] = r > 0 ? 2.0 * front * p[a] / r : 0.0;
      }
      cell.refinementLevel = levels[node];
      const Box& b = boxes[node];
      masked[node] =
          o.cutaway && b.low[0] >= 0 && b.low[1] >= 0 && (o.dimension == 2 || b.low[2] >= 0);
    }
    slotOffset += boxes.size();
    Refinement.push_back(std::move(refinement));
    Masked.push_back(std::move(masked));
    Slots.push_back(std::move(slots));
  }
  // Leaves-only pressure, one value per leaf in slot order (the simulation's order).
  std::vector<std::uint8_t> slotIsLeaf(Cells.size(), 0);
  for (std::size_t t = 0; t < Refinement.size(); ++t)
  {
    for (std::size_t node = 0; node < Refinement[t].size(); ++node)
    {
      slotIsLeaf[static_cast<std::size_t>(Slots[t][node])] = Refinement[t][node] == 0;
    }
  }
  for (std::size_t s = 0; s < Cells.size(); ++s)
  {
    if (slotIsLeaf[s])
    {
      Pressure.push_back(std::pow(Cells[s].density, 1.4));
    }
  }

  for (std::size_t t = 0; t < Refinement.size(); ++t)
  {
    TreeDescription tree;
    tree.rootIndex = static_cast<std::int64_t>(t);
    tree.refinement = Refinement[t].data();
    tree.numberOfNodes = Refinement[t].size();
    tree.masked = o.cutaway ? Masked[t].data() : nullptr;
    tree.storageSlots = o.depthFirstStorage ? Slots[t].data() : nullptr;
    Description.trees.push_back(tree);
  }
  const std::size_t stride = sizeof(CellRecord);
  Description.fields.push_back(
      FieldDescription::strided("density", &Cells[0].density, stride, Cells.size()));
  Description.fields.push_back(
      FieldDescription::strided("velocity", &Cells[0].velocity[0], stride, Cells.size(), 3));
  Description.fields.push_back(FieldDescription::strided(
      "refinementLevel", &Cells[0].refinementLevel, stride, Cells.size()));
  Description.fields.push_back(FieldDescription::aos("pressure", Pressure.data(), Pressure.size(),
                                                     1, Centering::LeavesOnly));
}

} // namespace canopy::tools
