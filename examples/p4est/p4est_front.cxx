// A p4est simulation with Canopy in situ: a front (a circle, a sphere in 3D)
// moves through a brick of trees; the forest refines at the front and coarsens
// behind it, is 2:1 balanced and repartitioned every step, and each quadrant
// carries a density in its user_data. Canopy's pipelines (images of the
// adaptive surface, a selection extract and hypertree-grid extracts) run on
// the forest as p4est holds it: no copy, no reordering.
//
// Compiled twice, as p4est examples are: this file for 2D, p8est_front.cxx
// (P4_TO_P8, p4est_to_p8est.h) for 3D. The Canopy glue is marked below.
//
//   mpirun -np 3 canopy_p4est_front [--steps N] [--every N] [--max-level L] [output-dir]
#ifndef P4_TO_P8
#include <p4est_bits.h>
#include <p4est_extended.h>
#include <p4est_iterate.h>
#else
#include <p4est_to_p8est.h>
#include <p8est_bits.h>
#include <p8est_extended.h>
#include <p8est_iterate.h>
#endif

// ---- Canopy glue (1 of 3): the headers ----
#include <canopy/InSitu.h>
#include <canopy/P4estForest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace
{

/// What each quadrant carries (p4est's user_data).
struct Cell
{
  double density;
};

struct Front
{
  double center[3];
  double radius;
  int maxLevel;
};

/// Lower and upper corners of a quadrant in vertex coordinates.
void quadrantCorners(p4est_t* p4est, p4est_topidx_t tree, const p4est_quadrant_t* q, double lo[3],
                     double hi[3])
{
  const p4est_qcoord_t length = P4EST_QUADRANT_LEN(q->level);
#ifndef P4_TO_P8
  p4est_qcoord_to_vertex(p4est->connectivity, tree, q->x, q->y, lo);
  p4est_qcoord_to_vertex(p4est->connectivity, tree, q->x + length, q->y + length, hi);
#else
  p4est_qcoord_to_vertex(p4est->connectivity, tree, q->x, q->y, q->z, lo);
  p4est_qcoord_to_vertex(p4est->connectivity, tree, q->x + length, q->y + length, q->z + length,
                         hi);
#endif
}

/// Lower corner and size of a quadrant in vertex coordinates.
void quadrantBox(p4est_t* p4est, p4est_topidx_t tree, const p4est_quadrant_t* q, double lo[3],
                 double& size)
{
  double hi[3];
  quadrantCorners(p4est, tree, q, lo, hi);
  size = hi[0] - lo[0];
}

/// Signed distance from the quadrant's center to the front.
double distanceToFront(p4est_t* p4est, p4est_topidx_t tree, const p4est_quadrant_t* q)
{
  const auto* front = static_cast<const Front*>(p4est->user_pointer);
  double lo[3];
  double size;
  quadrantBox(p4est, tree, q, lo, size);
  double squared = 0;
  for (int a = 0; a < P4EST_DIM; ++a)
  {
    const double d = lo[a] + 0.5 * size - front->center[a];
    squared += d * d;
  }
  return std::sqrt(squared) - front->radius;
}

void setDensity(p4est_t* p4est, p4est_topidx_t tree, p4est_quadrant_t* q)
{
  // A smoothed step across the front: 2 inside, 1 outside.
  static_cast<Cell*>(q->p.user_data)->density =
      1.5 - 0.5 * std::tanh(distanceToFront(p4est, tree, q) / 0.15);
}

int nearFront(p4est_t* p4est, p4est_topidx_t tree, p4est_quadrant_t* q)
{
  double lo[3];
  double size;
  quadrantBox(p4est, tree, q, lo, size);
  const auto* front = static_cast<const Front*>(p4est->user_pointer);
  return q->level < front->maxLevel &&
         std::abs(distanceToFront(p4est, tree, q)) < 0.9 * size * std::sqrt(P4EST_DIM);
}

int awayFromFront(p4est_t* p4est, p4est_topidx_t tree, p4est_quadrant_t* children[])
{
  for (int c = 0; c < P4EST_CHILDREN; ++c)
  {
    if (nearFront(p4est, tree, children[c]))
    {
      return 0;
    }
  }
  return 1;
}

/// What the simulation reports of its own quadrants, for the test to compare Canopy's
/// outputs with (tests/p4est/p4est_front_check.py).
struct Totals
{
  long dense = 0;  ///< quadrants with a density in [1.9, 2.1]
  double mass = 0; ///< sum of density * volume, in vertex coordinates
  double minimum = std::numeric_limits<double>::infinity();
  double maximum = -std::numeric_limits<double>::infinity();
};

void updateDensity(p4est_iter_volume_info_t* info, void* data)
{
  setDensity(info->p4est, info->treeid, info->quad);
  const double density = static_cast<Cell*>(info->quad->p.user_data)->density;
  double lo[3];
  double hi[3];
  quadrantCorners(info->p4est, info->treeid, info->quad, lo, hi);
  double volume = 1;
  for (int a = 0; a < P4EST_DIM; ++a)
    volume *= hi[a] - lo[a];
  auto* totals = static_cast<Totals*>(data);
  totals->dense += density >= 1.9 && density <= 2.1;
  totals->mass += density * volume;
  totals->minimum = std::min(totals->minimum, density);
  totals->maximum = std::max(totals->maximum, density);
}

/// One step of the "simulation": move the front, adapt, balance, repartition.
/// Returns the rank's totals (Totals).
Totals advance(p4est_t* p4est, Front& front, double time)
{
  front.center[0] = 1.0 + 1.6 * time;
  // One level per step: recursive coarsening would depend on how families are partitioned.
  p4est_coarsen(p4est, 0, awayFromFront, setDensity);
  p4est_refine(p4est, 1, nearFront, setDensity);
  p4est_balance(p4est, P4EST_CONNECT_FULL, setDensity);
  // Keep sibling families on one rank, so coarsening does not depend on the partition.
  p4est_partition(p4est, 1, nullptr);
  Totals totals;
  p4est_iterate(p4est, nullptr, &totals, updateDensity, nullptr,
#ifdef P4_TO_P8
                nullptr,
#endif
                nullptr);
  return totals;
}

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  long steps = 20;
  long every = 5;
  Front front{{1.0, 1.5, 1.0}, 0.8, P4EST_DIM == 2 ? 6 : 4};
  std::string output = "p4est-output";
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--steps" && i + 1 < argc)
      steps = std::atol(argv[++i]);
    else if (arg == "--every" && i + 1 < argc)
      every = std::atol(argv[++i]);
    else if (arg == "--max-level" && i + 1 < argc)
      front.maxLevel = std::atoi(argv[++i]);
    else
      output = arg;
  }
  sc_init(MPI_COMM_WORLD, 1, 1, nullptr, SC_LP_ERROR);
  p4est_init(nullptr, SC_LP_ERROR);
#ifndef P4_TO_P8
  p4est_connectivity_t* brick = p4est_connectivity_new_brick(4, 3, 0, 0);
#else
  p4est_connectivity_t* brick = p4est_connectivity_new_brick(4, 3, 2, 0, 0, 0);
#endif
  p4est_t* p4est = p4est_new_ext(MPI_COMM_WORLD, brick, 0, 1, 1, sizeof(Cell), setDensity, &front);
  std::vector<double> owner; // a per-quadrant array, indexed by local quadrant number

  // ---- Canopy glue (2 of 3): open, with the shipped pipelines by name ----
  const std::string frequency = "--frequency=" + std::to_string(every);
  canopy::InSituOptions options;
#ifndef P4_TO_P8
  options.scripts = {{"surface_image.py", {frequency, "--color-by=density"}}};
#else
  // 3D: slices through the centre with the front's isosurface (density 1.5, the
  // sphere itself), written as .pvtp too, and the dense region (inside the sphere)
  // with the octant towards the camera cut away: what is inside shows.
  options.scripts = {{"slice_image.py",
                      {frequency, "--color-by=density", "--contour-field=density",
                       "--contour-values=1.5", "--slice-extract=1"}},
                     {"surface_image.py",
                      {frequency, "--color-by=density", "--select-field=density",
                       "--select-range=1.5,1e30", "--cut-away=octant", "--file-prefix=region"}}};
#endif
  options.scripts.push_back(
      {"selection_extract.py",
       {frequency, "--selection=range", "--value-field=density", "--value-range=1.9,2.1"}});
  options.scripts.push_back({"data_extracts.py", {frequency}});
  options.outputDirectory = output;
  canopy::InSitu insitu(MPI_COMM_WORLD, options);

  for (long step = 0; step <= steps; ++step)
  {
    const double time = 0.1 * static_cast<double>(step);
    const Totals mine = advance(p4est, front, time);
    Totals all;
    MPI_Reduce(&mine.dense, &all.dense, 1, MPI_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
    MPI_Reduce(&mine.mass, &all.mass, 1, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
    MPI_Reduce(&mine.minimum, &all.minimum, 1, MPI_DOUBLE, MPI_MIN, 0, MPI_COMM_WORLD);
    MPI_Reduce(&mine.maximum, &all.maximum, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
    if (rank == 0 && step % every == 0)
    {
      std::printf("p4est_front: step %ld: %lld quadrants, %ld with density in [1.9, 2.1]\n", step,
                  static_cast<long long>(p4est->global_num_quadrants), all.dense);
      // Full precision: the test compares Canopy's extracts with these to 1e-12.
      std::printf("p4est_front: step %ld: mass %.17g, density from %.17g to %.17g\n", step,
                  all.mass, all.minimum, all.maximum);
    }
    owner.assign(static_cast<std::size_t>(p4est->local_num_quadrants), rank);

    // ---- Canopy glue (3 of 3): describe the forest as it is now, run what is due ----
    if (insitu.willExecute(step, time))
    {
#ifndef P4_TO_P8
      canopy::P4estForest described(p4est);
#else
      canopy::P8estForest described(p4est);
#endif
      described.addUserDataField<double>("density", offsetof(Cell, density));
      described.addQuadrantField("owner", owner.data());
      const canopy::StepReport report = insitu.execute(step, time, described.description());
      for (const std::string& failure : report.failures)
        std::fprintf(stderr, "canopy: %s\n", failure.c_str());
      // What the pipelines measured (the quads and triangles they drew, all ranks).
      if (rank == 0)
        for (const auto& [name, value] : report.measures)
          std::printf("p4est_front: step %ld: %s %.17g\n", step, name.c_str(), value);
    }
  }
  insitu.close();

  p4est_destroy(p4est);
  p4est_connectivity_destroy(brick);
  sc_finalize();
  MPI_Finalize();
  return 0;
}
