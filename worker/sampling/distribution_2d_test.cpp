#include "sampling/distribution_2d.h"

#include <gtest/gtest.h>

#include <vector>

namespace farm {
namespace {

// A 4x2 grid: row 0 holds 1, 0, 2, 1 and row 1 holds 0, 0, 4, 0 (total 8).
const std::vector<float> kWeights = {1, 0, 2, 1, 0, 0, 4, 0};

TEST(Distribution2D, DensityIsTheWeightOverTheCellArea) {
  const Distribution2D d(kWeights, 4, 2);
  SCOPED_TRACE(d.ToString());
  // Cell area 1/8: density = (weight / 8) / (1 / 8) = weight.
  EXPECT_FLOAT_EQ(d.Pdf({0.1f, 0.2f}), 1);
  EXPECT_FLOAT_EQ(d.Pdf({0.3f, 0.2f}), 0);
  EXPECT_FLOAT_EQ(d.Pdf({0.6f, 0.9f}), 4);
  EXPECT_DOUBLE_EQ(d.total(), 8);
}

TEST(Distribution2D, SamplesLandInProportionToWeightWithTheirDensity) {
  const Distribution2D d(kWeights, 4, 2);
  std::vector<int> count(8, 0);
  const int n = 64;  // n x n stratified points
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Distribution2D::Sample s = d.Draw({(i + 0.5f) / n, (j + 0.5f) / n});
      ASSERT_GE(s.uv.x, 0);
      ASSERT_LT(s.uv.x, 1);
      ASSERT_GE(s.uv.y, 0);
      ASSERT_LT(s.uv.y, 1);
      EXPECT_FLOAT_EQ(s.pdf, d.Pdf(s.uv));
      ++count[int(s.uv.y * 2) * 4 + int(s.uv.x * 4)];
    }
  for (int c = 0; c < 8; ++c) EXPECT_EQ(count[c], int(kWeights[c] / 8 * n * n)) << "cell " << c;
}

TEST(Distribution2D, ZeroWeightsAreUniform) {
  const std::vector<float> zero(6, 0.0f);
  const Distribution2D d(zero, 3, 2);
  EXPECT_FLOAT_EQ(d.Pdf({0.5f, 0.5f}), 1);
  EXPECT_FLOAT_EQ(d.Draw({0.5f, 0.25f}).pdf, 1);
}

TEST(Distribution2D, RefusesAGridOfTheWrongSize) {
  EXPECT_THROW(Distribution2D(kWeights, 3, 2), std::invalid_argument);
}

}  // namespace
}  // namespace farm
