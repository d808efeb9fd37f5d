// The mini-app's command line.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace miniamr
{

/// An object moving through the domain; refinement follows its surface.
struct MovingObject
{
  enum class Kind
  {
    Sphere, ///< center, radius, velocity; bounces off the domain's walls
    Plane   ///< normal, offset (n . x = offset), speed along the normal; periodic
  };
  Kind kind = Kind::Sphere;
  std::array<double, 3> center{{0.5, 0.5, 0.5}}; ///< sphere
  double radius = 0.1;                           ///< sphere
  std::array<double, 3> velocity{{0, 0, 0}};     ///< sphere
  std::array<double, 3> normal{{1, 0, 0}};       ///< plane (normalized on parse)
  double offset = 0.5;                           ///< plane
  double speed = 0.0;                            ///< plane
};

struct MiniAppOptions
{
  int dimension = 2;
  int branchFactor = 2;
  std::array<int, 3> roots{{16, 16, 16}};
  int maxLevel = 6;
  int steps = 40;
  double endTime = 0; ///< > 0: run to this time instead of --steps (the last step lands on it)
  double cfl = 0.5;
  double diffusion = 0.0;
  std::string velocity = "swirl"; ///< swirl | uniform:vx,vy[,vz]
  std::array<double, 3> uniformVelocity{{1.0, 0.5, 0.25}};
  double refineGradient = 0.05;  ///< refine where a face jump exceeds this
  double coarsenGradient = 0.01; ///< may coarsen where every face jump is below this
  int regridEvery = 1;
  double repartitionImbalance = 1.1; ///< repartition when max/mean leaves exceeds this
  std::vector<MovingObject> objects;
  /// > 0: a block forest for Canopy. Every leaf is shown as a block of blocks^d cells
  /// (a power of the branch factor) holding the leaf's fields at the cells' centres
  /// (Simulation::sampleBlocks); 0: one cell per leaf.
  int blocks = 0;
  /// "gaussian": a Gaussian translated by a uniform velocity on a fixed uniform mesh
  /// at maxLevel, with its errors against the exact solution; empty: the usual run.
  std::string exactSolution;
  // In situ.
  std::vector<std::string> pipelines; ///< empty: the default set; "none": no Canopy
  std::vector<std::vector<std::string>> pipelineArguments;
  bool noInSitu = false;
  std::string output = "canopy-output";
  int imageEvery = 5;
  std::string live;              ///< Catalyst Live address (host:port); empty: no Live
  double livePauseLimit = 300.0; ///< seconds a viewer's pause may hold the run (<= 0: none)
  double liveStallLimit = 20.0;  ///< seconds of a silent viewer before it is dropped
  int selectionEvery = 10;
  int extractEvery = 20;
  /// Query-language expressions printed every step (InSituOptions::queries).
  std::vector<std::string> queries;
  /// A trigger for the data extracts (their --trigger=, docs/queries.md) and its mode.
  std::string extractTrigger;
  std::string extractTriggerMode;
  // Reporting.
  bool quiet = false;
  bool verifyUntouched = false;
  std::string dump; ///< write the final leaves (key and value) to this file
  /// Per rank and step, resident memory and open file descriptors to
  /// <resourceLog>.<rank>.csv (soak tests, docs/testing.md); empty: none.
  std::string resourceLog;
  /// Bytes allocated, written and never freed per step: the soak check's own
  /// planted leak (tests that it would be seen); 0: none.
  long long plantLeak = 0;
};

/// Parses argv; throws std::invalid_argument naming the bad option.
MiniAppOptions parseOptions(int argc, char** argv);

/// The options table (also in docs/miniapp.md).
std::string usage();

} // namespace miniamr
