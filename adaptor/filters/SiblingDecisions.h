// A walk's yes-or-no decision per node (does level of detail stop here?),
// kept within one tree for a few blocks of siblings per level.
//
// The edge queries (EdgeVertices.h) ask the drawing walk's rule at the nodes
// across a drawn piece's edges; most of those are the drawn node's siblings or
// its neighbours' children, which the walk decides about too, just before or
// after, and which several drawn nodes ask about. Keeping each decision once,
// for both, keeps them from paying for the same node's projection again. The
// decision is the same function of the node either way, so what the walk
// draws and what the queries find agree.
//
// A tree's children come in blocks: those of one node are elderChild ..
// elderChild + N - 1, and VTK's trees allocate the blocks in order after the
// root, so block b holds nodes 1 + b N .. b N + N. A node whose position says
// otherwise (its child digits) is decided without being kept.
#pragma once

#include "HyperTreeAccess.h"
#include "TreeTraversal.h"

#include <array>
#include <cstdint>
#include <vector>

namespace canopy
{

class SiblingDecisions
{
public:
  /// `maxLevel`: the deepest level whose decisions are kept (a walk allocates
  /// one per tree: the tree's own depth, not every level a grid can address).
  explicit SiblingDecisions(int maxLevel) : Levels(static_cast<std::size_t>(maxLevel) + 1) {}

  /// decide(m) for `m` of `tree` (the walk's own tree), kept with its block
  /// (decided without being kept below maxLevel).
  template <typename Decide>
  bool get(const HyperTreeAccess& grid, const WalkNode& m, Decide&& decide)
  {
    const int children = grid.childrenPerNode();
    if (m.level == 0 || m.node < 1 || static_cast<std::size_t>(m.level) >= Levels.size())
    {
      return decide(m);
    }
    const int f = grid.branchFactor();
    const vtkIdType block = (m.node - 1) / children;
    const int digit = static_cast<int>((m.node - 1) - block * children);
    // The child digit the position gives must be the one the block gives.
    int fromPosition = 0;
    int weight = 1;
    for (int a : grid.activeAxes())
    {
      const std::int64_t p = m.ijk[static_cast<std::size_t>(a)];
      fromPosition += static_cast<int>(f == 2 ? p & 1 : p % f) * weight;
      weight *= f;
    }
    if (fromPosition != digit)
    {
      return decide(m);
    }
    Set& set = Levels[static_cast<std::size_t>(m.level)];
    Entry* entry = nullptr;
    for (Entry& e : set.entries)
    {
      if (e.block == block)
      {
        entry = &e;
        break;
      }
    }
    if (!entry)
    {
      entry = &set.entries[set.next++ % Ways];
      *entry = Entry{block, 0, 0};
    }
    const std::uint32_t bit = 1u << digit;
    if (!(entry->known & bit))
    {
      entry->known |= bit;
      if (decide(m))
      {
        entry->stops |= bit;
      }
    }
    return (entry->stops & bit) != 0;
  }

private:
  static constexpr unsigned Ways = 8;
  struct Entry
  {
    vtkIdType block = -1;
    std::uint32_t known = 0; ///< bit c: child c decided (at most 27 children)
    std::uint32_t stops = 0; ///< bit c: child c's decision
  };
  struct Set
  {
    std::array<Entry, Ways> entries{};
    unsigned next = 0;
  };
  std::vector<Set> Levels;
};

} // namespace canopy
