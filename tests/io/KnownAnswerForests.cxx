// Tiny forests written to VTKHDF through Canopy's public writer
// (canopy::io::VtkHdfWriter), for tests/io/vtkhdf_known_answer.py: that test
// holds every dataset's expected contents written out by hand from VTK's
// VTKHDF HyperTreeGrid specification. Keep each forest here in step with the
// comments there; nothing else reads them.
//
// Every forest is given literally: refinement (and mask) bytes breadth-first,
// root children x fastest then y then z, and one float64 field "value" with
// one literal value per node, in storage order.
//
// Usage: canopy_vtkhdf_known_answer_write --output DIR
//   1 rank:  DIR/a_2d_binary.vtkhdf ... DIR/e_two_steps.vtkhdf
//   2 ranks: DIR/f_two_pieces.vtkhdf (each rank one piece with its own tree)
#include <canopy/HtgBuilder.h>
#include <canopy/io/VtkHdfWriter.h>

#include <mpi.h>
#include <vtkHyperTreeGrid.h>

#include <cstdint>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace
{

struct Tree
{
  std::int64_t root = 0;
  std::vector<std::uint8_t> refinement; // breadth-first
  std::vector<std::uint8_t> masked;     // empty: none
  std::vector<std::int64_t> slots;      // empty: breadth-first storage
};

/// Owns what a ForestDescription borrows.
struct Forest
{
  int dimension = 2;
  int branchFactor = 2;
  int maxLevels = 2;
  std::vector<double> x, y, z;
  std::vector<Tree> trees;
  std::vector<double> values; // one per node, storage order
  bool missingTreesAreElsewhere = false;

  canopy::ForestDescription description() const
  {
    canopy::ForestDescription d;
    d.dimension = this->dimension;
    d.branchFactor = this->branchFactor;
    d.maxLevels = this->maxLevels;
    d.rootGrid = {this->x.data(), this->y.data(), this->z.data(),
                  this->x.size(), this->y.size(), this->z.size()};
    d.missingTreesAreElsewhere = this->missingTreesAreElsewhere;
    for (const Tree& tree : this->trees)
    {
      d.trees.push_back({tree.root, tree.refinement.data(), tree.refinement.size(),
                         tree.masked.empty() ? nullptr : tree.masked.data(),
                         tree.slots.empty() ? nullptr : tree.slots.data(), nullptr});
    }
    d.fields.push_back(
        canopy::FieldDescription::aos("value", this->values.data(), this->values.size()));
    return d;
  }
};

/// Appends one step per forest to a new file `path`.
void write(MPI_Comm communicator, const std::filesystem::path& path,
           const std::vector<std::pair<const Forest*, double>>& steps)
{
  canopy::io::VtkHdfWriter writer(communicator, path.string());
  std::int64_t step = 0;
  for (const auto& [forest, time] : steps)
  {
    // The description outlives the write: the grid borrows what it points to.
    const canopy::ForestDescription description = forest->description();
    const auto htg = canopy::buildHyperTreeGrid(description);
    writer.writeStep(htg, step++, time);
  }
}

void writeSerialCases(const std::filesystem::path& output)
{
  // (a) 2D binary, 2x1 roots; root 0 refined once, root 1 a leaf.
  Forest a;
  a.x = {0, 1, 2};
  a.y = {0, 1};
  a.z = {0};
  a.trees = {{0, {1, 0, 0, 0, 0}, {}, {}}, {1, {0}, {}, {}}};
  a.values = {10, 11, 12, 13, 14, 20};
  write(MPI_COMM_WORLD, output / "a_2d_binary.vtkhdf", {{&a, 0.0}});

  // (b) 3D binary, 1 root refined once, its child 5 refined again. Stored
  // depth-first (slot map), so the file's breadth-first order differs from memory.
  Forest b;
  b.dimension = 3;
  b.maxLevels = 3;
  b.x = {0, 1};
  b.y = {0, 1};
  b.z = {0, 1};
  Tree bTree;
  bTree.root = 0;
  bTree.refinement = {1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  // Breadth-first node -> depth-first slot: root, c0..c5, then c5's children
  // (slots 7..14) before c6 (15) and c7 (16).
  bTree.slots = {0, 1, 2, 3, 4, 5, 6, 15, 16, 7, 8, 9, 10, 11, 12, 13, 14};
  b.trees = {bTree};
  b.values = {100, 101, 102, 103, 104, 105, 106, 107, 108,
              109, 110, 111, 112, 113, 114, 115, 116}; // value = 100 + slot
  write(MPI_COMM_WORLD, output / "b_3d_binary.vtkhdf", {{&b, 0.0}});

  // (c) 2D ternary, 1 root refined once, its centre child (c4) refined again.
  Forest c;
  c.branchFactor = 3;
  c.maxLevels = 3;
  c.x = {0, 3};
  c.y = {0, 3};
  c.z = {0};
  c.trees = {{0, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, {}, {}}};
  for (int n = 0; n < 19; ++n)
  {
    c.values.push_back(300 + n);
  }
  write(MPI_COMM_WORLD, output / "c_2d_ternary.vtkhdf", {{&c, 0.0}});

  // (d) Masked, 2D binary, 2x1 roots. Root 0: c1 refined; c2 (a leaf) and
  // c1's child 3 masked. Root 1: c0 refined and masked (a masked subtree).
  Forest d;
  d.maxLevels = 3;
  d.x = {0, 1, 2};
  d.y = {0, 1};
  d.z = {0};
  d.trees = {{0, {1, 0, 1, 0, 0, 0, 0, 0, 0}, {0, 0, 0, 1, 0, 0, 0, 0, 1}, {}},
             {1, {1, 1, 0, 0, 0, 0, 0, 0, 0}, {0, 1, 0, 0, 0, 0, 0, 0, 0}, {}}};
  d.values = {40, 41, 42, 43, 44, 45, 46, 47, 48, 50, 51, 52, 53, 54, 55, 56, 57, 58};
  write(MPI_COMM_WORLD, output / "d_masked.vtkhdf", {{&d, 0.0}});

  // (e) Two steps of one 2D root, refined differently, root grid moved.
  Forest e0;
  e0.maxLevels = 3;
  e0.x = {0, 1};
  e0.y = {0, 1};
  e0.z = {0};
  e0.trees = {{0, {1, 0, 1, 0, 0, 0, 0, 0, 0}, {}, {}}};
  e0.values = {60, 61, 62, 63, 64, 65, 66, 67, 68};
  Forest e1;
  e1.maxLevels = 4;
  e1.x = {0, 2};
  e1.y = {0, 2};
  e1.z = {1};
  // c3 refined, and c3's child 0 refined again.
  e1.trees = {{0, {1, 0, 0, 0, 1, 1, 0, 0, 0, 0, 0, 0, 0}, {}, {}}};
  e1.values = {70, 71, 72, 73, 74, 75, 76, 77, 78, 79, 80, 81, 82};
  write(MPI_COMM_WORLD, output / "e_two_steps.vtkhdf", {{&e0, 0.0}, {&e1, 0.5}});
}

void writePieces(const std::filesystem::path& output, int rank)
{
  // (f) 2D binary, 2x1 roots; each rank its own tree, one piece per rank.
  Forest f;
  f.maxLevels = 3;
  f.x = {0, 1, 2};
  f.y = {0, 1};
  f.z = {0};
  f.missingTreesAreElsewhere = true;
  if (rank == 0)
  {
    f.trees = {{0, {1, 0, 0, 0, 0}, {}, {}}};
    f.values = {80, 81, 82, 83, 84};
  }
  else
  {
    // c0 refined; c3 (a leaf) and c0's child 0 masked.
    f.trees = {{1, {1, 1, 0, 0, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 1, 1, 0, 0, 0}, {}}};
    f.values = {90, 91, 92, 93, 94, 95, 96, 97, 98};
  }
  write(MPI_COMM_WORLD, output / "f_two_pieces.vtkhdf", {{&f, 0.0}});
}

} // namespace

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  int status = 0;
  try
  {
    if (argc != 3 || std::string(argv[1]) != "--output")
    {
      throw std::invalid_argument("usage: canopy_vtkhdf_known_answer_write --output DIR");
    }
    const std::filesystem::path output = argv[2];
    std::filesystem::create_directories(output);
    if (ranks == 1)
    {
      writeSerialCases(output);
    }
    else if (ranks == 2)
    {
      writePieces(output, rank);
    }
    else
    {
      throw std::invalid_argument("run on 1 rank (cases a-e) or 2 ranks (case f)");
    }
  }
  catch (const std::exception& error)
  {
    std::cerr << "rank " << rank << ": " << error.what() << "\n";
    status = 1;
  }
  MPI_Finalize();
  return status;
}
