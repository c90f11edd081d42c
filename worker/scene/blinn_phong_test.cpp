#include "scene/blinn_phong.h"

#include <gtest/gtest.h>

#include <cmath>

#include "math/math.h"
#include "sampling/sobol.h"
#include "sampling/warps.h"
#include "scene/test_directions.h"

namespace farm {
namespace {

TEST(BlinnPhong, PdfIntegratesToTheShareOfSamplesAboveTheHorizon) {
  // The density over the sphere of reflected half-vector samples integrates to 1; the part
  // below the horizon is the share of samples SampleBlinnPhong refuses.
  for (float exponent : {1.0f, 10.0f, 60.0f}) {
    for (float theta : {0.0f, 45.0f, 80.0f}) {
      const Vec3 wo = Dir(theta);
      const int n = 1 << 20;
      double integral = 0;
      int accepted = 0;
      for (int i = 0; i < n; ++i) {
        const Vec3 w = SampleUniformSphere(Sobol2(i, 11));
        integral += BlinnPhongPdf(wo, w, exponent) / UniformSpherePdf();
        if (SampleBlinnPhong(wo, Sobol2(i, 5), exponent)) ++accepted;
      }
      integral /= n;
      EXPECT_NEAR(integral, double(accepted) / n, 4e-3)
          << "exponent " << exponent << " theta " << theta;
      if (theta == 0 && exponent >= 60) {  // (cos 45)^(e+1) of the lobe falls below
        EXPECT_NEAR(integral, 1.0, 4e-3);
      }
    }
  }
}

TEST(BlinnPhong, AlbedoIsAtMostOneAndMatchesTheSampleWeights) {
  // White furnace: the integral of f cos over the hemisphere, by uniform sampling, is <= 1,
  // and equals the mean weight f cos / pdf of the lobe's own samples.
  for (float exponent : {1.0f, 5.0f, 40.0f}) {
    for (float theta : {0.0f, 30.0f, 60.0f, 85.0f}) {
      const Vec3 wo = Dir(theta);
      const int n = 1 << 20;
      double uniform = 0, sampled = 0;
      for (int i = 0; i < n; ++i) {
        const Vec3 w = SampleUniformSphere(Sobol2(i, 3));
        if (w.z > 0) uniform += BlinnPhongValue(wo, w, exponent) * w.z / UniformSpherePdf();
        if (const auto s = SampleBlinnPhong(wo, Sobol2(i, 9), exponent)) {
          const float pdf = BlinnPhongPdf(wo, *s, exponent);
          ASSERT_GT(pdf, 0);
          const double weight = BlinnPhongValue(wo, *s, exponent) * s->z / pdf;
          ASSERT_LE(weight, 1 + 1e-5);
          sampled += weight;
        }
      }
      uniform /= n;
      sampled /= n;
      EXPECT_LE(uniform, 1.0 + 3e-3) << "exponent " << exponent << " theta " << theta;
      EXPECT_LE(sampled, 1.0);
      EXPECT_NEAR(uniform, sampled, 5e-3 + 0.01 * sampled)
          << "exponent " << exponent << " theta " << theta;
    }
  }
}

TEST(BlinnPhong, IsReciprocal) {
  const Vec3 a = Normalize(Vec3(0.3f, 0.2f, 0.9f)), b = Normalize(Vec3(-0.5f, 0.1f, 0.6f));
  EXPECT_FLOAT_EQ(BlinnPhongValue(a, b, 20), BlinnPhongValue(b, a, 20));
  EXPECT_EQ(BlinnPhongValue(a, Vec3(0, 0, -1), 20), 0.0f);
}

}  // namespace
}  // namespace farm
