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
    const std::optional<float> hit = DeltaTrack(grid, 1, ray, 0, 10, u);
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
// the length times the mean of the end values; through the clamped half cells at the faces
// the density is the end values'. Integrated exactly, to rounding.
TEST(OpticalDepth, LinearRampMatchesTheClosedForm) {
  std::vector<float> values(4 * 2 * 2);
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 4; ++x) values[(z * 2 + y) * 4 + x] = 0.2f + 0.6f * float(x);  // 0.2 .. 2
  const DenseGrid grid(4, 2, 2, values, kBox);
  const float first = 0.25f, last = 1.75f;  // cell centres in x
  EXPECT_NEAR(OpticalDepth(grid, Ray{{first, 1, 1}, {1, 0, 0}}, 0, last - first), (last - first) * (0.2 + 2.0) / 2,
              1e-6);
  // The whole box from outside: 0.25 of 0.2, the ramp, 0.25 of 2.
  EXPECT_NEAR(OpticalDepth(grid, Ray{{-1, 1, 1}, {1, 0, 0}}, 0, 10), 0.25 * 0.2 + 1.5 * 1.1 + 0.25 * 2, 1e-6);
}

TEST(DenseGrid, OutsideTheBoxIsEmptyAndBadGridsAreRefused) {
  const DenseGrid grid = ConstantAlongTheRay();
  EXPECT_EQ(grid.Density({-0.1f, 1, 1}), 0);
  std::mt19937 rng(17);
  EXPECT_FALSE(DeltaTrack(grid, 1, Ray{{-1, 5, 1}, {1, 0, 0}}, 0, 10, Uniforms(rng))) << "misses the box";
  EXPECT_THROW(DenseGrid(2, 2, 2, std::vector<float>(7, 1), kBox), std::invalid_argument);
  EXPECT_THROW(DenseGrid(1, 1, 1, {-1}, kBox), std::invalid_argument);
  EXPECT_THROW(DenseGrid(1, 1, 1, {1}, Bounds3{{0, 0, 0}, {0, 1, 1}}), std::invalid_argument);
}

// A sparse grid: 40 x 24 x 24 cells, empty but for a blob of density 3 in one corner
// brick and a thin wisp of 0.05 elsewhere, seen along random rays. The bricks' spans tile
// the ray's part inside the box without gap or overlap, in order, and every point of a
// span has a density under its brick's majorant; most bricks are empty.
DenseGrid Sparse() {
  const int nx = 40, ny = 24, nz = 24;
  std::vector<float> values(std::size_t(nx) * ny * nz, 0.0f);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        float& v = values[(std::size_t(z) * ny + y) * nx + x];
        if (x < 6 && y < 6 && z < 6) v = 3;
        if (x > 30 && y > 10 && y < 14) v = 0.05f;
      }
  return DenseGrid(nx, ny, nz, values, Bounds3{{-2, 0, 0}, {2, 1.2f, 2.4f}});
}

TEST(DenseGridWalk, SpansTileTheRayInOrderUnderTheirMajorants) {
  const DenseGrid grid = Sparse();
  std::mt19937 rng(18);
  std::uniform_real_distribution<float> coord(-3, 3);
  int empty = 0, spans = 0, checked = 0;
  for (int r = 0; r < 200; ++r) {
    const Vec3 o(coord(rng), coord(rng), coord(rng));
    const Vec3 target(coord(rng) / 1.5f, coord(rng) / 5 + 0.6f, coord(rng) / 2.5f + 1.2f);
    const Ray ray{o, Normalize(target - o)};
    DenseGrid::Walk walk(grid, ray, 0, 100);
    float previous = -1;
    for (DenseGrid::Span span; walk.Next(span);) {
      ++spans;
      if (previous >= 0) {
        EXPECT_EQ(span.t0, previous) << "a gap or an overlap";
      }
      EXPECT_LE(span.t0, span.t1);
      previous = span.t1;
      empty += span.majorant == 0;
      for (int i = 0; i <= 8; ++i) {
        const float t = span.t0 + (span.t1 - span.t0) * float(i) / 8;
        ASSERT_LE(grid.Density(ray.At(t)), span.majorant) << "t " << t;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(empty, spans / 2) << "most bricks of sparse smoke are empty";
}

// Through the blob and the wisp at once, along a slanted ray (every kind of piece and
// clamp): the exact optical depth against the midpoint rule on 200,000 steps (relative
// error far below 1e-4 for a piecewise cubic), and delta tracking's pass fraction against
// its exponential.
TEST(DenseGridWalk, DepthAndFlightsThroughSparseSmokeMatchQuadrature) {
  const DenseGrid grid = Sparse();
  const Ray ray{{-3, 0.1f, 0.1f}, Normalize(Vec3(5, 0.52f, 0.1f))};
  const float t_max = 8;
  double quadrature = 0;
  const int steps = 200000;
  for (int i = 0; i < steps; ++i) quadrature += grid.Density(ray.At((float(i) + 0.5f) * t_max / steps));
  quadrature *= t_max / steps;
  const double depth = OpticalDepth(grid, ray, 0, t_max);
  EXPECT_NEAR(depth / quadrature, 1.0, 1e-4);
  const double want = std::exp(-0.7 * depth);  // sigma_scale 0.7
  ASSERT_GT(want, 0.2);
  ASSERT_LT(want, 0.8);
  std::mt19937 rng(19);
  const UniformSource u = Uniforms(rng);
  const int n = 400000;
  int passed = 0;
  for (int i = 0; i < n; ++i) passed += !DeltaTrack(grid, 0.7f, ray, 0, t_max, u);
  // Binomial: the relative standard deviation sqrt((1 - T) / (T n)) is below 0.25% here.
  EXPECT_NEAR(double(passed) / n / want, 1.0, 0.01);
}

// The truncated free flight through sparse smoke inverts the exact optical depth: the
// k-th of n stratified samples lands where the truncated CDF (1 - T(t)) / (1 - T(end)) is
// (k + 1/2) / n, and its pdf is sigma_t(t) T(t) / (1 - T(end)), so that sigma_t T / pdf is
// the same 1 - T(end) for every sample (no noise of its own), each inside the stretch; its
// density at any t (TruncatedFlightPdf) is that pdf.
TEST(DenseGridWalk, TruncatedFlightsInvertTheExactDepth) {
  const DenseGrid grid = Sparse();
  const Ray ray{{-3, 0.1f, 0.1f}, Normalize(Vec3(5, 0.52f, 0.1f))};
  const float t_min = 0.5f, t_max = 7, scale = 0.7f;
  const double mass = -std::expm1(-scale * OpticalDepth(grid, ray, t_min, t_max));
  const int n = 2000;
  for (int k = 0; k < n; ++k) {
    const float u = (float(k) + 0.5f) / n;
    const std::optional<DistanceSample> d = SampleTruncatedFlight(grid, scale, ray, t_min, t_max, u);
    ASSERT_TRUE(d) << u;
    ASSERT_GE(d->t, t_min);
    ASSERT_LE(d->t, t_max);
    const double transmittance = std::exp(-scale * OpticalDepth(grid, ray, t_min, d->t));
    ASSERT_NEAR((1 - transmittance) / mass, u, 1e-4) << "t " << d->t;
    ASSERT_NEAR(scale * grid.Density(ray.At(d->t)) * transmittance / d->pdf / mass, 1.0, 1e-3) << "t " << d->t;
    // The density MIS weighs other strategies' distances against is the sampler's.
    ASSERT_NEAR(TruncatedFlightPdf(grid, scale, ray, t_min, t_max, d->t) / d->pdf, 1.0, 1e-4) << "t " << d->t;
  }
  // A density over the stretch: it integrates to 1 (midpoint rule), and is 0 outside.
  double integral = 0;
  const int steps = 20000;
  for (int i = 0; i < steps; ++i)
    integral += TruncatedFlightPdf(grid, scale, ray, t_min, t_max, t_min + (float(i) + 0.5f) * (t_max - t_min) / steps);
  EXPECT_NEAR(integral * (t_max - t_min) / steps, 1.0, 1e-3);
  EXPECT_EQ(TruncatedFlightPdf(grid, scale, ray, t_min, t_max, t_min - 0.01f), 0);
  EXPECT_EQ(TruncatedFlightPdf(grid, scale, ray, t_min, t_max, t_max + 0.01f), 0);
  EXPECT_FALSE(SampleTruncatedFlight(grid, scale, Ray{{-3, 1.1f, 2.3f}, {1, 0, 0}}, 0, 1, 0.5f))
      << "outside the box: nothing to land on";
}

}  // namespace
}  // namespace farm
