// Canopy::IO from the package, without Catalyst, the way docs/api.md shows it: a
// simulation builds its grid each step and appends it to a VTKHDF file and to the
// .pvd series ParaView 5.11 opens, on MPI_COMM_WORLD.
//
// Usage: canopy_io_consumer OUTPUT_DIR
#include <canopy/GridBuilder.h>
#include <canopy/io/HtgSeriesWriter.h>
#include <canopy/io/VtkHdfWriter.h>

#include <mpi.h>
#include <vtkHyperTreeGrid.h>

#include <cstdint>
#include <filesystem>
#include <iostream>
#include <vector>

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  int code = 1;
  {
    const std::filesystem::path output = argc > 1 ? argv[1] : "io-consumer-output";
    std::filesystem::create_directories(output);
    int rank = 0, ranks = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    // Two roots: tree 0 refined once (5 nodes), tree 1 a single leaf; on two
    // ranks each rank owns one tree, on one rank both.
    const std::vector<double> x{0.0, 1.0, 2.0}, y{0.0, 1.0}, z{0.0};
    const std::vector<std::uint8_t> refined0{1, 0, 0, 0, 0}, refined1{0};
    const bool owns0 = rank == 0, owns1 = ranks == 1 || rank == 1;
    std::vector<double> density(owns0 ? 5 : 0, 1.0);
    density.resize(density.size() + (owns1 ? 1 : 0), 2.0);

    canopy::ForestDescription forest;
    forest.dimension = 2;
    forest.branchFactor = 2;
    forest.maxLevels = 2;
    forest.rootGrid = {x.data(), y.data(), z.data(), x.size(), y.size(), z.size()};
    forest.missingTreesAreElsewhere = true;
    if (owns0)
      forest.trees.push_back({0, refined0.data(), refined0.size(), nullptr, nullptr});
    if (owns1)
      forest.trees.push_back({1, refined1.data(), refined1.size(), nullptr, nullptr});
    forest.fields.push_back(
        canopy::FieldDescription::aos("density", density.data(), density.size()));

    canopy::GridBuilder builder;
    canopy::io::VtkHdfWriter vtkhdf(MPI_COMM_WORLD, (output / "grid.vtkhdf").string());
    canopy::io::HtgSeriesWriter series(MPI_COMM_WORLD, (output / "grid.pvd").string());
    try
    {
      for (std::int64_t step = 0; step < 2; ++step)
      {
        for (double& value : density)
          value += 1.0;
        vtkHyperTreeGrid* grid = builder.build(forest);
        vtkhdf.writeStep(grid, step, 0.5 * static_cast<double>(step));
        series.writeStep(grid, step, 0.5 * static_cast<double>(step));
      }
      const bool ok = vtkhdf.numberOfSteps() == 2 && series.numberOfSteps() == 2 &&
                      std::filesystem::file_size(output / "grid.vtkhdf") > 0 &&
                      std::filesystem::exists(output / "grid.pvd") &&
                      std::filesystem::exists(output / "grid_000001.vtm");
      std::cout << (ok ? "io consumer: ok" : "io consumer: FAILED") << std::endl;
      code = ok ? 0 : 1;
    }
    catch (const canopy::io::WriteError& error)
    {
      std::cerr << "io consumer: " << error.what() << std::endl;
    }
  }
  MPI_Finalize();
  return code;
}
