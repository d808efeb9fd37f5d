// The core promise: the grid reads the simulation's memory in place and never
// writes it.
#include "RandomForest.h"

#include <canopy/HtgBuilder.h>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkSOADataArrayTemplate.h>

#include <numeric>

namespace canopy::testing
{
namespace
{

RandomForestOptions smallForest()
{
  RandomForestOptions o;
  o.dimension = 3;
  o.branchFactor = 2;
  o.rootCells = {{3, 2, 2}};
  o.maxLevels = 4;
  o.maskProbability = 0.1;
  o.seed = 7;
  return o;
}

TEST(ZeroCopy, AosArrayPointsAtSimulationMemory)
{
  RandomForest forest(smallForest());
  const std::size_t n = forest.numberOfNodes();
  std::vector<double> pressure(n);
  std::iota(pressure.begin(), pressure.end(), 0.5);
  std::vector<float> velocity(3 * n, 1.0f);
  std::vector<std::int32_t> owner(n, 3);
  std::vector<std::int64_t> id(n, 42);
  auto& d = forest.description();
  d.fields.push_back(FieldDescription::aos("pressure", pressure.data(), n));
  d.fields.push_back(FieldDescription::aos("velocity", velocity.data(), n, 3));
  d.fields.push_back(FieldDescription::aos("owner", owner.data(), n));
  d.fields.push_back(FieldDescription::aos("id", id.data(), n));

  auto htg = buildHyperTreeGrid(d);
  vtkCellData* cd = htg->GetCellData();
  ASSERT_EQ(cd->GetNumberOfArrays(), 4);
  EXPECT_EQ(cd->GetArray("pressure")->GetVoidPointer(0), static_cast<void*>(pressure.data()));
  EXPECT_EQ(cd->GetArray("velocity")->GetVoidPointer(0), static_cast<void*>(velocity.data()));
  EXPECT_EQ(cd->GetArray("owner")->GetVoidPointer(0), static_cast<void*>(owner.data()));
  EXPECT_EQ(cd->GetArray("id")->GetVoidPointer(0), static_cast<void*>(id.data()));
  EXPECT_EQ(cd->GetArray("velocity")->GetNumberOfComponents(), 3);
  EXPECT_EQ(cd->GetArray("pressure")->GetNumberOfTuples(), static_cast<vtkIdType>(n));
  EXPECT_EQ(cd->GetArray("pressure")->GetDataType(), VTK_DOUBLE);
  EXPECT_EQ(cd->GetArray("velocity")->GetDataType(), VTK_FLOAT);

  // The root coordinates are borrowed too.
  EXPECT_EQ(htg->GetXCoordinates()->GetVoidPointer(0),
            static_cast<const void*>(forest.coordinates()[0].data()));
  EXPECT_EQ(htg->GetZCoordinates()->GetVoidPointer(0),
            static_cast<const void*>(forest.coordinates()[2].data()));
}

TEST(ZeroCopy, SimulationUpdatesAreSeenThroughTheGrid)
{
  RandomForest forest(smallForest());
  const std::size_t n = forest.numberOfNodes();
  std::vector<double> pressure(n, 1.0);
  std::vector<double> u(n, 0.0), v(n, 0.0);
  struct Cell
  {
    double density;
    float momentum[2];
    int flags;
  };
  std::vector<Cell> cells(n, Cell{1.0, {0.f, 0.f}, 0});
  auto& d = forest.description();
  d.fields.push_back(FieldDescription::aos("pressure", pressure.data(), n));
  d.fields.push_back(FieldDescription::soa<double>("uv", {u.data(), v.data()}, n));
  d.fields.push_back(
      FieldDescription::strided("momentum", &cells[0].momentum[0], sizeof(Cell), n, 2));
  d.fields.push_back(FieldDescription::strided("density", &cells[0].density, sizeof(Cell), n));
  auto htg = buildHyperTreeGrid(d);

  const vtkIdType k = static_cast<vtkIdType>(n / 2);
  pressure[k] = 123.25;
  v[k] = -7.5;
  cells[k].momentum[1] = 9.5f;
  cells[k].density = 0.125;
  vtkCellData* cd = htg->GetCellData();
  EXPECT_EQ(cd->GetArray("pressure")->GetComponent(k, 0), 123.25);
  EXPECT_EQ(cd->GetArray("uv")->GetComponent(k, 1), -7.5);
  EXPECT_EQ(cd->GetArray("momentum")->GetComponent(k, 1), 9.5);
  EXPECT_EQ(cd->GetArray("density")->GetComponent(k, 0), 0.125);

  // SoA components are the simulation's own arrays.
  auto* soa = vtkSOADataArrayTemplate<double>::SafeDownCast(cd->GetArray("uv"));
  ASSERT_NE(soa, nullptr);
  EXPECT_EQ(soa->GetComponentArrayPointer(0), u.data());
  EXPECT_EQ(soa->GetComponentArrayPointer(1), v.data());
}

TEST(ZeroCopy, SlotMappedFieldsAreReadInPlaceAtEveryCell)
{
  // Depth-first storage: the grid's cells are breadth-first, fields read through
  // the cell -> slot table, the simulation's arrays in place.
  RandomForestOptions o = smallForest();
  o.order = StorageOrder::DepthFirst;
  RandomForest forest(o);
  const std::size_t n = forest.numberOfNodes();
  std::vector<double> pressure(n);
  for (std::size_t s = 0; s < n; ++s)
    pressure[s] = 0.5 * static_cast<double>(s);
  auto& d = forest.description();
  d.fields.push_back(FieldDescription::aos("pressure", pressure.data(), n));
  auto htg = buildHyperTreeGrid(d);
  vtkDataArray* array = htg->GetCellData()->GetArray("pressure");
  ASSERT_EQ(array->GetNumberOfTuples(), static_cast<vtkIdType>(n));
  std::size_t checked = 0;
  for (std::size_t t = 0; t < forest.nodes().size(); ++t)
  {
    for (std::size_t node = 0; node < forest.nodes()[t].size(); ++node)
    {
      const auto slot = static_cast<std::size_t>(forest.nodes()[t][node].slot);
      const vtkIdType cell = forest.cellOf(t, node);
      ASSERT_EQ(array->GetComponent(cell, 0), pressure[slot]);
      // A change in the simulation's memory is seen at once: nothing was copied.
      pressure[slot] = -1.0 - static_cast<double>(slot);
      ASSERT_EQ(array->GetComponent(cell, 0), pressure[slot]);
      ++checked;
    }
  }
  EXPECT_EQ(checked, n);
}

TEST(ZeroCopy, BuildNeverWritesSimulationMemory)
{
  RandomForestOptions o = smallForest();
  o.order = StorageOrder::DepthFirst;
  RandomForest forest(o);
  const std::size_t n = forest.numberOfNodes();
  const std::size_t leaves = forest.numberOfLeaves();
  std::vector<double> pressure(n);
  std::iota(pressure.begin(), pressure.end(), -3.0);
  std::vector<double> energy(leaves);
  std::iota(energy.begin(), energy.end(), 100.0);
  struct Cell
  {
    double rho;
    double m[3];
  };
  std::vector<Cell> cells(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    cells[i] = Cell{double(i), {1.0 * i, 2.0 * i, 3.0 * i}};
  }
  auto& d = forest.description();
  d.fields.push_back(FieldDescription::aos("pressure", pressure.data(), n));
  d.fields.push_back(
      FieldDescription::aos("energy", energy.data(), leaves, 1, Centering::LeavesOnly));
  d.fields.push_back(FieldDescription::strided("m", &cells[0].m[0], sizeof(Cell), n, 3));

  auto sum = [&]
  {
    std::uint64_t h = checksum(pressure.data(), n * sizeof(double));
    h ^= checksum(energy.data(), leaves * sizeof(double)) * 3;
    h ^= checksum(cells.data(), n * sizeof(Cell)) * 5;
    for (std::size_t t = 0; t < forest.refinement().size(); ++t)
    {
      h ^= checksum(forest.refinement()[t].data(), forest.refinement()[t].size()) * (7 + t);
      h ^= checksum(forest.masked()[t].data(), forest.masked()[t].size()) * (11 + t);
    }
    for (const auto& axis : forest.coordinates())
    {
      h ^= checksum(axis.data(), axis.size() * sizeof(double)) * 13;
    }
    return h;
  };
  const std::uint64_t before = sum();
  auto htg = buildHyperTreeGrid(d);
  // Reading everything, including raw pointers, leaves the simulation untouched.
  for (int a = 0; a < htg->GetCellData()->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = htg->GetCellData()->GetArray(a);
    double range[2];
    array->GetRange(range, -1);
    array->GetVoidPointer(0);
  }
  EXPECT_EQ(sum(), before);
}

TEST(ZeroCopy, WritingThroughABorrowingArrayDetachesInsteadOfWritingTheSimulation)
{
  RandomForest forest(smallForest());
  const std::size_t n = forest.numberOfNodes();
  struct Cell
  {
    double rho;
    double pad;
  };
  std::vector<Cell> cells(n, Cell{2.0, 0.0});
  auto& d = forest.description();
  d.fields.push_back(FieldDescription::strided("rho", &cells[0].rho, sizeof(Cell), n));
  auto htg = buildHyperTreeGrid(d);
  vtkDataArray* rho = htg->GetCellData()->GetArray("rho");
  rho->SetComponent(1, 0, 99.0);
  EXPECT_EQ(rho->GetComponent(1, 0), 99.0);
  EXPECT_EQ(rho->GetComponent(2, 0), 2.0);
  EXPECT_EQ(cells[1].rho, 2.0);
}

TEST(ZeroCopy, OnlyRequestedFieldsAreWrapped)
{
  RandomForest forest(smallForest());
  const std::size_t n = forest.numberOfNodes();
  std::vector<double> a(n, 1.0), b(n, 2.0), c(n, 3.0);
  auto& d = forest.description();
  d.fields.push_back(FieldDescription::aos("a", a.data(), n));
  d.fields.push_back(FieldDescription::aos("b", b.data(), n));
  d.fields.push_back(FieldDescription::aos("c", c.data(), n));

  auto some = buildHyperTreeGrid(d, FieldRequest::only({"c", "a"}));
  ASSERT_EQ(some->GetCellData()->GetNumberOfArrays(), 2);
  EXPECT_NE(some->GetCellData()->GetArray("a"), nullptr);
  EXPECT_EQ(some->GetCellData()->GetArray("b"), nullptr);
  EXPECT_NE(some->GetCellData()->GetArray("c"), nullptr);

  auto none = buildHyperTreeGrid(d, FieldRequest::none());
  EXPECT_EQ(none->GetCellData()->GetNumberOfArrays(), 0);
  EXPECT_EQ(none->GetNumberOfCells(), static_cast<vtkIdType>(n));

  try
  {
    buildHyperTreeGrid(d, FieldRequest::only({"a", "temperature"}));
    FAIL() << "an unknown field name must be rejected";
  }
  catch (const InvalidForest& e)
  {
    EXPECT_NE(std::string(e.what()).find("'temperature'"), std::string::npos) << e.what();
  }
}

} // namespace
} // namespace canopy::testing
