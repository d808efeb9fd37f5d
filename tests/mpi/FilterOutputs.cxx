// Writes what Canopy's filters make of fixed inputs, for the determinism check
// (tests/mpi/filter_outputs_check.py): the same input, camera and options must
// give the same bytes on every run, whatever the number of threads, and the
// same cells on every number of ranks.
//
//   mpirun -np N canopy_filter_outputs OUTPUT_DIR
//
// Every rank holds its part of the same random forests as p4est would split
// them (RankPart: trees cut between ranks, the other ranks' parts absent) and
// writes, per case:
//   <case>.rank<r>.bytes   its output as it is (points, cells, cell arrays, mask
//                          bits, in the filter's order): compared between runs
//   <case>.cells           (rank 0) every rank's cells, each as one line (its
//                          global id, level and points to the last bit), sorted:
//                          compared between rank counts
// Level of detail is in the byte comparison only: by design it never draws a
// node part of which is another rank's (docs/filters.md), so the cells it draws
// depend on how the trees are split.
#include "RandomForest.h"
#include "RankPart.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSlice.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <vtkBitArray.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkMPIController.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace
{

using namespace canopy;
using namespace canopy::testing;

void appendBytes(std::string& out, const void* data, std::size_t size)
{
  out.append(static_cast<const char*>(data), size);
}

void appendArray(std::string& out, vtkDataArray* array)
{
  if (array == nullptr)
  {
    return;
  }
  out += std::string(array->GetName() ? array->GetName() : "") + "\n";
  appendBytes(out, array->GetVoidPointer(0),
              static_cast<std::size_t>(array->GetNumberOfValues() * array->GetDataTypeSize()));
}

void appendCells(std::string& out, vtkCellArray* cells)
{
  appendArray(out, cells->GetOffsetsArray());
  appendArray(out, cells->GetConnectivityArray());
}

void appendCellData(std::string& out, vtkDataSet* data)
{
  for (int a = 0; a < data->GetCellData()->GetNumberOfArrays(); ++a)
  {
    appendArray(out, data->GetCellData()->GetArray(a));
  }
}

/// The output as it is, for the run-to-run comparison.
std::string bytesOf(vtkDataObject* output)
{
  std::string out;
  if (auto* poly = vtkPolyData::SafeDownCast(output))
  {
    appendArray(out, poly->GetPoints() ? poly->GetPoints()->GetData() : nullptr);
    appendCells(out, poly->GetPolys());
    appendCells(out, poly->GetLines());
    appendCellData(out, poly);
  }
  else if (auto* grid = vtkUnstructuredGrid::SafeDownCast(output))
  {
    appendArray(out, grid->GetPoints() ? grid->GetPoints()->GetData() : nullptr);
    appendCells(out, grid->GetCells());
    appendArray(out, grid->GetCellTypesArray());
    appendCellData(out, grid);
  }
  else if (auto* htg = vtkHyperTreeGrid::SafeDownCast(output))
  {
    vtkBitArray* mask = htg->GetMask();
    for (vtkIdType i = 0; mask && i < mask->GetNumberOfValues(); ++i)
    {
      out += mask->GetValue(i) ? '1' : '0';
    }
  }
  return out;
}

/// One line per cell: the whole forest's node it shows (its "node" value: cell
/// ids are each rank's own), its level, its points (hexadecimal floats: every bit).
std::vector<std::string> cellLines(vtkDataObject* output)
{
  std::vector<std::string> lines;
  auto* data = vtkDataSet::SafeDownCast(output);
  vtkDataArray* nodes = data ? data->GetCellData()->GetArray("node") : nullptr;
  vtkDataArray* levels = data ? data->GetCellData()->GetArray("Level") : nullptr;
  for (vtkIdType c = 0; data && nodes && levels && c < data->GetNumberOfCells(); ++c)
  {
    std::ostringstream line;
    char node[64];
    std::snprintf(node, sizeof node, "%a", nodes->GetTuple1(c));
    line << node << " " << levels->GetTuple1(c);
    vtkIdList* points = data->GetCell(c)->GetPointIds();
    for (vtkIdType p = 0; p < points->GetNumberOfIds(); ++p)
    {
      double x[3];
      data->GetPoint(points->GetId(p), x);
      char text[96];
      std::snprintf(text, sizeof text, " %a %a %a", x[0], x[1], x[2]);
      line << text;
    }
    lines.push_back(line.str());
  }
  return lines;
}

/// Rank 0 gets every rank's lines.
std::vector<std::string> gatherLines(const std::vector<std::string>& mine)
{
  std::string joined;
  for (const std::string& line : mine)
  {
    joined += line + "\n";
  }
  int size = 0;
  int rank = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  int length = static_cast<int>(joined.size());
  std::vector<int> lengths(static_cast<std::size_t>(size));
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<int> offsets(static_cast<std::size_t>(size), 0);
  for (int r = 1; r < size; ++r)
  {
    offsets[static_cast<std::size_t>(r)] =
        offsets[static_cast<std::size_t>(r - 1)] + lengths[static_cast<std::size_t>(r - 1)];
  }
  std::string all(rank == 0 ? static_cast<std::size_t>(offsets.back() + lengths.back()) : 0, ' ');
  MPI_Gatherv(joined.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR,
              0, MPI_COMM_WORLD);
  std::vector<std::string> lines;
  std::istringstream in(all);
  for (std::string line; std::getline(in, line);)
  {
    lines.push_back(line);
  }
  return lines;
}

/// A random forest with every-node fields "node" and "hash", split as p4est would.
struct Case
{
  RandomForest whole;
  std::vector<std::unique_ptr<RankPart>> keep;
  vtkSmartPointer<vtkHyperTreeGrid> grid;

  Case(const RandomForestOptions& options, int rank, int ranks) : whole(options)
  {
    keep.push_back(std::make_unique<RankPart>(whole.description(), rank, ranks, rank % 2 == 1));
    grid = buildHyperTreeGrid(keep.back()->description);
  }
};

RandomForestOptions forest(int dimension, std::uint64_t seed, double masked)
{
  RandomForestOptions o;
  o.dimension = dimension;
  o.rootCells = dimension == 2 ? std::array<std::size_t, 3>{{5, 4, 1}}
                               : std::array<std::size_t, 3>{{3, 3, 2}};
  o.maxLevels = dimension == 2 ? 7 : 5;
  o.refineProbability = 0.5;
  o.maskProbability = masked;
  o.seed = seed;
  return o;
}

/// A perspective camera looking at `center` from `eye`, 800 x 600 pixels.
template <typename Filter>
void view(Filter* filter, const std::array<double, 3>& eye, const std::array<double, 3>& center,
          bool lod)
{
  filter->SetCameraPosition(eye.data());
  filter->SetCameraFocalPoint(center.data());
  filter->SetCameraViewUp(0, 1, 0);
  filter->SetViewAngle(30);
  filter->SetViewportSize(800, 600);
  filter->SetLevelOfDetail(lod);
  filter->SetPixelThreshold(1.0);
}

} // namespace

int main(int argc, char** argv)
{
  vtkNew<vtkMPIController> controller;
  controller->Initialize(&argc, &argv);
  vtkMultiProcessController::SetGlobalController(controller);
  const int rank = controller->GetLocalProcessId();
  const int ranks = controller->GetNumberOfProcesses();
  if (argc < 2)
  {
    std::cerr << "usage: canopy_filter_outputs OUTPUT_DIR\n";
    MPI_Abort(MPI_COMM_WORLD, 2);
  }
  const std::string folder = argv[1];
  auto write = [&](const std::string& name, vtkDataObject* output, bool compareRanks)
  {
    std::ofstream(folder + "/" + name + ".rank" + std::to_string(rank) + ".bytes", std::ios::binary)
        << bytesOf(output);
    if (compareRanks)
    {
      std::vector<std::string> lines = gatherLines(cellLines(output));
      std::sort(lines.begin(), lines.end());
      if (rank == 0)
      {
        std::ofstream cells(folder + "/" + name + ".cells");
        for (const std::string& line : lines)
        {
          cells << line << "\n";
        }
      }
    }
  };

  for (double masked : {0.0, 0.15})
  {
    const std::string suffix = masked > 0 ? "_masked" : "";
    Case flat(forest(2, 11, masked), rank, ranks);
    for (bool lod : {false, true})
    {
      vtkNew<vtkCanopyAdaptiveSurface> surface;
      surface->SetInputData(flat.grid);
      surface->AddField("node");
      view(surface.Get(), {{2.1, 1.7, lod ? 30.0 : 6.0}}, {{2.3, 1.9, 0}}, lod);
      surface->Update();
      write("surface2d" + suffix + (lod ? "_lod" : "_culled"), surface->GetOutput(), !lod);
    }
    Case solid(forest(3, 5, masked), rank, ranks);
    for (bool lod : {false, true})
    {
      vtkNew<vtkCanopyAdaptiveSurface> surface;
      surface->SetInputData(solid.grid);
      surface->AddField("node");
      view(surface.Get(), {{8.0, 6.5, lod ? 30.0 : 9.0}}, {{1.4, 1.4, 1.0}}, lod);
      surface->Update();
      write("surface3d" + suffix + (lod ? "_lod" : "_culled"), surface->GetOutput(), !lod);

      vtkNew<vtkCanopyAdaptiveSlice> slice;
      slice->SetInputData(solid.grid);
      slice->AddField("node");
      slice->AddXPlane(1.3);
      slice->AddYPlane(0.7);
      slice->AddZPlane(1.1);
      view(slice.Get(), {{8.0, 6.5, lod ? 30.0 : 9.0}}, {{1.4, 1.4, 1.0}}, lod);
      slice->Update();
      write("slice3d" + suffix + (lod ? "_lod" : "_full"), slice->GetOutput(), !lod);
    }
    for (const char* field : {"node", "hash"})
    {
      vtkNew<vtkCanopyExtractSelection> byValue;
      byValue->SetInputData(solid.grid);
      byValue->SetSelectionMode(vtkCanopyExtractSelection::VALUE_RANGE);
      byValue->SetValueArrayName(field);
      byValue->SetValueRange(std::string(field) == "hash" ? 0.2 : wholeValue(2, 3),
                             std::string(field) == "hash" ? 0.7 : wholeValue(9, 10));
      byValue->SetPreserveTopology(false);
      byValue->Update();
      write(std::string("selection_cells_") + field + suffix, byValue->GetOutput(), true);
      byValue->SetPreserveTopology(true);
      byValue->Update();
      write(std::string("selection_mask_") + field + suffix, byValue->GetOutput(), false);
      vtkNew<vtkCanopyExtractSelection> cut;
      cut->SetInputConnection(byValue->GetOutputPort());
      cut->SetSelectionMode(vtkCanopyExtractSelection::BOX);
      cut->SetBox(1.5, 9, 1.5, 9, 1.0, 9);
      cut->InvertOn();
      cut->PreserveTopologyOn();
      vtkNew<vtkCanopyAdaptiveSurface> region;
      region->SetInputConnection(cut->GetOutputPort());
      region->ViewDependentOff();
      region->AddField("node");
      region->Update();
      write(std::string("region3d_") + field + suffix, region->GetOutput(), false);
    }
  }
  vtkMultiProcessController::SetGlobalController(nullptr);
  controller->Finalize();
  return 0;
}
