// The program that docs/insitu.md's CMake lines build: tests/consumer copies
// those lines verbatim into a project of their own, with this file as main.cxx.
// It opens canopy::InSitu with a pipeline script given by its bare name (found
// among the package's pipelines, not in the working directory), runs it once
// on one rank and checks the extract it wrote.
// Usage: my_simulation OUTPUT_DIR EXPECTED_PIPELINES_DIR
#include <canopy/InSitu.h>

#include <mpi.h>

#include <cstdint>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  bool ok = false;
  if (argc != 3)
  {
    std::cerr << "usage: my_simulation OUTPUT_DIR EXPECTED_PIPELINES_DIR\n";
  }
  else
  {
    try
    {
      // One root cell refined once: the root (id 0) and four leaves (ids 1-4).
      const std::vector<double> x{0.0, 1.0}, y{0.0, 1.0}, z{0.0};
      const std::vector<std::uint8_t> refined{1, 0, 0, 0, 0};
      const std::vector<double> density{0.5, 1.0, 2.0, 3.0, 4.0};
      canopy::ForestDescription forest;
      forest.dimension = 2;
      forest.branchFactor = 2;
      forest.maxLevels = 2;
      forest.rootGrid = {x.data(), y.data(), z.data(), x.size(), y.size(), z.size()};
      forest.trees.push_back({0, refined.data(), refined.size(), nullptr, nullptr});
      forest.fields.push_back(
          canopy::FieldDescription::aos("density", density.data(), density.size()));

      canopy::InSituOptions options;
      options.scripts = {{"selection_extract.py", {"--selection=ids", "--ids=2"}}};
      options.outputDirectory = argv[1];
      canopy::InSitu insitu(MPI_COMM_WORLD, options);
      const canopy::StepReport report = insitu.execute(0, 0.0, forest);
      insitu.close();

      namespace fs = std::filesystem;
      const fs::path shipped = fs::path(argv[2]) / "selection_extract.py";
      const bool ranShipped =
          report.pipelinesRun.size() == 1 && fs::equivalent(report.pipelinesRun[0], shipped);
      const bool wrote = fs::exists(fs::path(argv[1]) / "selection_000000.pvtu");
      std::cout << "ran: " << (report.pipelinesRun.empty() ? "nothing" : report.pipelinesRun[0])
                << " (expected " << shipped.string() << ")\n";
      for (const auto& failure : report.failures)
      {
        std::cout << "failure: " << failure << "\n";
      }
      ok = report.failures.empty() && ranShipped && wrote;
    }
    catch (const std::exception& error)
    {
      std::cerr << error.what() << "\n";
    }
  }
  std::cout << (ok ? "docs snippet: ok" : "docs snippet: FAILED") << std::endl;
  MPI_Finalize();
  return ok ? 0 : 1;
}
