#include "scene/fresnel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "math/math.h"

namespace farm {
namespace {

constexpr double kPiD = std::numbers::pi;

// Transmittance from the Fresnel amplitude transmission coefficients, independently of the
// reflectance: T = (eta cos_t / cos_i) |t|^2 for each polarisation (the power a plane wave
// carries through the interface per unit area of it), averaged.
double TransmittanceFromAmplitudes(double cos_i, double eta) {
  const double sin2_t = (1 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1) return 0;
  const double cos_t = std::sqrt(1 - sin2_t);
  const double t_perpendicular = 2 * cos_i / (cos_i + eta * cos_t);
  const double t_parallel = 2 * cos_i / (eta * cos_i + cos_t);
  const double factor = eta * cos_t / cos_i;
  return factor * (t_perpendicular * t_perpendicular + t_parallel * t_parallel) / 2;
}

TEST(Fresnel, DielectricNormalIncidenceIsSquaredIndexRatio) {
  for (float n : {1.33f, 1.5f, 2.42f, 4.0f}) {
    const float expected = Sqr((n - 1) / (n + 1));
    EXPECT_NEAR(FresnelDielectric(1, n), expected, 1e-6) << n;
    EXPECT_NEAR(FresnelDielectric(-1, n), expected, 1e-6) << n;  // from inside
  }
}

TEST(Fresnel, DielectricReflectancePlusTransmittanceIsOneOnBothSides) {
  for (double eta : {1.5, 1 / 1.5, 1.33, 2.4}) {
    for (int i = 0; i <= 90; ++i) {
      const double theta = Radians(i == 90 ? 89.9 : i);
      const double cos_i = std::cos(theta);
      const double R = FresnelDielectric(static_cast<float>(cos_i), static_cast<float>(eta));
      const double T = TransmittanceFromAmplitudes(cos_i, eta);
      EXPECT_NEAR(R + T, 1.0, 2e-5) << "eta " << eta << " angle " << i;
      EXPECT_GE(R, 0);
      EXPECT_LE(R, 1);
    }
  }
}

TEST(Fresnel, TotalInternalReflectionPastTheCriticalAngle) {
  const float ior = 1.5f;
  const double critical = std::asin(1 / ior);  // 41.81 degrees
  // From inside the glass: cos_i < 0 relative to the outward normal.
  for (double theta = critical + 1e-3; theta < kPiD / 2; theta += 0.01)
    EXPECT_EQ(FresnelDielectric(-static_cast<float>(std::cos(theta)), ior), 1.0f) << theta;
  EXPECT_LT(FresnelDielectric(-static_cast<float>(std::cos(critical - 0.01)), ior), 1.0f);
  // The same angles from outside never reflect totally.
  EXPECT_LT(FresnelDielectric(static_cast<float>(std::cos(critical + 0.2)), ior), 0.2f);
  // Refract agrees: no transmitted direction past the critical angle.
  const Vec3 n(0, 0, 1);
  const float s = static_cast<float>(std::sin(critical + 0.01));
  EXPECT_FALSE(Refract(Vec3(s, 0, SafeSqrt(1 - s * s)), n, 1 / ior));
}

TEST(Fresnel, RefractObeysSnellAndReverses) {
  const Vec3 n(0, 0, 1);
  const Vec3 w = Normalize(Vec3(0.4f, -0.3f, 0.8f));
  const float eta = 1.5f;
  const std::optional<Vec3> t = Refract(w, n, eta);
  ASSERT_TRUE(t);
  EXPECT_LT(t->z, 0);
  const float sin_i = std::sqrt(1 - w.z * w.z), sin_t = std::sqrt(1 - t->z * t->z);
  EXPECT_NEAR(sin_i, eta * sin_t, 1e-5);
  // Same plane of incidence, opposite tangential side convention: t's tangent parallel to
  // -w's.
  EXPECT_NEAR(t->x * w.y - t->y * w.x, 0, 1e-6);
  // Reversibility: light arriving from t's side along -t leaves along w.
  const std::optional<Vec3> back = Refract(*t, -n, 1 / eta);
  ASSERT_TRUE(back);
  EXPECT_NEAR(Distance(*back, w), 0, 1e-5);
}

TEST(Fresnel, ConductorNormalIncidenceAndGold) {
  // R(0) = ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2).
  for (auto [n, k] : {std::pair{0.143f, 3.983f}, {0.374f, 2.385f}, {1.442f, 1.603f},
                      {2.0f, 0.0f}, {1.0f, 5.0f}}) {
    const float expected = (Sqr(n - 1) + k * k) / (Sqr(n + 1) + k * k);
    EXPECT_NEAR(FresnelConductor(1, n, k), expected, 1e-5) << n << " " << k;
  }
  // Gold's red channel: about 0.967 head-on, and every metal reflects fully at grazing.
  EXPECT_NEAR(FresnelConductor(1, 0.143f, 3.983f), 0.9667f, 1e-3);
  EXPECT_NEAR(FresnelConductor(0, 0.143f, 3.983f), 1.0f, 1e-6);
}

TEST(Fresnel, ConductorMatchesTheRealFormOfBornAndWolf) {
  // The classic real-arithmetic form (pbrt-v3's FrConductor): a^2 + b^2 from the complex
  // index, then Rs and Rp. An independent derivation of the same physics.
  auto reference = [](double cos_i, double eta, double k) {
    const double cos2 = cos_i * cos_i, sin2 = 1 - cos2;
    const double t0 = eta * eta - k * k - sin2;
    const double a2b2 = std::sqrt(t0 * t0 + 4 * eta * eta * k * k);
    const double t1 = a2b2 + cos2;
    const double a = std::sqrt(0.5 * (a2b2 + t0));
    const double t2 = 2 * cos_i * a;
    const double rs = (t1 - t2) / (t1 + t2);
    const double t3 = cos2 * a2b2 + sin2 * sin2;
    const double t4 = t2 * sin2;
    const double rp = rs * (t3 - t4) / (t3 + t4);
    return (rp + rs) / 2;
  };
  for (auto [n, k] : {std::pair{0.143, 3.983}, {1.442, 1.603}, {0.2, 0.9}, {3.0, 0.5}})
    for (int deg = 0; deg < 90; deg += 5) {
      const double c = std::cos(Radians(deg));
      EXPECT_NEAR(FresnelConductor(float(c), float(n), float(k)), reference(c, n, k), 2e-5)
          << n << " " << k << " at " << deg;
    }
}

TEST(Fresnel, ConductorWithoutAbsorptionIsADielectric) {
  for (int deg = 0; deg < 90; deg += 7) {
    const float c = static_cast<float>(std::cos(Radians(deg)));
    EXPECT_NEAR(FresnelConductor(c, 1.5f, 0), FresnelDielectric(c, 1.5f), 1e-5) << deg;
  }
}

}  // namespace
}  // namespace farm
