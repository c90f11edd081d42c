#include "media/equiangular.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "media/test_quadrature.h"

namespace farm {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Samples stay on the segment and their density is proportional to 1 / |x(t) - p|^2 with
// the constant that makes it integrate to 1 over the segment.
TEST(Equiangular, DensityIsTheNormalisedInverseSquare) {
  const Vec3 origin(0, 0, 0), dir = Normalize(Vec3(1, 0.2f, 0));
  const Vec3 light(2, 1.5f, -0.5f);
  const float t0 = 0.1f, t1 = 6;
  const double mass = testing::Simpson(
      [&](double t) { return 1 / double(LengthSquared(origin + dir * float(t) - light)); }, t0, t1);
  for (const float u : {0.0f, 0.2f, 0.5f, 0.9f, 0.999f}) {
    const std::optional<DistanceSample> s = SampleEquiangular(origin, dir, t0, t1, light, u);
    ASSERT_TRUE(s);
    EXPECT_GE(s->t, t0);
    EXPECT_LE(s->t, t1);
    const double want = 1 / (double(LengthSquared(origin + dir * s->t - light)) * mass);
    EXPECT_NEAR(s->pdf / want, 1.0, 1e-4) << "u=" << u;
  }
}

// A ray along the line through the light, moving away from it: the limit density
// 1 / (s^2 (1 / s0 - 1 / s1)), here with s1 infinite.
TEST(Equiangular, LightOnTheLineUsesTheLimit) {
  const Vec3 light(0, 0, -2);
  for (const float u : {0.0f, 0.5f, 0.99f}) {
    const std::optional<DistanceSample> s = SampleEquiangular(Vec3(0, 0, 0), Vec3(0, 0, 1), 0, kInf, light, u);
    ASSERT_TRUE(s);
    const double d = 2 + double(s->t);
    EXPECT_NEAR(s->pdf, 2 / (d * d), 1e-6 * (1 + s->pdf)) << "u=" << u;
  }
  EXPECT_FALSE(SampleEquiangular(Vec3(0, 0, -4), Vec3(0, 0, 1), 0, 10, light, 0.5f)) << "the segment crosses the light";
  EXPECT_FALSE(SampleEquiangular(Vec3(0, 0, 0), Vec3(0, 0, 1), 3, 3, light, 0.5f)) << "empty segment";
}

// EquiangularPdf gives the density the sampler reported at each sample, off and on the
// line, and 0 off the segment: it is what MIS weighs other strategies' distances against.
TEST(Equiangular, PdfAgreesWithTheSampler) {
  const Vec3 origin(0, 0, 0), dir = Normalize(Vec3(1, 0.2f, 0));
  for (const Vec3& light : {Vec3(2, 1.5f, -0.5f), origin - dir * 2.0f}) {  // off the line, on it
    for (const float t1 : {6.0f, kInf}) {
      for (const float u : {0.01f, 0.3f, 0.7f, 0.99f}) {
        const std::optional<DistanceSample> s = SampleEquiangular(origin, dir, 0.1f, t1, light, u);
        ASSERT_TRUE(s);
        EXPECT_NEAR(EquiangularPdf(origin, dir, 0.1f, t1, light, s->t) / s->pdf, 1.0, 1e-4) << "u=" << u;
      }
      EXPECT_EQ(EquiangularPdf(origin, dir, 0.1f, t1, light, 0.05f), 0.0f) << "before the segment";
    }
  }
  EXPECT_EQ(EquiangularPdf(origin, dir, 0.1f, 6, Vec3(2, 1.5f, -0.5f), 7), 0.0f) << "beyond the segment";
}

}  // namespace
}  // namespace farm
