// A selected region of a whole random 3D forest, worked out by brute force:
// leaves whose value of a field lies in a range ("node": wholeValue, a blocky
// region of whole trees and node ranges; "hash": wholeHash, scattered cells;
// RankPart.h) and that do not overlap a cut-away box with positive volume; the oracle is the whole
// forest's grid with every other leaf masked (its voxels are the region). And
// the shipped pipelines' chain that draws it: a value range, then the box cut
// away (both vtkCanopyExtractSelection with PreserveTopology), then the surface.
#pragma once

#include "ErrorMessages.h"
#include "HtgWalk.h"
#include "RandomForest.h"
#include "RankPart.h"
#include "VoxelBoundary.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <vtkBitArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include <array>
#include <map>
#include <string>
#include <vector>

namespace canopy::testing
{

/// Positive-volume overlap of two closed boxes (the selection's box rule).
inline bool overlapsBox(const double a[6], const std::array<double, 6>& b)
{
  for (int axis = 0; axis < 3; ++axis)
  {
    if (!(std::max(a[2 * axis], b[2 * axis]) < std::min(a[2 * axis + 1], b[2 * axis + 1])))
    {
      return false;
    }
  }
  return true;
}

struct SelectedRegionCase
{
  RandomForest whole;
  std::string field;          ///< "node" or "hash"
  std::vector<double> values; ///< by slot: wholeValue of each node
  std::vector<double> hashes; ///< by slot: wholeHash of each node
  ForestDescription described;
  vtkSmartPointer<vtkHyperTreeGrid> oracle;
  double range[2];
  std::array<double, 6> cutAway;
  std::size_t selected = 0;
  std::size_t leaves = 0;

  static RandomForestOptions options(std::uint64_t seed)
  {
    RandomForestOptions o;
    o.dimension = 3;
    o.rootCells = {{3, 2, 2}};
    o.maxLevels = 4; // fewer than 1000 nodes per tree: wholeValue stays unique
    o.refineProbability = 0.55;
    o.seed = seed;
    return o;
  }

  SelectedRegionCase(std::uint64_t seed, const std::string& selectBy = "node")
      : whole(options(seed)), field(selectBy)
  {
    values.resize(whole.numberOfNodes());
    hashes.resize(whole.numberOfNodes());
    std::map<vtkIdType, double> valueOfCell;
    for (std::size_t t = 0; t < whole.nodes().size(); ++t)
    {
      for (std::size_t n = 0; n < whole.nodes()[t].size(); ++n)
      {
        const auto slot = static_cast<std::size_t>(whole.nodes()[t][n].slot);
        values[slot] = wholeValue(t, n);
        hashes[slot] = wholeHash(t, n);
        valueOfCell[whole.cellOf(t, n)] = field == "hash" ? hashes[slot] : values[slot];
      }
    }
    described = whole.description();
    described.fields.push_back(FieldDescription::aos("node", values.data(), values.size()));
    described.fields.push_back(FieldDescription::aos("hash", hashes.data(), hashes.size()));
    oracle = buildHyperTreeGrid(described);
    double b[6];
    oracle->GetBounds(b);
    // "node": trees 2..7 partly (their nodes 20 and up, 2 and up), a blocky
    // region; "hash": about half of the cells. The octant at the upper corner cut away.
    range[0] = field == "hash" ? 0.0 : wholeValue(2, 20);
    range[1] = field == "hash" ? 0.5 : wholeValue(7, 2);
    cutAway = {{0.5 * (b[0] + b[1]), b[1], 0.5 * (b[2] + b[3]), b[3], 0.5 * (b[4] + b[5]), b[5]}};
    vtkNew<vtkBitArray> mask;
    mask->SetNumberOfValues(oracle->GetNumberOfCells());
    for (vtkIdType i = 0; i < oracle->GetNumberOfCells(); ++i)
    {
      mask->SetValue(i, 0);
    }
    forEachVisibleLeaf(oracle,
                       [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor)
                       {
                         double bounds[6];
                         cursor->GetBounds(bounds);
                         const vtkIdType global = cursor->GetGlobalNodeIndex();
                         const double v = valueOfCell.at(global);
                         const bool in =
                             v >= range[0] && v <= range[1] && !overlapsBox(bounds, cutAway);
                         mask->SetValue(global, in ? 0 : 1);
                         selected += in;
                         ++leaves;
                       });
    oracle->SetMask(mask);
  }
  SelectedRegionCase(const SelectedRegionCase&) = delete;
  SelectedRegionCase& operator=(const SelectedRegionCase&) = delete;
};

/// The chain of the shipped pipelines on one grid: the value range of `field`,
/// then the box cut away; then the full surface's quads.
inline std::vector<Quad> selectedSurface(vtkHyperTreeGrid* htg, const std::string& field,
                                         const double range[2],
                                         const std::array<double, 6>& cutAway)
{
  vtkNew<vtkCanopyExtractSelection> byValue;
  byValue->SetInputData(htg);
  byValue->SetSelectionMode(vtkCanopyExtractSelection::VALUE_RANGE);
  byValue->SetValueArrayName(field.c_str());
  byValue->SetValueRange(range[0], range[1]);
  byValue->PreserveTopologyOn();
  vtkNew<vtkCanopyExtractSelection> cut;
  cut->SetInputConnection(byValue->GetOutputPort());
  cut->SetSelectionMode(vtkCanopyExtractSelection::BOX);
  cut->SetBox(cutAway.data());
  cut->InvertOn();
  cut->PreserveTopologyOn();
  vtkNew<vtkCanopyAdaptiveSurface> surface;
  surface->SetInputConnection(cut->GetOutputPort());
  surface->ViewDependentOff();
  EXPECT_TRUE(errorsOfUpdate(surface).empty());
  return quadsOf(surface->GetPolyDataOutput());
}

} // namespace canopy::testing
