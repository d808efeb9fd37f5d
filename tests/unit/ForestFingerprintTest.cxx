// tools/ForestFingerprint: what the benchmarks print to trace a figure to its
// input. The same input gives the same fingerprint; any bit of its refinement,
// mask or values a different one, whatever the layout the values are read in.
#include "ForestFingerprint.h"
#include "SyntheticForest.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

namespace
{

canopy::tools::SyntheticForestOptions smallForest()
{
  canopy::tools::SyntheticForestOptions o;
  o.dimension = 3;
  o.rootsPerAxis = 3;
  o.maxLevels = 4;
  return o;
}

TEST(ForestFingerprint, TheSameInputTheSameFingerprint)
{
  const canopy::tools::SyntheticForest a(smallForest());
  const canopy::tools::SyntheticForest b(smallForest());
  EXPECT_EQ(canopy::tools::forestFingerprint(a.description()),
            canopy::tools::forestFingerprint(b.description()));
  auto other = smallForest();
  other.maxLevels = 5;
  const canopy::tools::SyntheticForest c(other);
  EXPECT_NE(canopy::tools::forestFingerprint(a.description()),
            canopy::tools::forestFingerprint(c.description()));
}

TEST(ForestFingerprint, OneRefinementBitOrOneValueChangesIt)
{
  const canopy::tools::SyntheticForest forest(smallForest());
  const canopy::ForestDescription& original = forest.description();
  const std::uint64_t reference = canopy::tools::forestFingerprint(original);

  canopy::ForestDescription refined = original;
  std::vector<std::uint8_t> bits(original.trees[1].refinement,
                                 original.trees[1].refinement + original.trees[1].numberOfNodes);
  bits.back() ^= 1;
  refined.trees[1].refinement = bits.data();
  EXPECT_NE(canopy::tools::forestFingerprint(refined), reference);

  // The last value of "pressure" (stored AoS), in a copy read as AoS and as strided.
  std::size_t f = 0;
  while (f < original.fields.size() && original.fields[f].name != "pressure")
  {
    ++f;
  }
  ASSERT_LT(f, original.fields.size());
  const canopy::FieldDescription& field = original.fields[f];
  ASSERT_EQ(field.layout, canopy::Layout::AoS);
  ASSERT_EQ(field.type, canopy::ValueType::Float64);
  const std::size_t count = field.numberOfTuples * static_cast<std::size_t>(field.components);
  std::vector<double> values(static_cast<const double*>(field.data),
                             static_cast<const double*>(field.data) + count);
  canopy::ForestDescription copied = original;
  copied.fields[f].data = values.data();
  EXPECT_EQ(canopy::tools::forestFingerprint(copied), reference) << "values, not addresses";
  values.back() = std::nextafter(values.back(), 1e300);
  EXPECT_NE(canopy::tools::forestFingerprint(copied), reference);

  canopy::ForestDescription strided = copied;
  strided.fields[f].layout = canopy::Layout::Strided;
  strided.fields[f].tupleStrideBytes = sizeof(double) * static_cast<std::size_t>(field.components);
  EXPECT_EQ(canopy::tools::forestFingerprint(strided), canopy::tools::forestFingerprint(copied))
      << "the same values in another layout";
}

} // namespace
