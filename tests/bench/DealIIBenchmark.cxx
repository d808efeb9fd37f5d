// What handing a deal.II mesh and its cell data to Canopy costs, against what
// deal.II users do today, in one run: a parallel::distributed::Triangulation
// (2D: 4 x 4 coarse cells, 3D: 2 x 2 x 2) refined globally and then twice at a
// circle (sphere), with two cell vectors (a float indicator by active_cell_index,
// a double by global_active_cell_index). Per mesh, best of R repetitions:
//   - Canopy: DealIIForest + addCellVector x 2 (describe), then the
//     vtkHyperTreeGrid built from it (what an executed step does before its
//     pipelines); memory written: the heap bytes allocated meanwhile
//     (AllocationCounter.c: the description's tables, kept and scratch, and the
//     grid's), and DealIIForest::memoryWritten() for the description alone;
//   - DataOut: attach_triangulation, the same two cell vectors, build_patches,
//     write_vtu_with_pvtu_record (8 groups, as step-40; deal.II's default zlib
//     best_compression, and again with best_speed); memory written: the heap
//     bytes allocated meanwhile and the bytes of the files;
//   - one refine_and_coarsen_fixed_number (30% / 3%) +
//     execute_coarsening_and_refinement (p4est refines, balances, repartitions).
//
// Usage: mpirun -np N canopy_bench_dealii [--repetitions R] [--output DIR]
// Prints a Markdown table (rank 0); times are the slowest rank's, bytes all ranks'.
#include <canopy/DealIIForest.h>
#include <canopy/GridBuilder.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/partitioner.h>
#include <deal.II/distributed/grid_refinement.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/numerics/data_out.h>

extern "C" unsigned long long canopy_bench_allocated_bytes(void);

#include <vtkHyperTreeGrid.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace
{

using namespace dealii;
using Clock = std::chrono::steady_clock;

/// Maximum over ranks of a local duration, in milliseconds.
double slowest(Clock::time_point start)
{
  const double local = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return Utilities::MPI::max(local, MPI_COMM_WORLD);
}

template <int dim>
void refineAtFront(parallel::distributed::Triangulation<dim>& tria)
{
  for (const auto& cell : tria.active_cell_iterators())
  {
    if (!cell->is_locally_owned())
      continue;
    double distance = 0;
    for (int a = 0; a < dim; ++a)
    {
      const double d = cell->center()[a] - 0.45;
      distance += d * d;
    }
    if (std::abs(std::sqrt(distance) - 0.3) < cell->diameter())
      cell->set_refine_flag();
  }
  tria.execute_coarsening_and_refinement();
}

struct Row
{
  unsigned long long cells = 0;
  double describe = 1e300, build = 1e300, dataOut = 1e300, write = 1e300, fastWrite = 1e300,
         adapt = 0;
  unsigned long long canopyHeap = 0, descriptionBytes = 0, dataOutHeap = 0, fileBytes = 0;
};

template <int dim>
Row measure(int globalLevels, int repetitions, const std::string& output)
{
  parallel::distributed::Triangulation<dim> tria(MPI_COMM_WORLD);
  GridGenerator::subdivided_hyper_cube(tria, dim == 2 ? 4 : 2);
  tria.refine_global(globalLevels);
  refineAtFront(tria);
  refineAtFront(tria);
  Row row;
  row.cells = tria.n_global_active_cells();
  Vector<float> indicator(tria.n_active_cells());
  LinearAlgebra::distributed::Vector<double> density(
      tria.global_active_cell_index_partitioner().lock());
  for (const auto& cell : tria.active_cell_iterators())
  {
    if (!cell->is_locally_owned())
      continue;
    const auto c = cell->center();
    indicator[cell->active_cell_index()] = static_cast<float>(std::sin(7 * c[0]) * c[1]);
    density[cell->global_active_cell_index()] = 1 + c[0] * c[1];
  }
  // DataOut takes cell data as Vector<double|float> by active_cell_index.
  Vector<double> densityByActive(tria.n_active_cells());
  for (const auto& cell : tria.active_cell_iterators())
    if (cell->is_locally_owned())
      densityByActive[cell->active_cell_index()] = density[cell->global_active_cell_index()];

  for (int r = 0; r < repetitions; ++r)
  {
    canopy::GridBuilder builder; // a first build each time: nothing kept
    MPI_Barrier(MPI_COMM_WORLD);
    unsigned long long heap = canopy_bench_allocated_bytes();
    auto start = Clock::now();
    canopy::DealIIForest<dim> described(tria);
    described.addCellVector("indicator", indicator);
    described.addCellVector("density", density);
    row.describe = std::min(row.describe, slowest(start));
    start = Clock::now();
    vtkSmartPointer<vtkHyperTreeGrid> grid = builder.build(described.description());
    row.build = std::min(row.build, slowest(start));
    row.canopyHeap = Utilities::MPI::sum(canopy_bench_allocated_bytes() - heap, MPI_COMM_WORLD);
    row.descriptionBytes = Utilities::MPI::sum(
        static_cast<unsigned long long>(described.memoryWritten()), MPI_COMM_WORLD);

    MPI_Barrier(MPI_COMM_WORLD);
    heap = canopy_bench_allocated_bytes();
    start = Clock::now();
    DataOut<dim> out;
    out.attach_triangulation(tria);
    out.add_data_vector(indicator, "indicator", DataOut<dim>::type_cell_data);
    out.add_data_vector(densityByActive, "density", DataOut<dim>::type_cell_data);
    out.build_patches();
    row.dataOut = std::min(row.dataOut, slowest(start));
    start = Clock::now();
    const std::string name = "cells_" + std::to_string(dim) + "d_" + std::to_string(globalLevels);
    out.write_vtu_with_pvtu_record(output + "/", name, r, MPI_COMM_WORLD, 2, 8);
    row.write = std::min(row.write, slowest(start));
    row.dataOutHeap = Utilities::MPI::sum(canopy_bench_allocated_bytes() - heap, MPI_COMM_WORLD);
    // The same files with zlib's fastest level (deal.II's default is its best).
    DataOutBase::VtkFlags fast;
    fast.compression_level = DataOutBase::VtkFlags::best_speed;
    out.set_flags(fast);
    start = Clock::now();
    out.write_vtu_with_pvtu_record(output + "/", name + "_fast", r, MPI_COMM_WORLD, 2, 8);
    row.fastWrite = std::min(row.fastWrite, slowest(start));
    if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    {
      unsigned long long bytes = 0;
      for (const auto& entry : std::filesystem::directory_iterator(output))
      {
        const std::string file = entry.path().filename().string();
        if (file.rfind(name + "_" + (r < 10 ? "0" : "") + std::to_string(r), 0) == 0)
          bytes += entry.file_size();
      }
      row.fileBytes = bytes;
    }
  }
  // One adaptation cycle of the same mesh, as step-40 does it (p4est refines,
  // balances and repartitions).
  MPI_Barrier(MPI_COMM_WORLD);
  const auto start = Clock::now();
  parallel::distributed::GridRefinement::refine_and_coarsen_fixed_number(tria, indicator, 0.3,
                                                                         0.03);
  tria.execute_coarsening_and_refinement();
  row.adapt = slowest(start);
  return row;
}

void print(int dim, const Row& r)
{
  const double canopy = r.describe + r.build;
  const double cells = static_cast<double>(r.cells);
  std::printf("| %dD | %llu | %.1f | %.1f | %.1f | %.0f | %.0f | %.0f | %.0fx | %.0fx | %.0f | "
              "%.0f | %.0f | %.0f | %.1fx |\n",
              dim, r.cells, r.describe, r.build, r.dataOut, r.write, r.fastWrite, r.adapt,
              (r.dataOut + r.write) / canopy, (r.dataOut + r.fastWrite) / canopy,
              static_cast<double>(r.descriptionBytes) / cells,
              static_cast<double>(r.canopyHeap) / cells, static_cast<double>(r.dataOutHeap) / cells,
              static_cast<double>(r.fileBytes) / cells,
              static_cast<double>(r.dataOutHeap + r.fileBytes) / static_cast<double>(r.canopyHeap));
}

} // namespace

int main(int argc, char** argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  int repetitions = 3;
  std::string output = "canopy-bench-dealii";
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--repetitions" && i + 1 < argc)
      repetitions = std::atoi(argv[++i]);
    else if (arg == "--output" && i + 1 < argc)
      output = argv[++i];
  }
  const bool root = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
  if (root)
    std::filesystem::create_directories(output);
  MPI_Barrier(MPI_COMM_WORLD);
  if (root)
  {
    std::printf("| dim | cells | describe ms | build ms | build_patches ms | write_vtu ms | "
                "write_vtu best_speed ms | refine + repartition ms | DataOut / Canopy time | "
                "the same, best_speed | description B/cell | Canopy heap B/cell | DataOut heap "
                "B/cell | VTU file B/cell | DataOut / Canopy bytes |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  }
  for (int levels : {5, 7})
  {
    const Row row = measure<2>(levels, repetitions, output);
    if (root)
      print(2, row);
  }
  for (int levels : {3, 4})
  {
    const Row row = measure<3>(levels, repetitions, output);
    if (root)
      print(3, row);
  }
  return 0;
}
