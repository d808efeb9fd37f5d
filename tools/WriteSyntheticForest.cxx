// A stand-in simulation for benchmarks and file tests: build a synthetic AMR forest
// through Canopy's public API and write it as a .htg file ParaView opens.
//
// Usage: canopy_write_synthetic_forest [--output DIR] [--dimension 2|3]
//          [--branch-factor 2|3] [--roots N] [--levels L] [--no-cutaway]
#include "SyntheticForest.h"

#include <canopy/io/HtgFileWriter.h>

#include <canopy/HtgBuilder.h>

#include <vtkHyperTreeGrid.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>

namespace
{

int usage(const std::string& problem)
{
  std::cerr << "canopy_write_synthetic_forest: " << problem << "\n"
            << "usage: canopy_write_synthetic_forest [--output DIR] [--dimension 2|3]\n"
            << "         [--branch-factor 2|3] [--roots N] [--levels L] [--no-cutaway]\n";
  return 2;
}

} // namespace

int main(int argc, char** argv)
{
  canopy::tools::SyntheticForestOptions options;
  std::filesystem::path output = "canopy-output";
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    const bool hasValue = i + 1 < argc;
    auto number = [&](int& target) { target = std::atoi(argv[++i]); };
    if (arg == "--output" && hasValue)
      output = argv[++i];
    else if (arg == "--dimension" && hasValue)
      number(options.dimension);
    else if (arg == "--branch-factor" && hasValue)
      number(options.branchFactor);
    else if (arg == "--roots" && hasValue)
      number(options.rootsPerAxis);
    else if (arg == "--levels" && hasValue)
      number(options.maxLevels);
    else if (arg == "--no-cutaway")
      options.cutaway = false;
    else
      return usage("unknown or incomplete argument '" + arg + "'");
  }
  if (options.rootsPerAxis < 1 || options.rootsPerAxis > 1000)
    return usage("--roots must be in [1, 1000]");
  if (options.maxLevels < 1 || options.maxLevels > 20)
    return usage("--levels must be in [1, 20]");
  if (options.dimension != 2 && options.dimension != 3)
    return usage("--dimension must be 2 or 3");
  if (options.branchFactor != 2 && options.branchFactor != 3)
    return usage("--branch-factor must be 2 or 3");

  try
  {
    canopy::tools::SyntheticForest forest(options);
    const auto start = std::chrono::steady_clock::now();
    vtkSmartPointer<vtkHyperTreeGrid> htg = canopy::buildHyperTreeGrid(forest.description());
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

    std::filesystem::create_directories(output);
    const std::filesystem::path file = output / "synthetic_forest.htg";
    const std::string problem = canopy::io::writeHtgFile(htg, file.string());
    if (!problem.empty())
    {
      std::cerr << "canopy_write_synthetic_forest: " << problem << "\n";
      return 1;
    }
    std::cout << "canopy: " << options.dimension << "D forest, branch factor "
              << options.branchFactor << ", " << forest.description().trees.size() << " trees, "
              << forest.numberOfNodes() << " cells (" << forest.numberOfLeaves()
              << " leaves), grid built in " << ms << " ms\n"
              << "canopy: wrote " << file.string() << " (open it in ParaView)\n";
  }
  catch (const std::exception& e)
  {
    std::cerr << "canopy_write_synthetic_forest: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
