#include "ContourGhosts.h"

#include "DualTraversal.h"
#include "LeafGradient.h"

#include <vtkDataArray.h>

#include <stdexcept>
#include <string>

namespace canopy
{

namespace
{

/// The visible leaves sharing a vertex with another rank's part: the cells of
/// the full-resolution dual with a leaf and such a part. Only the groups that
/// hold another rank's part, or a node with absent descendants, are descended.
struct BorderLeaves
{
  std::vector<std::vector<unsigned char>>& marked;
  std::vector<DualNode>& found;
  const HyperTreeAccess& grid;
  unsigned corners;

  bool enter(const DualGroup& group, unsigned axes)
  {
    for (unsigned s = 0; s < corners; ++s)
    {
      if ((s & ~axes) != 0)
      {
        continue; // not a slot of this group (no node)
      }
      const DualNode& n = *group[s];
      if ((n.kind == DualNode::Hidden && n.remote) ||
          (n.kind == DualNode::Inner && n.tree->hasAbsentDescendant(n.node)))
      {
        return true;
      }
    }
    return false;
  }

  void cell(const DualGroup& group)
  {
    bool other = false;
    for (unsigned s = 0; s < corners && !other; ++s)
    {
      other = group[s]->kind == DualNode::Hidden && group[s]->remote;
    }
    if (!other)
    {
      return;
    }
    for (unsigned s = 0; s < corners; ++s)
    {
      mark(*group[s]);
    }
  }

  void mark(const DualNode& n)
  {
    if (n.kind != DualNode::Leaf || n.remote)
    {
      return;
    }
    auto& flags = marked[static_cast<std::size_t>(n.tree - grid.trees().data())];
    if (flags.empty())
    {
      flags.assign(static_cast<std::size_t>(n.tree->numberOfVertices), 0);
    }
    unsigned char& flag = flags[static_cast<std::size_t>(n.node)];
    if (!flag)
    {
      flag = 1;
      found.push_back(n);
    }
  }
};

} // namespace

std::vector<double> ContourGhosts::collect(const HyperTreeAccess& grid, const ContourField& field,
                                           const std::vector<vtkDataArray*>& interpolated,
                                           int maximumLevel, const ViewOptions& view)
{
  std::vector<double> records;
  if (!grid.hasAbsent() && !grid.hasTreesElsewhere())
  {
    return records;
  }
  // The contour's forest (its maximum level, its level of detail), no ghosts.
  const DualTraversal dual(grid, maximumLevel, view.view, view.levelOfDetail, view.pixelThreshold);
  std::vector<std::vector<unsigned char>> marked(grid.trees().size());
  std::vector<DualNode> leaves;
  BorderLeaves border{marked, leaves, grid, 1u << dual.dimension()};
  for (vtkIdType task = 0; task < dual.numberOfTasks(); ++task)
  {
    dual.runTask(task, border);
  }
  // Their face neighbours: what their boundary gradients are fitted to.
  const LeafGradient gradient(grid, dual, field);
  const std::size_t first = leaves.size();
  for (std::size_t l = 0; l < first; ++l)
  {
    const DualNode leaf = leaves[l];
    for (int i = 0; i < dual.dimension(); ++i)
    {
      for (int side = 0; side < 4; ++side)
      {
        border.mark(gradient.across(leaf, i, side & 1, side & 2));
      }
    }
  }
  // Each of them with its ancestors, each node once, parents before children.
  std::vector<std::vector<unsigned char>> sent(grid.trees().size());
  auto record =
      [&](const TreeAccess& tree, vtkIdType node, int level, const std::array<std::int64_t, 3>& ijk)
  {
    auto& flags = sent[static_cast<std::size_t>(&tree - grid.trees().data())];
    if (flags.empty())
    {
      flags.assign(static_cast<std::size_t>(tree.numberOfVertices), 0);
    }
    if (flags[static_cast<std::size_t>(node)])
    {
      return;
    }
    flags[static_cast<std::size_t>(node)] = 1;
    const auto& roots = grid.rootCells();
    const vtkIdType global = tree.globalIndex(node);
    records.push_back(static_cast<double>(
        (static_cast<std::int64_t>(tree.rootIJK[2]) * roots[1] + tree.rootIJK[1]) * roots[0] +
        tree.rootIJK[0]));
    records.push_back(level);
    records.insert(records.end(), {static_cast<double>(ijk[0]), static_cast<double>(ijk[1]),
                                   static_cast<double>(ijk[2])});
    records.push_back(tree.isLeaf(node) ? 1 : (tree.hasAbsentDescendant(node) ? 2 : 0));
    records.push_back(field(global));
    for (vtkDataArray* array : interpolated)
    {
      for (int c = 0; c < array->GetNumberOfComponents(); ++c)
      {
        records.push_back(array->GetComponent(global, c));
      }
    }
  };
  for (const DualNode& leaf : leaves)
  {
    const TreeAccess& tree = *leaf.tree;
    vtkIdType node = 0;
    std::array<std::int64_t, 3> ijk{{0, 0, 0}};
    for (int level = 0; level < leaf.level; ++level)
    {
      record(tree, node, level, ijk);
      const int c = grid.childToward(level, leaf.level, leaf.ijk);
      node = tree.firstChild(node) + c;
      ijk = grid.childPosition(ijk, c);
    }
    record(tree, leaf.node, leaf.level, leaf.ijk);
  }
  return records;
}

ContourGhosts::ContourGhosts(const HyperTreeAccess& grid,
                             const std::vector<std::vector<double>>& records, int self,
                             const std::vector<int>& components)
    : Grid(grid), Components(components), Fields(components.size())
{
  std::size_t width = RecordHeader + 1;
  for (int c : components)
  {
    width += static_cast<std::size_t>(c);
  }
  const auto& roots = grid.rootCells();
  const std::int64_t rootCount = static_cast<std::int64_t>(roots[0]) * roots[1] * roots[2];
  for (std::size_t rank = 0; rank < records.size(); ++rank)
  {
    const std::vector<double>& from = records[rank];
    if (from.size() % width != 0)
    {
      throw std::invalid_argument("rank " + std::to_string(rank) + " sent " +
                                  std::to_string(from.size()) + " numbers, not whole records of " +
                                  std::to_string(width));
    }
    if (static_cast<int>(rank) == self)
    {
      continue;
    }
    Received += from.size() * sizeof(double);
    for (std::size_t at = 0; at < from.size(); at += width)
    {
      const double* r = &from[at];
      const std::int64_t root = static_cast<std::int64_t>(r[0]);
      const int level = static_cast<int>(r[1]);
      if (root < 0 || root >= rootCount || level < 0 || level > grid.maxLevel())
      {
        throw std::invalid_argument("rank " + std::to_string(rank) + " sent a node of root cell " +
                                    std::to_string(root) + " at level " + std::to_string(level) +
                                    ", outside this grid");
      }
      const Key key{root,
                    level,
                    {{static_cast<std::int64_t>(r[2]), static_cast<std::int64_t>(r[3]),
                      static_cast<std::int64_t>(r[4])}}};
      const std::int64_t ghost = static_cast<std::int64_t>(Leaf.size());
      if (!Index.emplace(key, ghost).second)
      {
        continue; // an ancestor two ranks share
      }
      Leaf.push_back(static_cast<unsigned char>(r[5]));
      Values.push_back(r[6]);
      std::size_t offset = RecordHeader + 1;
      for (std::size_t f = 0; f < components.size(); ++f)
      {
        Fields[f].insert(Fields[f].end(), r + offset, r + offset + components[f]);
        offset += static_cast<std::size_t>(components[f]);
      }
      // A tree on another rank: a stand-in for its geometry.
      const std::array<unsigned int, 3> ijk{
          {static_cast<unsigned int>(root % roots[0]),
           static_cast<unsigned int>(root / roots[0] % roots[1]),
           static_cast<unsigned int>(root / roots[0] / roots[1])}};
      if (level == 0 && !grid.treeAt(ijk[0], ijk[1], ijk[2]) && !Elsewhere.count(root))
      {
        TreeAccess stand;
        stand.rootIJK = ijk;
        for (std::size_t a = 0; a < 3; ++a)
        {
          const std::vector<double>& x = grid.coordinates(static_cast<int>(a));
          const bool active = x.size() > 1; // a flat axis has one coordinate
          stand.origin[a] = active ? x[ijk[a]] : x[0];
          stand.size[a] = active ? x[ijk[a] + 1] - x[ijk[a]] : 0;
        }
        Elsewhere.emplace(root, Stand.size());
        Stand.push_back(std::move(stand));
      }
    }
  }
}

} // namespace canopy
