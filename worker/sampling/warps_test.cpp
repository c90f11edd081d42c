#include "sampling/warps.h"

#include <gtest/gtest.h>

#include <cmath>

#include "math/math.h"
#include "sampling/sobol.h"

namespace farm {
namespace {

Vec2 U(uint32_t i) { return {SobolSample(i, 0, 11), SobolSample(i, 1, 12)}; }

// Midpoint quadrature of f(direction) over the unit sphere in (cos theta, phi), which is
// area preserving, so each cell has solid angle 4 pi / (n * m).
template <typename F>
double IntegrateOverSphere(F f, int n = 2000, int m = 400) {
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double z = -1 + 2 * (i + 0.5) / n;
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    for (int j = 0; j < m; ++j) {
      const double phi = 2 * std::numbers::pi * (j + 0.5) / m;
      sum += f(Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)));
    }
  }
  return sum * 4 * std::numbers::pi / (double(n) * m);
}

TEST(Warps, TriangleBarycentricsAreUniformByArea) {
  const int n = 1 << 14;
  double mean0 = 0, mean1 = 0, below_half = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 b = SampleUniformTriangle(U(i));
    ASSERT_GE(b.x, 0);
    ASSERT_GE(b.y, 0);
    ASSERT_GE(b.z, -1e-6f);
    mean0 += b.x;
    mean1 += b.y;
    below_half += b.x < 0.5f;  // region b0 < 1/2 has 3/4 of the area
  }
  EXPECT_NEAR(mean0 / n, 1.0 / 3, 2e-3);
  EXPECT_NEAR(mean1 / n, 1.0 / 3, 2e-3);
  EXPECT_NEAR(below_half / n, 0.75, 2e-3);
}

TEST(Warps, ParallelogramCoversItsCorners) {
  const Vec3 o(1, 2, 3), eu(2, 0, 0), ev(1, 1, 0);
  EXPECT_EQ(SampleParallelogram(o, eu, ev, {0, 0}), o);
  EXPECT_EQ(SampleParallelogram(o, eu, ev, {1, 1}), o + eu + ev);
  EXPECT_EQ(SampleParallelogram(o, eu, ev, {0.5f, 0.5f}), o + (eu + ev) * 0.5f);
}

TEST(Warps, UniformSphereIsUnitAndCentred) {
  const int n = 1 << 12;
  Vec3d mean;
  for (int i = 0; i < n; ++i) {
    const Vec3 w = SampleUniformSphere(U(i));
    ASSERT_NEAR(Length(w), 1, 1e-5);
    mean += Vec3d(w);
  }
  EXPECT_NEAR(Length(mean / double(n)), 0, 5e-3);
  EXPECT_NEAR(IntegrateOverSphere([](Vec3) { return UniformSpherePdf(); }), 1, 1e-6);
}

TEST(Warps, ConeSamplesStayInTheConeWithTheRightMeanCosine) {
  const float cos_max = 0.8f;
  const int n = 1 << 12;
  double mean_cos = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 w = SampleUniformCone(U(i), cos_max);
    ASSERT_GE(w.z, cos_max - 1e-6f);
    mean_cos += w.z;
  }
  EXPECT_NEAR(mean_cos / n, (1 + cos_max) / 2, 1e-3);
  const double integral =
      IntegrateOverSphere([&](Vec3 w) { return w.z >= cos_max ? UniformConePdf(cos_max) : 0.0f; });
  EXPECT_NEAR(integral, 1, 5e-3);
}

TEST(Warps, CosineHemispherePdfIntegratesToOne) {
  const double integral = IntegrateOverSphere(
      [](Vec3 w) { return w.z > 0 ? CosineHemispherePdf(w.z) : 0.0f; });
  EXPECT_NEAR(integral, 1, 1e-3);
  const int n = 1 << 12;
  double mean_z = 0;  // E[cos] under cos/pi is 2/3
  for (int i = 0; i < n; ++i) {
    const Vec3 w = SampleCosineHemisphere(U(i));
    ASSERT_NEAR(Length(w), 1, 1e-5);
    ASSERT_GE(w.z, 0);
    mean_z += w.z;
  }
  EXPECT_NEAR(mean_z / n, 2.0 / 3, 1e-3);
}

TEST(Warps, SphereFromOutsideSamplesTheVisibleCap) {
  const Vec3 center(0, 0, 10), ref(0.5f, -0.2f, 0);
  const float radius = 3;
  const int n = 1 << 12;
  for (int i = 0; i < n; ++i) {
    const SphereSample s = SampleSphereFromPoint(center, radius, ref, U(i));
    ASSERT_TRUE(s.in_cone);
    ASSERT_NEAR(Distance(s.p, center), radius, 1e-4);
    // Faces ref (visible side), and the density matches the pdf query for its direction.
    const Vec3 w = Normalize(s.p - ref);
    ASSERT_LT(Dot(s.n, w), 1e-4f);
    ASSERT_NEAR(SphereFromPointPdf(center, radius, ref, w), s.pdf, 1e-3f * s.pdf);
  }
  // The density integrates to 1 over all directions, and 1/pdf is the cone's solid angle
  // 2 pi (1 - cos theta_max).
  const double integral =
      IntegrateOverSphere([&](Vec3 w) { return SphereFromPointPdf(center, radius, ref, w); });
  EXPECT_NEAR(integral, 1, 5e-3);
  const double d = Distance(Vec3d(center), Vec3d(ref));
  const double solid_angle = 2 * std::numbers::pi * (1 - std::sqrt(1 - radius * radius / (d * d)));
  EXPECT_NEAR(1 / SampleSphereFromPoint(center, radius, ref, {0.3f, 0.3f}).pdf, solid_angle,
              1e-4 * solid_angle);
}

TEST(Warps, DistantSphereKeepsPrecision) {
  // sin^2(theta_max) = 1e-8: 1 - cos(theta_max) in float would be 0 and the pdf infinite.
  const SphereSample s = SampleSphereFromPoint({0, 0, 1e4f}, 1, {0, 0, 0}, {0.5f, 0.5f});
  const double expected = 1 / (2 * std::numbers::pi * 0.5e-8);
  EXPECT_TRUE(std::isfinite(s.pdf));
  EXPECT_NEAR(s.pdf, expected, 1e-4 * expected);
  EXPECT_NEAR(Distance(s.p, Vec3(0, 0, 1e4f)), 1, 1e-2);
  EXPECT_LT(s.p.z, 1e4f);
}

TEST(Warps, SphereFromInsideFallsBackToAreaSampling) {
  const Vec3 center(1, 2, 3), ref(1.5f, 2, 3);
  const float radius = 2;
  const SphereSample s = SampleSphereFromPoint(center, radius, ref, {0.25f, 0.75f});
  EXPECT_FALSE(s.in_cone);
  EXPECT_NEAR(Distance(s.p, center), radius, 1e-5);
  EXPECT_GT(s.pdf, 0);
  const double integral =
      IntegrateOverSphere([&](Vec3 w) { return SphereFromPointPdf(center, radius, ref, w); });
  EXPECT_NEAR(integral, 1, 5e-3);
}

}  // namespace
}  // namespace farm
