// canopy::InSitu from an installed Canopy: rank r passes root r of a 2 x 1
// forest to the installed selection_extract.py (found through the package's
// Canopy_PIPELINES_DIR), which selects by id; the installed helper module and
// plugin are found next to the library. Checks both ranks' pieces.
// Usage: canopy_insitu_consumer SELECTION_SCRIPT OUTPUT_DIR
#include <canopy/InSitu.h>

#include <mpi.h>

#include <cstdint>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  int status = 1;
  {
    const std::vector<double> x{0.0, 1.0, 2.0}, y{0.0, 1.0}, z{0.0};
    const std::vector<std::uint8_t> refined{1, 0, 0, 0, 0}, leaf{0};
    const std::vector<double> density =
        rank == 0 ? std::vector<double>{1, 2, 3, 4, 5} : std::vector<double>{6};
    canopy::ForestDescription forest;
    forest.dimension = 2;
    forest.branchFactor = 2;
    forest.maxLevels = 4;
    forest.rootGrid = {x.data(), y.data(), z.data(), x.size(), y.size(), z.size()};
    forest.trees.push_back({rank, rank == 0 ? refined.data() : leaf.data(),
                            rank == 0 ? refined.size() : leaf.size(), nullptr, nullptr});
    forest.fields.push_back(
        canopy::FieldDescription::aos("density", density.data(), density.size()));
    canopy::InSituOptions options;
    options.scripts = {{argv[1], {"--selection=ids", "--ids=1,5"}}};
    options.outputDirectory = argv[2];
    canopy::InSitu insitu(MPI_COMM_WORLD, options);
    const auto report = insitu.execute(0, 0.0, forest);
    insitu.close();
    // Global ids are per rank here (each rank's storage starts at 0): rank 0
    // selects its leaf 1, rank 1 (one cell, id 0) selects nothing.
    std::ifstream piece(std::string(argv[2]) + "/selection_000000/selection_000000_" +
                        std::to_string(rank) + ".vtu");
    std::stringstream text;
    text << piece.rdbuf();
    // ParaView's writer leaves out empty pieces.
    const bool pieceRight = rank == 0 ? text.str().find("NumberOfCells=\"1\"") != std::string::npos
                                      : text.str().find("NumberOfCells=\"1\"") == std::string::npos;
    const bool ok = report.failures.empty() && report.pipelinesRun.size() == 1 && pieceRight;
    std::cout << "rank " << rank << (ok ? ": ok" : ": FAILED") << "\n";
    int localOk = ok ? 1 : 0;
    int allOk = 0;
    MPI_Allreduce(&localOk, &allOk, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    status = allOk ? 0 : 1;
  }
  MPI_Finalize();
  return status;
}
