#include "scene/principled.h"

#include <gtest/gtest.h>

#include <cmath>

#include "contract/rules.h"
#include "math/frame.h"
#include "math/math.h"
#include "renderfarm/v1/scene.pb.h"
#include "sampling/sobol.h"
#include "sampling/warps.h"
#include "scene/fresnel.h"
#include "scene/ggx.h"
#include "scene/materials.h"
#include "scene/test_directions.h"

namespace farm {
namespace {

// A uniformly distributed direction of the upper hemisphere (density 1 / (2 pi)).
Vec3 Upper(Vec2 u) {
  const Vec3 w = SampleUniformSphere(u);
  return {w.x, w.y, std::abs(w.z)};
}

PrincipledLobes Lobes(Rgb base, float metallic, float roughness) {
  return PrincipledLobes{base, metallic, std::max(kMinGgxAlpha, roughness * roughness), false};
}

// The integral of f cos over the hemisphere by quadrature, in half vectors (wi =
// reflect(wo, h), dwi = 4 (wo.h) dh), where the lobe's peak is at the pole whatever wo:
// uniform in cos theta_h and phi_h. What SamplePrincipled's weights average to.
Rgb Albedo(const PrincipledLobes& m, const Vec3& wo) {
  constexpr int kCos = 4000, kPhi = 1000;
  Rgb sum;
  for (int i = 0; i < kCos; ++i)
    for (int j = 0; j < kPhi; ++j) {
      const float z = (i + 0.5f) / kCos, phi = 2 * kPi * (j + 0.5f) / kPhi, r = SafeSqrt(1 - z * z);
      const Vec3 h(r * std::cos(phi), r * std::sin(phi), z);
      const float wo_h = Dot(wo, h);
      if (!(wo_h > 0)) continue;
      const Vec3 wi = Reflect(wo, h);
      if (wi.z > 0) sum += PrincipledValue(m, wo, wi) * (wi.z * 4 * wo_h);
    }
  return sum * (2 * kPi / (float(kCos) * kPhi));
}

TEST(Principled, IsReciprocal) {
  for (const PrincipledLobes& m : {Lobes(Rgb(0.8f, 0.5f, 0.2f), 0, 0.4f), Lobes(Rgb(0.9f, 0.6f, 0.3f), 1, 0.2f),
                                   Lobes(Rgb(0.3f), 0.5f, 0.8f)}) {
    for (uint32_t k = 0; k < 200; ++k) {
      const Vec3 a = Upper(Sobol2(k, 4)), b = Upper(Sobol2(k, 8));
      const Rgb ab = PrincipledValue(m, a, b), ba = PrincipledValue(m, b, a);
      EXPECT_NEAR(ab.r, ba.r, 1e-5f * std::max(1.0f, ab.r));
      EXPECT_NEAR(ab.g, ba.g, 1e-5f * std::max(1.0f, ab.g));
      EXPECT_NEAR(ab.b, ba.b, 1e-5f * std::max(1.0f, ab.b));
    }
  }
}

// Single scattering loses what the microsurface would reflect more than once: a white
// full metal (F = 1) reflects 1 - loss of the light from wo, where loss is at most
//
//   roughness      0.25    0.5     0.75    1
//   head on        1%      10%     40%     72%
//   75 degrees     5%      18%     28%     43%
//
// (measured 0.6%, 8.4%, 37.3%, 69.3% head on; 3.8%, 16.1%, 26.0%, 40.9% at 75 degrees: at
// roughness 1, GGX's normals are uniform and half of those seen head on reflect below the
// horizon) and never negative: a white metal never reflects more than it receives.
// glTF's dielectric (metallic 0) is not energy conserving: its diffuse base is weighted by
// 1 - F(wo.h), not by what the specular lobe leaves, so a white one reflects up to 17% more
// than it receives at grazing angles (roughness 0.25, 75 degrees; at most 20% here), and
// never less than the metal.
struct FurnaceCase {
  float roughness, theta, max_loss;
};
constexpr FurnaceCase kSingleScatteringLoss[] = {
    {0.25f, 0, 0.01f},  {0.5f, 0, 0.10f},  {0.75f, 0, 0.40f},  {1, 0, 0.72f},
    {0.25f, 75, 0.05f}, {0.5f, 75, 0.18f}, {0.75f, 75, 0.28f}, {1, 75, 0.43f},
};
constexpr float kMaxDielectricGain = 0.2f;

TEST(Principled, WhiteFurnaceLosesAtMostTheSingleScatteringLoss) {
  for (const FurnaceCase& c : kSingleScatteringLoss) {
    const Vec3 wo = Dir(c.theta);
    const PrincipledLobes metal = Lobes(Rgb(1), 1, c.roughness), plastic = Lobes(Rgb(1), 0, c.roughness);
    const float quadrature = Albedo(metal, wo).g;
    // The sampler's estimate of the same integral (its weights are f cos / pdf).
    const int n = 1 << 17;
    double sampled = 0;
    for (int k = 0; k < n; ++k)
      if (const auto s = SamplePrincipled(metal, wo, SobolSample(k, 2, 5), Sobol2(k, 6))) sampled += s->weight.g;
    sampled /= n;
    EXPECT_NEAR(sampled, quadrature, 5e-3) << "roughness " << c.roughness << " theta " << c.theta;
    EXPECT_LE(quadrature, 1.0f) << "roughness " << c.roughness << " theta " << c.theta;
    EXPECT_LE(1 - quadrature, c.max_loss) << "roughness " << c.roughness << " theta " << c.theta;
    const float dielectric = Albedo(plastic, wo).g;
    EXPECT_LE(dielectric, 1 + kMaxDielectricGain) << "roughness " << c.roughness << " theta " << c.theta;
    EXPECT_GT(dielectric, quadrature) << "roughness " << c.roughness << " theta " << c.theta;
  }
}

// The sampler's density is PrincipledPdf and its weight f cos / pdf; the density
// integrates over the hemisphere to the share of samples kept.
TEST(Principled, SamplesCarryTheirDensityAndWeight) {
  const PrincipledLobes m = Lobes(Rgb(0.7f, 0.4f, 0.2f), 0.3f, 0.5f);
  for (float theta : {10.0f, 60.0f}) {
    const Vec3 wo = Dir(theta, 30);
    const int n = 1 << 16;
    int kept = 0;
    for (int k = 0; k < n; ++k) {
      const auto s = SamplePrincipled(m, wo, SobolSample(k, 2, 3), Sobol2(k, 4));
      if (!s) continue;
      ++kept;
      ASSERT_GT(s->wi.z, 0);
      EXPECT_FALSE(s->specular);
      const float pdf = PrincipledPdf(m, wo, s->wi);
      EXPECT_NEAR(s->pdf, pdf, 1e-4f * pdf);
      const Rgb want = PrincipledValue(m, wo, s->wi) * (s->wi.z / pdf);
      EXPECT_NEAR(s->weight.r, want.r, 1e-4f * std::max(1.0f, want.r));
    }
    double integral = 0;
    for (int k = 0; k < n; ++k) {
      const Vec3 wi = Upper(Sobol2(k, 12));
      integral += PrincipledPdf(m, wo, wi) * (2 * kPi);
    }
    EXPECT_NEAR(integral / n, double(kept) / n, 5e-3) << "theta " << theta;
  }
}

// Below the roughness threshold the lobe is a delta: left out of the value and the
// density, drawn only as a specular sample, which for a smooth metal reflects the base
// colour head on (Schlick's F0) in the mirror direction.
TEST(Principled, ASmoothLobeCountsAsADelta) {
  PrincipledLobes m = Lobes(Rgb(0.9f, 0.5f, 0.1f), 1, 0);
  m.specular = true;
  const Vec3 wo(0, 0, 1);
  EXPECT_TRUE(PrincipledValue(m, wo, Dir(5)).IsBlack());
  EXPECT_EQ(PrincipledPdf(m, wo, Dir(5)), 0);
  const auto s = SamplePrincipledSpecular(m, wo, {0.3f, 0.6f});
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->specular);
  EXPECT_EQ(s->pdf, 0);
  EXPECT_GT(s->wi.z, 1 - 1e-6f);
  EXPECT_NEAR(s->weight.r, 0.9f, 1e-4f);
  EXPECT_NEAR(s->weight.b, 0.1f, 1e-4f);
  // A smooth dielectric: its diffuse base is drawn with the rest of the probability.
  PrincipledLobes plastic = Lobes(Rgb(0.5f), 0, 0.05f);
  plastic.specular = true;
  int specular = 0, diffuse = 0;
  for (uint32_t k = 0; k < 1000; ++k) {
    const auto t = SamplePrincipled(plastic, Dir(30), (k + 0.5f) / 1000, Sobol2(k, 2));
    if (!t) continue;
    (t->specular ? specular : diffuse)++;
    if (!t->specular) {
      EXPECT_NEAR(t->pdf, PrincipledPdf(plastic, Dir(30), t->wi), 1e-5f);
    }
  }
  EXPECT_NEAR(specular / 1000.0, SpecularLobeProbability(plastic, Dir(30)), 2e-3);
  EXPECT_GT(diffuse, 900);
}

// The capabilities Go's scene.CapabilitiesOf gives (contract/scene/capabilities_test.go).
TEST(Principled, CapabilitiesMatchTheContract) {
  const auto caps = [](double roughness, double metallic, bool mr_texture = false, double emission = 0) {
    renderfarm::v1::Material p;
    p.mutable_principled()->set_roughness(roughness);
    p.mutable_principled()->set_metallic(metallic);
    if (emission > 0) p.mutable_principled()->mutable_emission()->set_g(emission);
    Material m = MaterialFromProto(p);
    if (mr_texture) std::get<PrincipledMaterial>(m).metallic_roughness_texture = 0;
    return CapabilitiesOf(m);
  };
  const double threshold = contract::SceneLimits().principled_specular_roughness();
  const auto expect = [](const MaterialCapabilities& c, bool specular, bool reflects, bool emits) {
    EXPECT_EQ(c.specular, specular);
    EXPECT_EQ(c.reflects, reflects);
    EXPECT_EQ(c.emits, emits);
  };
  expect(caps(0.5, 0), false, true, false);
  expect(caps(0.5, 1), false, true, false);
  expect(caps(threshold, 1), false, true, false);
  expect(caps(std::nextafter(threshold, 0), 1), true, false, false);
  expect(caps(0, 1), true, false, false);
  expect(caps(0, 1, true), true, true, false);
  expect(caps(0, 0.5), true, true, false);
  expect(caps(1, 0, false, 2), false, true, true);
  EXPECT_EQ(caps(0, 0.5).diffuse_fraction, 1) << "a smooth surface's non-specular part is its base";
  EXPECT_EQ(caps(0.5, 1).diffuse_fraction, 0) << "a rough metal has no diffuse base";
}

TEST(Principled, FromProtoReadsTheFactorsAndDefaults) {
  renderfarm::v1::Material p;
  p.mutable_principled()->set_roughness(0.5);
  const PrincipledMaterial plain = std::get<PrincipledMaterial>(MaterialFromProto(p));
  EXPECT_EQ(plain.lobes.base_color, Rgb(1)) << "unset base colour is white";
  EXPECT_FLOAT_EQ(plain.lobes.alpha, 0.25f);
  EXPECT_EQ(plain.normal_scale, 1);
  EXPECT_EQ(plain.opacity, 1);
  EXPECT_EQ(plain.alpha_cutoff, 0.5f);
  EXPECT_FALSE(plain.alpha_mask);
  auto* q = p.mutable_principled();
  q->mutable_base_color()->set_r(0.25);
  q->set_metallic(0.75);
  q->set_transparency(0.4);
  q->set_alpha_mode(renderfarm::v1::ALPHA_MODE_MASK);
  q->set_alpha_cutoff(0.3);
  q->set_roughness(0);
  const PrincipledMaterial m = std::get<PrincipledMaterial>(MaterialFromProto(p));
  EXPECT_EQ(m.lobes.base_color, Rgb(0.25f, 0, 0));
  EXPECT_FLOAT_EQ(m.lobes.metallic, 0.75f);
  EXPECT_FLOAT_EQ(m.opacity, 0.6f);
  EXPECT_TRUE(m.alpha_mask);
  EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.3f);
  EXPECT_EQ(m.lobes.alpha, kMinGgxAlpha);
  EXPECT_TRUE(m.lobes.specular);
}

// The material evaluates its lobes about its shading normal, turned to wo's side.
TEST(Principled, LobesFollowTheShadingNormal) {
  PrincipledMaterial m;
  m.lobes = Lobes(Rgb(0.5f), 0, 0.3f);
  const Vec3 n(0, 0, 1), tilted = Normalize(Vec3(0.3f, 0, 1));
  m.shading_normal = tilted;
  const Vec3 wo = Normalize(Vec3(0.2f, 0.1f, 1)), wi = Normalize(Vec3(-0.4f, 0.3f, 1));
  const Frame frame = Frame::FromZ(tilted);
  const Rgb want = PrincipledValue(m.lobes, frame.ToLocal(wo), frame.ToLocal(wi));
  EXPECT_NEAR(EvaluateBsdf(m, n, wo, wi).g, want.g, 1e-6f);
  // From the back side, the same surface turned over.
  const Frame back = Frame::FromZ(-tilted);
  EXPECT_NEAR(EvaluateBsdf(m, n, -wo, -wi).g, PrincipledValue(m.lobes, back.ToLocal(-wo), back.ToLocal(-wi)).g, 1e-6f);
}

}  // namespace
}  // namespace farm
