// A whole forest written as JSON for the extract checkers: per tree its root,
// the rank that owns it, its breadth-first refinement and mask ("0"/"1" per
// node), the root grid, and every field's values at sampled cells, coarse
// values of leaves-only fields included (computed here the way Canopy
// documents them: the mean of the unmasked children, of all if every child is
// masked). The checkers compare what a file holds with this.
#pragma once

#include <canopy/ForestDescription.h>

#include <ostream>
#include <string>
#include <vector>

namespace canopy::testing
{

/// The opening of a forest's JSON, up to and including its root grid:
/// {"step": .., "time": .., "ranks": .., "dimension": .., "branch_factor": ..,
/// "coordinates": [[x...], [y...], [z...]] (the caller goes on with ", ...").
void writeForestJsonHeader(std::ostream& json, const ForestDescription& whole, int step,
                           double time, int ranks);

/// `owners[t]`: the rank that writes tree t (-1: several ranks). About
/// `samples` cells are sampled, spread over the forest, coarse and leaves.
std::string forestJson(const ForestDescription& whole, const std::vector<int>& owners, int step,
                       double time, int ranks, int samples = 24);

} // namespace canopy::testing
