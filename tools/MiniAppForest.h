// The bundled mini-app's own forest, built in-process through its library
// (miniapp/Simulation): real data for the benchmarks beside the synthetic forest.
// The simulation runs with the mini-app's default physics and objects to a late
// step; its description is what canopy_miniamr hands Canopy at that step
// (breadth-first trees, leaves-only AoS fields scalar, velocity, level, rank).
#pragma once

#include <canopy/ForestDescription.h>

#include <mpi.h>

#include <cstdint>
#include <memory>
#include <string>

namespace miniamr
{
class Simulation;
}

namespace canopy::tools
{

struct MiniAppForestOptions
{
  int dimension = 2;
  int roots = 32;      ///< root cells per axis
  int maxLevel = 8;    ///< finest level (level 0 = roots)
  int steps = 20;      ///< steps simulated before the forest is taken
  int regridEvery = 1; ///< the mesh adapts every this many steps (the mini-app's default: 1)
};

class MiniAppForest
{
public:
  /// Collective over `communicator` (MPI must be initialized): builds the
  /// mini-app's initial mesh and advances it `steps` steps.
  explicit MiniAppForest(const MiniAppForestOptions& options,
                         MPI_Comm communicator = MPI_COMM_WORLD);
  ~MiniAppForest();
  MiniAppForest(const MiniAppForest&) = delete;
  MiniAppForest& operator=(const MiniAppForest&) = delete;

  /// This rank's trees and fields, borrowed: valid until advance().
  ForestDescription description() const;
  /// Collective: one more simulation step (the forest changes as in the mini-app).
  void advance();

  int step() const;
  std::int64_t globalLeaves() const;
  std::int64_t globalNodes() const;
  /// This rank's nodes (cells of its grid).
  std::size_t localNodes() const;
  /// "mini-app 2D, 32^2 roots, 8 levels, step 20".
  std::string label() const;
  /// The command line that makes canopy_miniamr stop at the same state.
  std::string commandLine() const;

private:
  MiniAppForestOptions Options;
  std::unique_ptr<miniamr::Simulation> Simulation;
};

/// Parses "DIM,ROOTS,MAXLEVEL,STEPS[,REGRID_EVERY]" (e.g. "2,32,9,20"); throws
/// std::invalid_argument.
MiniAppForestOptions parseMiniAppForest(const std::string& text);

/// MPI_Init if nobody did (benchmarks run as a single process also work).
/// Returns true when this call initialized MPI (then finalize it at the end).
bool initializeMpiIfNeeded(int* argc, char*** argv);

} // namespace canopy::tools
