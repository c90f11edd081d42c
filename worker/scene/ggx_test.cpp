#include "scene/ggx.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "math/math.h"
#include "sampling/sobol.h"
#include "scene/fresnel.h"
#include "scene/test_directions.h"

namespace farm {
namespace {

// The direction of cell midpoint (i, j) of a grid of kCos x kPhi cells, uniform in cos theta
// over [-1, 1] and in phi: each cell has the solid angle 4 pi / (kCos kPhi).
constexpr int kCos = 2000, kPhi = 1000;
Vec3 Cell(int i, int j) {
  const float z = -1 + 2 * (i + 0.5f) / kCos, phi = 2 * kPi * (j + 0.5f) / kPhi;
  const float r = SafeSqrt(1 - z * z);
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// The alphas (roughness 0.3 to 1) and view angles the tests run through: narrower lobes
// need finer quadrature than these grids.
const float kAlphas[] = {0.09f, 0.25f, 0.5f, 1.0f};
const float kThetas[] = {0.0f, 40.0f, 75.0f};

// The normals' distribution is normalised as projected area: the integral of D(h) cos over
// the hemisphere is 1 (D is isotropic: a quadrature over cos theta alone).
TEST(Ggx, ProjectedNormalDistributionIntegratesToOne) {
  for (float alpha : {0.01f, 0.09f, 0.25f, 0.5f, 1.0f}) {
    constexpr int kCells = 1 << 20;
    double integral = 0;
    for (int i = 0; i < kCells; ++i) {
      const float z = (i + 0.5f) / kCells;
      integral += GgxD(Vec3(SafeSqrt(1 - z * z), 0, z), alpha) * z;
    }
    integral *= 2 * kPi / kCells;
    EXPECT_NEAR(integral, 1.0, 1e-3) << "alpha " << alpha;
  }
}

// The density of reflect(wo, h), h drawn by visible normals, integrates (by quadrature) to
// 1 over the sphere, and over the upper hemisphere to the share of samples that stay above
// the horizon (by sampling).
TEST(Ggx, ReflectionPdfIntegratesToOneAndToTheShareAboveTheHorizon) {
  for (float alpha : kAlphas) {
    for (float theta : kThetas) {
      const Vec3 wo = Dir(theta);
      double sphere = 0, upper = 0;
      for (int i = 0; i < kCos; ++i)
        for (int j = 0; j < kPhi; ++j) {
          const Vec3 wi = Cell(i, j);
          const double p = GgxReflectionPdf(wo, wi, alpha);
          sphere += p;
          if (wi.z > 0) upper += p;
        }
      const double cell = 4 * kPi / (double(kCos) * kPhi);
      sphere *= cell;
      upper *= cell;
      const int n = 1 << 18;
      int above = 0;
      for (int k = 0; k < n; ++k)
        if (Reflect(wo, SampleGgxVisibleNormal(wo, alpha, Sobol2(k, 3))).z > 0) ++above;
      EXPECT_NEAR(sphere, 1.0, 3e-3) << "alpha " << alpha << " theta " << theta;
      EXPECT_NEAR(upper, double(above) / n, 3e-3) << "alpha " << alpha << " theta " << theta;
    }
  }
}

// The sampled directions' histogram over the sphere matches the pdf: Pearson's chi-square
// over 16 x 32 cells (uniform in cos theta and phi; cells expecting fewer than 5 samples
// pooled into one) stays below its 0.1% critical value.
TEST(Ggx, SampledDirectionsFollowThePdf) {
  constexpr int kRows = 16, kCols = 32, kSub = 8, kSamples = 200000;
  for (float alpha : {0.25f, 0.6f}) {
    for (float theta : {20.0f, 70.0f}) {
      const Vec3 wo = Dir(theta);
      std::vector<double> observed(kRows * kCols, 0), expected(kRows * kCols, 0);
      for (int k = 0; k < kSamples; ++k) {
        const Vec3 wi = Reflect(wo, SampleGgxVisibleNormal(wo, alpha, Sobol2(k, 17)));
        const int row = std::clamp(int((wi.z + 1) / 2 * kRows), 0, kRows - 1);
        const float phi = std::atan2(wi.y, wi.x);
        const int col = std::clamp(int((phi < 0 ? phi + 2 * kPi : phi) / (2 * kPi) * kCols), 0, kCols - 1);
        observed[row * kCols + col] += 1;
      }
      const double sub_cell = 4 * kPi / (double(kRows) * kCols * kSub * kSub);
      for (int r = 0; r < kRows; ++r)
        for (int c = 0; c < kCols; ++c)
          for (int a = 0; a < kSub; ++a)
            for (int b = 0; b < kSub; ++b) {
              const float z = -1 + 2 * (r + (a + 0.5f) / kSub) / kRows;
              const float phi = 2 * kPi * (c + (b + 0.5f) / kSub) / kCols;
              const float s = SafeSqrt(1 - z * z);
              expected[r * kCols + c] += kSamples * sub_cell * GgxReflectionPdf(wo, {s * std::cos(phi), s * std::sin(phi), z}, alpha);
            }
      double chi2 = 0, pooled_observed = 0, pooled_expected = 0;
      int cells = 0;
      for (int k = 0; k < kRows * kCols; ++k) {
        if (expected[k] < 5) {
          pooled_observed += observed[k];
          pooled_expected += expected[k];
          continue;
        }
        chi2 += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
        ++cells;
      }
      if (pooled_expected >= 5) {
        chi2 += (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected) / pooled_expected;
        ++cells;
      } else {
        EXPECT_LT(pooled_observed, 20) << "samples where the pdf says there are none";
      }
      // Wilson and Hilferty's approximation of the chi-square quantile, z = 3.09 (0.1%).
      const double df = cells - 1, q = 1 - 2 / (9 * df) + 3.09 * std::sqrt(2 / (9 * df));
      EXPECT_LT(chi2, df * q * q * q) << "alpha " << alpha << " theta " << theta << ", " << cells << " cells";
    }
  }
}

TEST(Ggx, SampledNormalsAreVisibleAndUnit) {
  for (float alpha : {kMinGgxAlpha, 0.3f, 1.0f})
    for (float theta : {0.0f, 60.0f, 89.0f}) {
      const Vec3 wo = Dir(theta);
      for (uint32_t k = 0; k < 1000; ++k) {
        const Vec3 h = SampleGgxVisibleNormal(wo, alpha, Sobol2(k, 9));
        EXPECT_NEAR(Length(h), 1, 1e-5);
        EXPECT_GE(Dot(wo, h), -1e-6) << "a normal facing away from wo is never visible";
        EXPECT_GE(h.z, 0);
      }
    }
  // The narrowest lobe is a mirror.
  const Vec3 wo = Dir(30);
  EXPECT_GT(Dot(Reflect(wo, SampleGgxVisibleNormal(wo, kMinGgxAlpha, {0.7f, 0.2f})), Vec3(-wo.x, -wo.y, wo.z)), 1 - 1e-6);
}

TEST(Ggx, MaskingIsOneHeadOnAndFallsTowardsTheHorizon) {
  EXPECT_FLOAT_EQ(GgxG1(Vec3(0, 0, 1), 0.5f), 1);
  EXPECT_GT(GgxG1(Dir(45), 0.5f), GgxG1(Dir(80), 0.5f));
  EXPECT_EQ(GgxG1(Dir(90.5f), 0.5f), 0) << "below the horizon nothing is seen";
  EXPECT_FLOAT_EQ(GgxG2(Dir(30), Dir(60), 0.4f), GgxG2(Dir(60), Dir(30), 0.4f));
  EXPECT_GT(GgxG2(Dir(30), Dir(60), 0.4f), GgxG1(Dir(30), 0.4f) * GgxG1(Dir(60), 0.4f))
      << "height-correlated masking hides less than independent masking would";
}

}  // namespace
}  // namespace farm
