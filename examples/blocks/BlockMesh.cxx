#include "BlockMesh.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace blocks
{
namespace
{

/// Child c of a block (c's bit a: the upper half along axis a).
BlockKey childOf(const BlockKey& key, int c, int dimension)
{
  BlockKey child{key.tree, key.level + 1, {{0, 0, 0}}};
  for (int a = 0; a < dimension; ++a)
  {
    child.at[a] = 2 * key.at[a] + ((c >> a) & 1);
  }
  return child;
}

BlockKey parentOf(const BlockKey& key, int dimension)
{
  BlockKey parent{key.tree, key.level - 1, {{0, 0, 0}}};
  for (int a = 0; a < dimension; ++a)
  {
    parent.at[a] = key.at[a] / 2;
  }
  return parent;
}

} // namespace

BlockMesh::BlockMesh(int dimension, std::array<int, 3> roots, int maxLevel)
    : Dimension(dimension), MaxLevel(maxLevel), Roots(roots)
{
  if (dimension < 2 || dimension > 3 || maxLevel < 0 || maxLevel > 10)
  {
    throw std::invalid_argument("BlockMesh: dimension 2 or 3, maxLevel 0 .. 10");
  }
  for (int a = 0; a < 3; ++a)
  {
    if (a >= dimension)
    {
      Roots[a] = 1;
    }
    Domain[a] = a < dimension ? Roots[a] * blockSide(0) : 0;
  }
  for (int t = 0; t < numberOfTrees(); ++t)
  {
    Leaves.push_back({t, 0, {{0, 0, 0}}});
  }
  index();
}

Point BlockMesh::corner(const BlockKey& key) const
{
  const int tree[3] = {key.tree % Roots[0], (key.tree / Roots[0]) % Roots[1],
                       key.tree / (Roots[0] * Roots[1])};
  Point lo{{0, 0, 0}};
  for (int a = 0; a < Dimension; ++a)
  {
    lo[a] = tree[a] * blockSide(0) + key.at[a] * blockSide(key.level);
  }
  return lo;
}

void BlockMesh::index()
{
  Trees.assign(static_cast<std::size_t>(numberOfTrees()), std::vector<Node>(1));
  TreeFirstBlock.assign(static_cast<std::size_t>(numberOfTrees()) + 1, numberOfBlocks());
  const int children = childrenPerBlock();
  for (std::int64_t b = numberOfBlocks(); b-- > 0;)
  {
    TreeFirstBlock[static_cast<std::size_t>(Leaves[static_cast<std::size_t>(b)].tree)] = b;
  }
  for (std::size_t t = TreeFirstBlock.size() - 1; t-- > 0;)
  {
    TreeFirstBlock[t] = std::min(TreeFirstBlock[t], TreeFirstBlock[t + 1]);
  }
  for (std::int64_t b = 0; b < numberOfBlocks(); ++b)
  {
    const BlockKey& key = Leaves[static_cast<std::size_t>(b)];
    std::vector<Node>& nodes = Trees[static_cast<std::size_t>(key.tree)];
    std::size_t node = 0;
    for (int level = 0;; ++level)
    {
      if (nodes[node].endBlock == 0)
      {
        nodes[node].firstBlock = b;
      }
      nodes[node].endBlock = b + 1;
      if (level == key.level)
      {
        break;
      }
      if (nodes[node].firstChild < 0)
      {
        nodes[node].firstChild = static_cast<std::int32_t>(nodes.size());
        nodes.resize(nodes.size() + static_cast<std::size_t>(children));
      }
      int digit = 0;
      for (int a = 0; a < Dimension; ++a)
      {
        digit |= static_cast<int>((key.at[a] >> (key.level - level - 1)) & 1) << a;
      }
      node = static_cast<std::size_t>(nodes[node].firstChild + digit);
    }
  }
}

std::int64_t BlockMesh::locate(const Point& point) const
{
  int tree = 0;
  Point lo{{0, 0, 0}};
  for (int a = Dimension; a-- > 0;)
  {
    const auto along = static_cast<int>(point[a] / blockSide(0));
    tree = tree * Roots[a] + along;
    lo[a] = along * blockSide(0);
  }
  const std::vector<Node>& nodes = Trees[static_cast<std::size_t>(tree)];
  std::size_t node = 0;
  for (std::int64_t side = blockSide(0); nodes[node].firstChild >= 0; side /= 2)
  {
    int digit = 0;
    for (int a = 0; a < Dimension; ++a)
    {
      if (point[a] >= lo[a] + side / 2)
      {
        digit |= 1 << a;
        lo[a] += side / 2;
      }
    }
    node = static_cast<std::size_t>(nodes[node].firstChild + digit);
  }
  return nodes[node].firstBlock;
}

void BlockMesh::blocksOverlapping(const Point& lo, const Point& hi,
                                  std::vector<std::int64_t>& out) const
{
  struct Visit
  {
    const std::vector<Node>* nodes;
    std::size_t node;
    Point corner;
    std::int64_t side;
  };
  std::vector<Visit> stack;
  for (int t = 0; t < numberOfTrees(); ++t)
  {
    stack.push_back(
        {&Trees[static_cast<std::size_t>(t)], 0, corner({t, 0, {{0, 0, 0}}}), blockSide(0)});
  }
  while (!stack.empty())
  {
    const Visit visit = stack.back();
    stack.pop_back();
    bool overlaps = true;
    for (int a = 0; a < Dimension; ++a)
    {
      overlaps = overlaps && visit.corner[a] < hi[a] && visit.corner[a] + visit.side > lo[a];
    }
    if (!overlaps)
    {
      continue;
    }
    const Node& node = (*visit.nodes)[visit.node];
    if (node.firstChild < 0)
    {
      out.push_back(node.firstBlock);
      continue;
    }
    for (int c = 0; c < childrenPerBlock(); ++c)
    {
      Point child = visit.corner;
      for (int a = 0; a < Dimension; ++a)
      {
        child[a] += ((c >> a) & 1) * (visit.side / 2);
      }
      stack.push_back(
          {visit.nodes, static_cast<std::size_t>(node.firstChild + c), child, visit.side / 2});
    }
  }
}

bool BlockMesh::unbalanced(const BlockKey& key) const
{
  // A face neighbour two levels finer or more holds (or is inside) one of the
  // quarter-size cubes along the face: look at their centres.
  if (key.level + 2 > MaxLevel)
  {
    return false;
  }
  const std::int64_t side = blockSide(key.level);
  const std::int64_t quarter = side / 4;
  const Point lo = corner(key);
  const int samples = Dimension == 2 ? 4 : 16;
  for (int a = 0; a < Dimension; ++a)
  {
    for (int upper = 0; upper < 2; ++upper)
    {
      Point p = lo;
      p[a] = upper ? lo[a] + side + quarter / 2 : lo[a] - quarter / 2;
      if (p[a] < 0 || p[a] >= Domain[a])
      {
        continue;
      }
      for (int s = 0; s < samples; ++s)
      {
        for (int b = 0, digit = s; b < Dimension; ++b)
        {
          if (b != a)
          {
            p[b] = lo[b] + quarter * (digit % 4) + quarter / 2;
            digit /= 4;
          }
        }
        if (Leaves[static_cast<std::size_t>(locate(p))].level >= key.level + 2)
        {
          return true;
        }
      }
    }
  }
  return false;
}

std::vector<Origin> BlockMesh::adapt(const std::vector<int>& change)
{
  const std::vector<BlockKey> old = Leaves;
  const auto n = static_cast<std::int64_t>(old.size());
  const int children = childrenPerBlock();
  auto wants = [&](std::int64_t b, int direction)
  {
    const int c = change[static_cast<std::size_t>(b)];
    return direction > 0 ? c > 0 && old[static_cast<std::size_t>(b)].level < MaxLevel : c < 0;
  };
  // Whether blocks b .. b + 2^d - 1 are one family of siblings, all asking to coarsen.
  auto coarsenable = [&](std::int64_t b)
  {
    const BlockKey& first = old[static_cast<std::size_t>(b)];
    if (first.level == 0 || b + children > n)
    {
      return false;
    }
    for (int c = 0; c < children; ++c)
    {
      const BlockKey& sibling = old[static_cast<std::size_t>(b + c)];
      const BlockKey expected = childOf(parentOf(first, Dimension), c, Dimension);
      if (sibling.tree != first.tree || sibling.level != first.level || sibling.at != expected.at ||
          !wants(b + c, -1))
      {
        return false;
      }
    }
    return true;
  };

  std::vector<std::pair<BlockKey, Origin>> blocks;
  for (std::int64_t b = 0; b < n;)
  {
    const BlockKey& key = old[static_cast<std::size_t>(b)];
    if (coarsenable(b))
    {
      blocks.push_back({parentOf(key, Dimension), {Origin::Kind::Covers, b}});
      b += children;
      continue;
    }
    if (wants(b, +1))
    {
      for (int c = 0; c < children; ++c)
      {
        blocks.push_back({childOf(key, c, Dimension), {Origin::Kind::Inside, b}});
      }
    }
    else
    {
      blocks.push_back({key, {Origin::Kind::Inside, b}});
    }
    ++b;
  }

  // 2:1 balance: refine (or do not coarsen) blocks with a face neighbour two levels finer.
  for (;;)
  {
    Leaves.clear();
    for (const auto& [key, origin] : blocks)
    {
      Leaves.push_back(key);
    }
    index();
    std::vector<std::pair<BlockKey, Origin>> balanced;
    bool changed = false;
    for (const auto& [key, origin] : blocks)
    {
      if (!unbalanced(key))
      {
        balanced.push_back({key, origin});
        continue;
      }
      changed = true;
      for (int c = 0; c < children; ++c)
      {
        if (origin.kind == Origin::Kind::Covers)
        {
          balanced.push_back({old[static_cast<std::size_t>(origin.block + c)],
                              {Origin::Kind::Inside, origin.block + c}});
        }
        else
        {
          balanced.push_back({childOf(key, c, Dimension), origin});
        }
      }
    }
    if (!changed)
    {
      break;
    }
    blocks = std::move(balanced);
  }
  std::vector<Origin> origins;
  for (const auto& block : blocks)
  {
    origins.push_back(block.second);
  }
  return origins;
}

} // namespace blocks
