#include "AmrForest.h"

#include <cmath>
#include <deque>
#include <stdexcept>

namespace miniamr
{

AmrForest::AmrForest(int dimension, int branchFactor, std::array<int, 3> roots, int maxLevel)
    : Dimension(dimension), BranchFactor(branchFactor),
      Children(dimension == 2 ? branchFactor * branchFactor
                              : branchFactor * branchFactor * branchFactor),
      Roots(roots), MaxLevel(maxLevel)
{
  if (Dimension == 2)
  {
    Roots[2] = 1;
  }
  for (int k = 0; k < Roots[2]; ++k)
    for (int j = 0; j < Roots[1]; ++j)
      for (int i = 0; i < Roots[0]; ++i)
      {
        Tree tree;
        tree.rootIndex = i + static_cast<std::int64_t>(Roots[0]) * (j + Roots[1] * k);
        Tree::Node root;
        root.key = {0, {{i, j, k}}};
        tree.nodes.push_back(root);
        finish(tree);
        Trees.push_back(std::move(tree));
      }
  index();
}

std::int64_t AmrForest::totalLeaves() const
{
  std::int64_t leaves = 0;
  for (const auto& tree : Trees)
    leaves += tree.leafCount;
  return leaves;
}

std::int64_t AmrForest::totalNodes() const
{
  std::int64_t nodes = 0;
  for (const auto& tree : Trees)
    nodes += static_cast<std::int64_t>(tree.nodes.size());
  return nodes;
}

std::int64_t AmrForest::cellsAcross(int axis, int level) const
{
  if (axis >= Dimension)
    return 1;
  std::int64_t cells = Roots[axis];
  for (int l = 0; l < level; ++l)
    cells *= BranchFactor;
  return cells;
}

double AmrForest::cellSize(int axis, int level) const
{
  return 1.0 / static_cast<double>(cellsAcross(axis, level));
}

double AmrForest::cellVolume(int level) const
{
  double volume = 1.0;
  for (int a = 0; a < Dimension; ++a)
    volume *= cellSize(a, level);
  return volume;
}

std::array<double, 3> AmrForest::cellLow(const NodeKey& key) const
{
  std::array<double, 3> low{{0, 0, 0}};
  for (int a = 0; a < Dimension; ++a)
    low[a] = static_cast<double>(key.position[a]) * cellSize(a, key.level);
  return low;
}

std::array<double, 3> AmrForest::cellCenter(const NodeKey& key) const
{
  auto center = cellLow(key);
  for (int a = 0; a < Dimension; ++a)
    center[a] += 0.5 * cellSize(a, key.level);
  return center;
}

const Tree::Node* AmrForest::find(const NodeKey& key, NodeRef* where) const
{
  const auto found = Index.find(key);
  if (found == Index.end())
    return nullptr;
  if (where)
    *where = found->second;
  return &Trees[static_cast<std::size_t>(found->second.tree)]
              .nodes[static_cast<std::size_t>(found->second.node)];
}

void AmrForest::faceNeighbours(const NodeKey& key, int axis, int side,
                               std::vector<FaceNeighbour>& out) const
{
  out.clear();
  NodeKey across = key;
  const std::int64_t extent = cellsAcross(axis, key.level);
  across.position[axis] = (across.position[axis] + side + extent) % extent; // periodic
  NodeRef where;
  const Tree::Node* node = find(across, &where);
  // Not there at this level: the leaf across is coarser. Climb until found.
  while (node == nullptr)
  {
    if (across.level == 0)
      throw std::logic_error("faceNeighbours: no root across a face");
    across.level -= 1;
    for (int a = 0; a < Dimension; ++a)
      across.position[a] /= BranchFactor;
    node = find(across, &where);
  }
  if (node->firstChild < 0)
  {
    // Same level or coarser: one face, measured on this (finer or equal) cell.
    FaceNeighbour neighbour;
    neighbour.leaf = where;
    neighbour.node = node;
    neighbour.finer = key;
    neighbour.finerSide = side;
    out.push_back(neighbour);
  }
  else
  {
    // Finer: every leaf of the subtree touching the face, depth first in child order.
    const int touching = side > 0 ? 0 : BranchFactor - 1;
    std::vector<NodeRef> stack{where};
    while (!stack.empty())
    {
      const NodeRef current = stack.back();
      stack.pop_back();
      const auto& tree = Trees[static_cast<std::size_t>(current.tree)];
      const auto& n = tree.nodes[static_cast<std::size_t>(current.node)];
      if (n.firstChild < 0)
      {
        FaceNeighbour neighbour;
        neighbour.leaf = current;
        neighbour.node = &n;
        neighbour.finer = n.key;
        neighbour.finerSide = -side;
        out.push_back(neighbour);
        continue;
      }
      for (int c = Children - 1; c >= 0; --c)
      {
        const auto& child = tree.nodes[static_cast<std::size_t>(n.firstChild + c)];
        if (child.key.position[axis] % BranchFactor == touching)
          stack.push_back({current.tree, n.firstChild + c});
      }
    }
  }
  for (auto& neighbour : out)
  {
    double area = 1.0;
    for (int a = 0; a < Dimension; ++a)
      if (a != axis)
        area *= cellSize(a, neighbour.finer.level);
    neighbour.area = area;
  }
}

std::array<double, 3> AmrForest::faceCenter(const FaceNeighbour& neighbour, int axis) const
{
  auto center = cellCenter(neighbour.finer);
  const std::int64_t extent = cellsAcross(axis, neighbour.finer.level);
  const std::int64_t face =
      (neighbour.finer.position[axis] + (neighbour.finerSide > 0 ? 1 : 0)) % extent;
  center[axis] = static_cast<double>(face) / static_cast<double>(extent);
  return center;
}

void AmrForest::finish(Tree& tree) const
{
  tree.refinement.resize(tree.nodes.size());
  tree.leafCount = 0;
  for (std::size_t n = 0; n < tree.nodes.size(); ++n)
  {
    auto& node = tree.nodes[n];
    tree.refinement[n] = node.firstChild >= 0 ? 1 : 0;
    node.leaf = node.firstChild >= 0 ? -1 : tree.leafCount++;
  }
}

Tree AmrForest::rebuild(const Tree& old, const std::vector<std::int8_t>& wishes)
{
  // Walk the old tree breadth-first, emitting the new tree breadth-first.
  Tree tree;
  tree.rootIndex = old.rootIndex;
  Origins.clear();
  struct Pending
  {
    NodeKey key;
    std::int32_t oldNode; ///< -1: a new child of a refined old leaf
    std::int32_t oldLeaf; ///< for new children: the old leaf refined
  };
  std::deque<Pending> queue{{old.nodes[0].key, 0, -1}};
  auto childKey = [this](const NodeKey& parent, int c)
  {
    NodeKey key{parent.level + 1, {{0, 0, 0}}};
    int rest = c;
    for (int a = 0; a < 3; ++a)
    {
      const int digit = a < Dimension ? rest % BranchFactor : 0;
      if (a < Dimension)
        rest /= BranchFactor;
      key.position[a] = parent.position[a] * (a < Dimension ? BranchFactor : 1) + digit;
    }
    return key;
  };
  while (!queue.empty())
  {
    const Pending item = queue.front();
    queue.pop_front();
    Tree::Node node;
    node.key = item.key;
    LeafOrigin origin;
    bool refine = false;
    if (item.oldNode < 0)
    {
      origin.oldLeaf = item.oldLeaf; // a child of a refined leaf: a leaf
    }
    else
    {
      const auto& oldNode = old.nodes[static_cast<std::size_t>(item.oldNode)];
      if (oldNode.firstChild < 0)
      {
        const int wish = wishes[static_cast<std::size_t>(oldNode.leaf)];
        refine = wish > 0 && node.key.level < MaxLevel;
        origin.oldLeaf = oldNode.leaf;
        if (refine)
        {
          for (int c = 0; c < Children; ++c)
            queue.push_back({childKey(node.key, c), -1, oldNode.leaf});
        }
      }
      else
      {
        bool coarsen = true;
        for (int c = 0; c < Children && coarsen; ++c)
        {
          const auto& child = old.nodes[static_cast<std::size_t>(oldNode.firstChild + c)];
          coarsen = child.firstChild < 0 && wishes[static_cast<std::size_t>(child.leaf)] < 0;
        }
        if (coarsen)
        {
          for (int c = 0; c < Children; ++c)
            origin.oldChildren.push_back(
                old.nodes[static_cast<std::size_t>(oldNode.firstChild + c)].leaf);
        }
        else
        {
          refine = true;
          for (int c = 0; c < Children; ++c)
            queue.push_back({old.nodes[static_cast<std::size_t>(oldNode.firstChild + c)].key,
                             oldNode.firstChild + c, -1});
        }
      }
    }
    if (refine)
    {
      // Children are appended to the queue in order; their breadth-first index is
      // the number of nodes emitted so far plus those already queued before them.
      node.firstChild = static_cast<std::int32_t>(tree.nodes.size() + queue.size()) - Children + 1;
    }
    else
    {
      Origins.push_back(origin);
    }
    tree.nodes.push_back(node);
  }
  finish(tree);
  return tree;
}

void AmrForest::index()
{
  Index.clear();
  for (std::size_t t = 0; t < Trees.size(); ++t)
    for (std::size_t n = 0; n < Trees[t].nodes.size(); ++n)
      Index.emplace(Trees[t].nodes[n].key,
                    NodeRef{static_cast<std::int32_t>(t), static_cast<std::int32_t>(n)});
}

} // namespace miniamr
