#include "media/dense_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace farm {
namespace {

const Bounds3 kBox{{0, 0, 0}, {2, 2, 2}};

// 4 x 4 x 4 cells of density 0.5 but one corner cell of 2, the majorant: along the ray at
// y = z = 0.75 (the second cells' centres) the corner's interpolation never reaches, so
// the density the ray meets is 0.5 throughout while three in four tentative collisions are
// null ones.
DenseGrid ConstantAlongTheRay() {
  std::vector<float> values(64, 0.5f);
  values[(3 * 4 + 3) * 4 + 0] = 2;  // x = 0, y = 3, z = 3
  return DenseGrid(4, 4, 4, values, kBox);
}

UniformSource Uniforms(std::mt19937& rng) {
  return [&rng] { return std::uniform_real_distribution<float>(0, 1)(rng); };
}

// The fraction of delta-tracked flights that cross the box is a binomial estimate of the
// transmittance exp(-sigma L) = exp(-0.5 * 2): with n = 500000 flights its relative
// standard deviation is sqrt((1 - T) / (T n)) = 0.19%, so 1% is more than 5 of them.
TEST(DeltaTracking, ConstantDensityMatchesBeerLambertWithinOnePercent) {
  const DenseGrid grid = ConstantAlongTheRay();
  ASSERT_EQ(grid.max_density(), 2);
  ASSERT_FLOAT_EQ(grid.Density({1, 0.75f, 0.75f}), 0.5f);
  std::mt19937 rng(15);
  const UniformSource u = Uniforms(rng);
  const Ray ray{{-1, 0.75f, 0.75f}, {1, 0, 0}};
  const int n = 500000;
  int passed = 0;
  for (int i = 0; i < n; ++i) {
    const std::optional<float> hit = DeltaTrack(grid, 1, ray, 10, u);
    if (!hit) {
      ++passed;
    } else {
      ASSERT_GE(*hit, 1.0f);  // collisions happen inside the box only
      ASSERT_LE(*hit, 3.0f);
    }
  }
  const double want = std::exp(-1.0);
  EXPECT_NEAR(double(passed) / n / want, 1.0, 0.01);
}

// Along a density that grows linearly between the first and the last cell centres in x
// (trilinear interpolation is exact for it), from centre to centre: the optical depth is
// the length times the mean of the end values.
TEST(RatioTracking, LinearRampMatchesTheClosedFormWithinOnePercent) {
  std::vector<float> values(4 * 2 * 2);
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 4; ++x) values[(z * 2 + y) * 4 + x] = 0.2f + 0.6f * float(x);  // 0.2 .. 2
  const DenseGrid grid(4, 2, 2, values, kBox);
  const float first = 0.25f, last = 1.75f;  // cell centres in x
  const Ray ray{{first, 1, 1}, {1, 0, 0}};
  const double depth = 3.0 * (last - first) * (0.2 + 2.0) / 2;  // sigma_scale 3
  std::mt19937 rng(16);
  const UniformSource u = Uniforms(rng);
  const int n = 200000;
  double sum = 0;
  for (int i = 0; i < n; ++i) sum += RatioTrackTransmittance(grid, 3, ray, last - first, u);
  EXPECT_NEAR(sum / n / std::exp(-depth), 1.0, 0.01);
}

TEST(DenseGrid, OutsideTheBoxIsEmptyAndBadGridsAreRefused) {
  const DenseGrid grid = ConstantAlongTheRay();
  EXPECT_EQ(grid.Density({-0.1f, 1, 1}), 0);
  std::mt19937 rng(17);
  EXPECT_FALSE(DeltaTrack(grid, 1, Ray{{-1, 5, 1}, {1, 0, 0}}, 10, Uniforms(rng))) << "misses the box";
  EXPECT_THROW(DenseGrid(2, 2, 2, std::vector<float>(7, 1), kBox), std::invalid_argument);
  EXPECT_THROW(DenseGrid(1, 1, 1, {-1}, kBox), std::invalid_argument);
  EXPECT_THROW(DenseGrid(1, 1, 1, {1}, Bounds3{{0, 0, 0}, {0, 1, 1}}), std::invalid_argument);
}

}  // namespace
}  // namespace farm
