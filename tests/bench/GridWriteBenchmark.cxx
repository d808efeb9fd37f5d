// Writing a rank's hypertree grid each step: Canopy's VTKHDF writer (one file,
// every step, MPI-IO) against the XML .htg routes on the same grid: Canopy's
// .htg series (the form ParaView 5.11 opens) and VTK 9.2's own
// vtkXMLHyperTreeGridWriter (binary, as ParaView's HTG extractor writes; it
// corrupts vector fields, but writes as many bytes).
//
// The grid: tools/SyntheticForest (3D, 6^3 roots, a spherical front), trees
// dealt round robin to the ranks; each rank keeps its trees' values in its own
// breadth-first arrays, as a distributed simulation does (density, a velocity
// vector, an int32 level: every node; pressure: leaves only, restricted by
// Canopy). Prints one markdown table row per route: median seconds per step
// (slowest rank), bytes written per cell, MB/s.
//
// Usage: mpirun -np N canopy_bench_grid_write --output DIR [--levels L] [--steps S]
#include "ForestFingerprint.h"
#include "SyntheticForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/io/HtgSeriesWriter.h>
#include <canopy/io/VtkHdfWriter.h>

#include <mpi.h>
#include <vtkHyperTreeGrid.h>
#include <vtkNew.h>
#include <vtkXMLHyperTreeGridWriter.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

namespace
{

/// One rank's trees of the whole forest, with its own breadth-first copies of the values.
class RankPart
{
public:
  RankPart(const canopy::tools::SyntheticForest& whole, int rank, int ranks)
  {
    const canopy::ForestDescription& all = whole.description();
    Description = all;
    Description.trees.clear();
    Description.fields.clear();
    std::size_t slot = 0;
    std::size_t leafSlot = 0;
    const auto& cells = whole.cells();
    // Leaf tuples of the whole forest are in slot order: leaf rank of each slot.
    std::vector<std::int64_t> leafOfSlot(cells.size(), -1);
    {
      std::int64_t leaf = 0;
      std::vector<char> isLeaf(cells.size(), 0);
      for (const auto& tree : all.trees)
        for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
          isLeaf[static_cast<std::size_t>(tree.storageSlots[n])] = tree.refinement[n] ? 0 : 1;
      for (std::size_t s = 0; s < cells.size(); ++s)
        if (isLeaf[s])
          leafOfSlot[s] = leaf++;
    }
    const double* pressure = static_cast<const double*>(all.fields[3].data);
    for (std::size_t t = 0; t < all.trees.size(); ++t)
    {
      if (static_cast<int>(t % static_cast<std::size_t>(ranks)) != rank)
        continue;
      canopy::TreeDescription tree = all.trees[t];
      for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
      {
        const auto& cell = cells[static_cast<std::size_t>(tree.storageSlots[n])];
        Density.push_back(cell.density);
        Velocity.insert(Velocity.end(), cell.velocity, cell.velocity + 3);
        Level.push_back(cell.refinementLevel);
        if (!tree.refinement[n])
          Pressure.push_back(pressure[leafOfSlot[static_cast<std::size_t>(tree.storageSlots[n])]]);
      }
      slot += tree.numberOfNodes;
      tree.storageSlots = nullptr; // breadth-first, trees back to back
      Description.trees.push_back(tree);
    }
    leafSlot = Pressure.size();
    using canopy::FieldDescription;
    Description.fields.push_back(FieldDescription::aos("density", Density.data(), slot));
    Description.fields.push_back(FieldDescription::aos("velocity", Velocity.data(), slot, 3));
    Description.fields.push_back(FieldDescription::aos("refinementLevel", Level.data(), slot));
    Description.fields.push_back(FieldDescription::aos("pressure", Pressure.data(), leafSlot, 1,
                                                       canopy::Centering::LeavesOnly));
  }
  const canopy::ForestDescription& description() const { return Description; }

private:
  std::vector<double> Density, Velocity, Pressure;
  std::vector<std::int32_t> Level;
  canopy::ForestDescription Description;
};

std::uintmax_t bytesUnder(const std::filesystem::path& folder)
{
  std::uintmax_t total = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder))
    if (entry.is_regular_file())
      total += entry.file_size();
  return total;
}

/// Median over steps of the slowest rank's seconds for `write(step)`.
double medianSeconds(int steps, const std::function<void(int)>& write)
{
  std::vector<double> times;
  for (int step = 0; step < steps; ++step)
  {
    MPI_Barrier(MPI_COMM_WORLD);
    const auto start = std::chrono::steady_clock::now();
    write(step);
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    MPI_Allreduce(MPI_IN_PLACE, &seconds, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    times.push_back(seconds);
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  std::filesystem::path output = "grid-write-bench";
  int levels = 7;
  int steps = 5;
  for (int i = 1; i + 1 < argc; i += 2)
  {
    const std::string key = argv[i];
    if (key == "--output")
      output = argv[i + 1];
    else if (key == "--levels")
      levels = std::stoi(argv[i + 1]);
    else if (key == "--steps")
      steps = std::stoi(argv[i + 1]);
  }
  canopy::tools::SyntheticForestOptions options;
  options.dimension = 3;
  options.rootsPerAxis = 6;
  options.maxLevels = levels;
  options.cutaway = false;
  const canopy::tools::SyntheticForest whole(options);
  if (rank == 0)
    std::cout << canopy::tools::describeInput("synthetic 3D, 6^3 roots, " + std::to_string(levels) +
                                                  " levels",
                                              whole.description())
              << std::endl;
  const RankPart part(whole, rank, ranks);
  vtkSmartPointer<vtkHyperTreeGrid> htg = canopy::buildHyperTreeGrid(part.description());
  long long cells = htg->GetNumberOfCells();
  MPI_Allreduce(MPI_IN_PLACE, &cells, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);

  const std::vector<std::string> routes = {"vtkhdf", "htg-series", "vtk-xml-htg"};
  if (rank == 0)
  {
    std::filesystem::remove_all(output);
    for (const auto& route : routes)
      std::filesystem::create_directories(output / route);
  }
  MPI_Barrier(MPI_COMM_WORLD);

  std::vector<double> seconds;
  {
    canopy::io::VtkHdfWriter writer(MPI_COMM_WORLD, (output / "vtkhdf" / "grid.vtkhdf").string());
    seconds.push_back(
        medianSeconds(steps, [&](int step) { writer.writeStep(htg, step, 0.1 * step); }));
  }
  {
    canopy::io::HtgSeriesWriter writer(MPI_COMM_WORLD,
                                       (output / "htg-series" / "grid.pvd").string());
    seconds.push_back(
        medianSeconds(steps, [&](int step) { writer.writeStep(htg, step, 0.1 * step); }));
  }
  seconds.push_back(medianSeconds(
      steps,
      [&](int step)
      {
        vtkNew<vtkXMLHyperTreeGridWriter> writer;
        writer->SetInputData(htg);
        writer->SetDataModeToBinary();
        writer->SetFileName((output / "vtk-xml-htg" /
                             ("grid_" + std::to_string(step) + "_" + std::to_string(rank) + ".htg"))
                                .c_str());
        writer->Write();
      }));
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0)
  {
    std::printf("| route | ranks | cells | seconds/step | bytes/cell | MB/s |\n");
    std::printf("|---|---:|---:|---:|---:|---:|\n");
    for (std::size_t r = 0; r < routes.size(); ++r)
    {
      const double bytes = static_cast<double>(bytesUnder(output / routes[r])) / steps;
      std::printf("| %s | %d | %lld | %.3f | %.1f | %.0f |\n", routes[r].c_str(), ranks, cells,
                  seconds[r], bytes / static_cast<double>(cells), bytes / seconds[r] / 1e6);
    }
  }
  MPI_Finalize();
  return 0;
}
