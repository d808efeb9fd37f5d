// Builds the vtkHyperTreeGrid of a simulation's forest step after step, doing
// again only what changed since the previous build.
//
//   canopy::GridBuilder builder;                  // one per simulation run
//   for (each output step)
//     vtkHyperTreeGrid* grid = builder.build(describe(state), request);
//
// Each tree's topology is fingerprinted (64-bit hashes, one pass over its bytes,
// far cheaper than building it), unless the simulation's own revision
// (ForestDescription::revision) says nothing changed: a tree whose root and
// refinement did not change keeps its vtkHyperTree, a changed one is rebuilt;
// when nothing changed (masks, absent parts and slot maps included) the mask and
// the tables fields read through are kept as well. What changed is written into
// the grid (its topology stamp, TopologyStamp.h), which the filters' memos read:
// the one place that decides it. Fields are wrapped anew at every build (the simulation
// may have moved them; leaves-only fields get their coarse averages again), except
// a field whose values the simulation vouches for (FieldDescription::valuesRevision):
// its array object is kept, unmodified, while the topology and its description hold.
// The same vtkHyperTreeGrid object is returned while the root grid's shape and
// the set of trees stay the same, marked Modified() at every build so that
// pipelines downstream run again; a new one otherwise. A grid shallow-copied
// from an earlier build keeps that build's trees and arrays.
#pragma once

#include <canopy/HtgBuilder.h>

#include <vtkSmartPointer.h>

#include <cstddef>
#include <memory>

class vtkHyperTreeGrid;

namespace canopy
{

class GridBuilder
{
public:
  GridBuilder();
  ~GridBuilder();
  GridBuilder(const GridBuilder&) = delete;
  GridBuilder& operator=(const GridBuilder&) = delete;

  /// Validates `forest` (InvalidForest, nothing changed, when it is malformed)
  /// and returns its grid, reusing what did not change since the last build. The
  /// grid borrows the simulation's memory as buildHyperTreeGrid's does.
  vtkSmartPointer<vtkHyperTreeGrid> build(const ForestDescription& forest,
                                          const FieldRequest& request = FieldRequest::all());

  /// What the last build did.
  struct Reuse
  {
    bool newGrid = false;         ///< a new grid object (first build, or a different shape)
    std::size_t treesRebuilt = 0; ///< trees built from their bytes
    std::size_t treesKept = 0;    ///< trees whose topology was unchanged
    /// ForestDescription::revision vouched for every tree: no tree's bytes were read.
    bool revisionTrusted = false;
    /// Fields whose array was kept from the build before (valuesRevision).
    std::size_t fieldsKept = 0;
  };
  const Reuse& lastBuild() const;

  /// This builder's identity in the topology stamps of the grids it returns.
  std::uint64_t identity() const;

  /// Forgets the previous build: the next one builds everything.
  void reset();

private:
  struct State;
  std::unique_ptr<State> Impl;
};

} // namespace canopy
