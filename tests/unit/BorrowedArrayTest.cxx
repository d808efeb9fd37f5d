// The arrays Canopy hands to VTK for strided and leaves-only fields behave like
// ordinary vtkDataArrays under every generic operation VTK filters use, and
// never write simulation memory.
#include "RandomForest.h"

#include <canopy/HtgBuilder.h>

#include <gtest/gtest.h>
#include <vtkAOSDataArrayTemplate.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkIdList.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace canopy::testing
{
namespace
{

struct Record
{
  double u[3];
  std::int32_t tag;
};

class BorrowedArray : public ::testing::Test
{
protected:
  BorrowedArray() : Forest(options())
  {
    const std::size_t n = Forest.numberOfNodes();
    Records.resize(n);
    // Zero the padding too: the checksum reads every byte.
    std::memset(static_cast<void*>(Records.data()), 0, n * sizeof(Record));
    for (std::size_t i = 0; i < n; ++i)
    {
      Records[i].u[0] = 1.0 * i;
      Records[i].u[1] = -2.0 * i;
      Records[i].u[2] = 0.5 * i;
      Records[i].tag = static_cast<std::int32_t>(i);
    }
    Leaves.resize(2 * Forest.numberOfLeaves());
    for (std::size_t i = 0; i < Leaves.size(); ++i)
    {
      Leaves[i] = 3.0 * i;
    }
    auto& d = Forest.description();
    d.fields.push_back(FieldDescription::strided("u", &Records[0].u[0], sizeof(Record), n, 3));
    d.fields.push_back(FieldDescription::aos("leafPair", Leaves.data(), Forest.numberOfLeaves(), 2,
                                             Centering::LeavesOnly));
    Before = checksum(Records.data(), Records.size() * sizeof(Record)) ^
             checksum(Leaves.data(), Leaves.size() * sizeof(double));
    Htg = buildHyperTreeGrid(d);
  }

  static RandomForestOptions options()
  {
    RandomForestOptions o;
    o.rootCells = {{2, 2, 2}};
    o.maxLevels = 3;
    o.seed = 3;
    return o;
  }

  vtkDataArray* array(const char* name) { return Htg->GetCellData()->GetArray(name); }

  void expectSimulationUntouched()
  {
    EXPECT_EQ(checksum(Records.data(), Records.size() * sizeof(Record)) ^
                  checksum(Leaves.data(), Leaves.size() * sizeof(double)),
              Before);
  }

  RandomForest Forest;
  std::vector<Record> Records;
  std::vector<double> Leaves;
  std::uint64_t Before = 0;
  vtkSmartPointer<vtkHyperTreeGrid> Htg;
};

TEST_F(BorrowedArray, GetTupleReturnsEveryComponent)
{
  vtkDataArray* u = array("u");
  ASSERT_EQ(u->GetNumberOfComponents(), 3);
  for (vtkIdType i = 0; i < u->GetNumberOfTuples(); ++i)
  {
    const double* t = u->GetTuple3(i);
    ASSERT_EQ(t[0], 1.0 * i);
    ASSERT_EQ(t[1], -2.0 * i);
    ASSERT_EQ(t[2], 0.5 * i);
    double buffer[3];
    u->GetTuple(i, buffer);
    ASSERT_EQ(buffer[2], 0.5 * i);
  }
  vtkDataArray* pair = array("leafPair");
  ASSERT_EQ(pair->GetNumberOfComponents(), 2);
  const double* t = pair->GetTuple2(pair->GetNumberOfTuples() - 1);
  EXPECT_TRUE(std::isfinite(t[0]) && std::isfinite(t[1]));
  expectSimulationUntouched();
}

TEST_F(BorrowedArray, NewInstanceIsAnOrdinaryWritableArray)
{
  vtkDataArray* u = array("u");
  vtkSmartPointer<vtkDataArray> copy = vtkSmartPointer<vtkDataArray>::Take(u->NewInstance());
  EXPECT_NE(vtkAOSDataArrayTemplate<double>::SafeDownCast(copy), nullptr) << copy->GetClassName();
  copy->DeepCopy(u);
  EXPECT_EQ(copy->GetNumberOfTuples(), u->GetNumberOfTuples());
  EXPECT_EQ(copy->GetComponent(5, 1), -10.0);
  copy->SetComponent(5, 1, 42.0);
  EXPECT_NE(copy->GetVoidPointer(0), nullptr);
  EXPECT_EQ(Records[5].u[1], -10.0);
  // GetTuples into a new instance (what writers and extractors do).
  vtkNew<vtkIdList> ids;
  ids->InsertNextId(7);
  ids->InsertNextId(2);
  vtkSmartPointer<vtkDataArray> picked = vtkSmartPointer<vtkDataArray>::Take(u->NewInstance());
  picked->SetNumberOfComponents(3);
  picked->SetNumberOfTuples(2);
  u->GetTuples(ids, picked);
  EXPECT_EQ(picked->GetComponent(0, 0), 7.0);
  EXPECT_EQ(picked->GetComponent(1, 2), 1.0);
  expectSimulationUntouched();
}

TEST_F(BorrowedArray, GetTuplesGathersWhatGetComponentReads)
{
  // The typed gather (the filters' output fields) against the generic reads, for
  // a strided field and a leaves-only one (its coarse cells read computed means),
  // every cell in reverse order, into an AoS array of the same type.
  for (const char* name : {"u", "leafPair"})
  {
    vtkDataArray* source = array(name);
    vtkNew<vtkIdList> ids;
    for (vtkIdType cell = source->GetNumberOfTuples(); cell-- > 0;)
    {
      ids->InsertNextId(cell);
    }
    vtkSmartPointer<vtkDataArray> picked =
        vtkSmartPointer<vtkDataArray>::Take(source->NewInstance());
    picked->SetNumberOfComponents(source->GetNumberOfComponents());
    picked->SetNumberOfTuples(ids->GetNumberOfIds());
    source->GetTuples(ids, picked);
    for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i)
    {
      for (int c = 0; c < source->GetNumberOfComponents(); ++c)
      {
        ASSERT_EQ(picked->GetComponent(i, c), source->GetComponent(ids->GetId(i), c))
            << name << " cell " << ids->GetId(i) << " component " << c;
      }
    }
  }
  expectSimulationUntouched();
}

TEST_F(BorrowedArray, ReshapingAndGrowingDetachWithoutTouchingTheSimulation)
{
  vtkDataArray* u = array("u");
  const vtkIdType tuples = u->GetNumberOfTuples();
  u->SetNumberOfComponents(4); // wider than the borrow: must not read past it
  EXPECT_EQ(u->GetNumberOfComponents(), 4);
  u->SetNumberOfComponents(3);
  vtkDataArray* pair = array("leafPair");
  const double last = pair->GetComponent(pair->GetNumberOfTuples() - 1, 1);
  pair->InsertNextTuple2(1.5, 2.5);
  EXPECT_EQ(pair->GetComponent(pair->GetNumberOfTuples() - 2, 1), last);
  EXPECT_EQ(pair->GetComponent(pair->GetNumberOfTuples() - 1, 0), 1.5);
  pair->Resize(3);
  EXPECT_EQ(pair->GetNumberOfTuples(), 3);
  u->Initialize();
  EXPECT_EQ(u->GetNumberOfTuples(), 0);
  EXPECT_GT(tuples, 0);
  expectSimulationUntouched();
}

TEST_F(BorrowedArray, DeepCopyIntoABorrowingArrayReplacesTheBorrow)
{
  vtkDataArray* u = array("u");
  vtkNew<vtkDoubleArray> other;
  other->SetNumberOfComponents(2);
  other->SetNumberOfTuples(4);
  other->Fill(9.0);
  u->DeepCopy(other);
  EXPECT_EQ(u->GetNumberOfComponents(), 2);
  EXPECT_EQ(u->GetNumberOfTuples(), 4);
  EXPECT_EQ(u->GetComponent(3, 1), 9.0);
  expectSimulationUntouched();
}

TEST_F(BorrowedArray, SixtyFourBitIntegersReportOneVtkTypeInEveryLayout)
{
  const std::size_t n = Forest.numberOfNodes();
  std::vector<std::int64_t> a(n, 1), b(n, 2);
  struct R
  {
    std::int64_t id;
    float pad;
  };
  std::vector<R> r(n, R{3, 0.f});
  auto& d = Forest.description();
  d.fields.clear();
  d.fields.push_back(FieldDescription::aos("aos", a.data(), n));
  d.fields.push_back(FieldDescription::soa<std::int64_t>("soa", {a.data(), b.data()}, n));
  d.fields.push_back(FieldDescription::strided("strided", &r[0].id, sizeof(R), n));
  auto htg = buildHyperTreeGrid(d);
  for (const char* name : {"aos", "soa", "strided"})
  {
    EXPECT_EQ(htg->GetCellData()->GetArray(name)->GetDataType(), VTK_LONG_LONG) << name;
  }
  EXPECT_EQ(htg->GetCellData()->GetArray("strided")->GetComponent(1, 0), 3.0);
}

TEST_F(BorrowedArray, RangesEqualThoseOfAnOrdinaryCopy)
{
  // Canopy's arrays compute their ranges themselves (VTK's generic path is slow):
  // the same values as VTK gives an ordinary array, with NaN, infinities and ghosts.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  Records[1].u[1] = nan;
  Records[2].u[0] = inf;
  Records[3].u[2] = -inf;
  Leaves[4] = nan;
  Leaves[5] = -inf;
  Before = checksum(Records.data(), Records.size() * sizeof(Record)) ^
           checksum(Leaves.data(), Leaves.size() * sizeof(double));
  for (const char* name : {"u", "leafPair"})
  {
    SCOPED_TRACE(name);
    vtkDataArray* borrowed = array(name);
    ASSERT_NE(borrowed, nullptr);
    borrowed->Modified(); // the simulation's values changed after the build
    vtkNew<vtkDoubleArray> copy;
    copy->DeepCopy(borrowed);
    const int components = borrowed->GetNumberOfComponents();
    std::vector<unsigned char> ghosts(static_cast<std::size_t>(borrowed->GetNumberOfTuples()), 0);
    for (std::size_t t = 0; t < ghosts.size(); t += 3)
    {
      ghosts[t] = 1;
    }
    for (int c = -1; c < components; ++c)
    {
      SCOPED_TRACE(c);
      double expected[2], actual[2];
      copy->GetRange(expected, c);
      borrowed->GetRange(actual, c);
      EXPECT_EQ(actual[0], expected[0]);
      EXPECT_EQ(actual[1], expected[1]);
      copy->GetFiniteRange(expected, c);
      borrowed->GetFiniteRange(actual, c);
      EXPECT_EQ(actual[0], expected[0]);
      EXPECT_EQ(actual[1], expected[1]);
    }
    for (int c = -1; c < components; ++c)
    {
      SCOPED_TRACE(c);
      // VTK 9.2's GetRange(range, component, ghosts, ...) hands `range` itself to
      // ComputeScalarRange, which fills every component's range: room for all
      // (AddressSanitizer caught the overflow of a two-value buffer).
      std::vector<double> expectedAll(2 * static_cast<std::size_t>(components));
      std::vector<double> actualAll(2 * static_cast<std::size_t>(components));
      double* expected = expectedAll.data();
      double* actual = actualAll.data();
      copy->GetRange(expected, c, ghosts.data(), 1);
      borrowed->GetRange(actual, c, ghosts.data(), 1);
      EXPECT_DOUBLE_EQ(actual[0], expected[0]);
      EXPECT_DOUBLE_EQ(actual[1], expected[1]);
      copy->GetFiniteRange(expected, c, ghosts.data(), 1);
      borrowed->GetFiniteRange(actual, c, ghosts.data(), 1);
      EXPECT_DOUBLE_EQ(actual[0], expected[0]);
      EXPECT_DOUBLE_EQ(actual[1], expected[1]);
    }
  }
  expectSimulationUntouched();
}

} // namespace
} // namespace canopy::testing
