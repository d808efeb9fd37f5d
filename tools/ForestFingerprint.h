// A fingerprint of a forest description, printed by the benchmarks with every
// table, so that a published figure can be traced to the exact input it was
// measured on (docs/benchmarks.md): two runs on the same input print the same
// fingerprint, a different refinement, mask or field value a different one.
#pragma once

#include <canopy/ForestDescription.h>

#include <cstdint>
#include <string>

namespace canopy::tools
{

/// 64-bit fingerprint of `forest` (borrowed for the call): its shape and root
/// coordinates, every tree's arrays (refinement, mask, absent, slots, block
/// indices) and every field's name and values, read in whatever layout it has.
std::uint64_t forestFingerprint(const ForestDescription& forest);

/// "input <label>: <trees> trees, <nodes> nodes, fingerprint <16 hex digits>".
std::string describeInput(const std::string& label, const ForestDescription& forest);

} // namespace canopy::tools
