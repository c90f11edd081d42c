#include "scene/materials.h"

#include <gtest/gtest.h>

#include <cmath>

#include "math/frame.h"
#include "math/math.h"
#include "renderfarm/v1/scene.pb.h"
#include "sampling/hash.h"
#include "sampling/sobol.h"
#include "sampling/warps.h"
#include "scene/fresnel.h"

namespace farm {
namespace {

TEST(Materials, LambertReflectsRhoOverPiOnBothSidesOnly) {
  const Material m = LambertMaterial{Rgb(0.25f, 0.5f, 0.75f)};
  const Vec3 n(0, 0, 1);
  const Vec3 up = Normalize(Vec3(0.3f, 0.1f, 1)), up2 = Normalize(Vec3(-0.5f, 0.2f, 0.4f));
  EXPECT_NEAR(EvaluateBsdf(m, n, up, up2).g, 0.5f / kPi, 1e-7);
  EXPECT_NEAR(EvaluateBsdf(m, n, -up, -up2).g, 0.5f / kPi, 1e-7);  // two-sided
  EXPECT_TRUE(EvaluateBsdf(m, n, up, -up2).IsBlack());            // no transmission
  EXPECT_TRUE(Emitted(m, n, up).IsBlack());
  EXPECT_TRUE(CapabilitiesOf(m).reflects);
}

TEST(Materials, LambertAlbedoIsRho) {
  // Integral of f cos over the hemisphere, by uniform-sphere Monte Carlo, equals rho.
  const Material m = LambertMaterial{Rgb(0.6f)};
  const Vec3 n = Normalize(Vec3(1, 2, 3)), wo = n;
  const Frame frame = Frame::FromZ(n);
  const int count = 1 << 14;
  double sum = 0;
  for (int i = 0; i < count; ++i) {
    const Vec3 wi = frame.FromLocal(SampleUniformSphere({SobolSample(i, 0, 1), SobolSample(i, 1, 2)}));
    sum += EvaluateBsdf(m, n, wo, wi).r * std::max(0.0f, Dot(n, wi)) / UniformSpherePdf();
  }
  EXPECT_NEAR(sum / count, 0.6, 5e-3);
}

TEST(Materials, EmissiveEmitsFromTheFrontOnlyAndReflectsNothing) {
  const Material m = EmissiveMaterial{Rgb(4, 5, 6), Rgb()};
  const Vec3 n(0, 1, 0);
  EXPECT_EQ(Emitted(m, n, Vec3(0, 1, 0)), Rgb(4, 5, 6));
  EXPECT_TRUE(Emitted(m, n, Vec3(0, -1, 0)).IsBlack());
  EXPECT_TRUE(EvaluateBsdf(m, n, n, n).IsBlack());
  EXPECT_FALSE(CapabilitiesOf(m).reflects);
  EXPECT_TRUE(CapabilitiesOf(m).emits);
  EXPECT_FALSE(CapabilitiesOf(EmissiveMaterial{Rgb(0), Rgb()}).emits);  // black: not a light
  EXPECT_EQ(ToString(m), "Emissive{radiance=rgb(4, 5, 6), reflectance=rgb(0, 0, 0)}");
  EXPECT_FALSE(SampleBsdf(m, n, n, 0.5f, {0.5f, 0.5f}, TransportMode::kRadiance).has_value());
}

TEST(Materials, EmissiveWithAReflectanceReflectsAsALambertOfIt) {
  const Rgb rho(0.78f, 0.5f, 0.25f);
  const Material m = EmissiveMaterial{Rgb(4, 5, 6), rho};
  const Vec3 n(0, 1, 0);
  const Vec3 up = Normalize(Vec3(0.3f, 1, 0.1f)), up2 = Normalize(Vec3(-0.5f, 0.4f, 0.2f));
  EXPECT_NEAR(EvaluateBsdf(m, n, up, up2).r, 0.78f / kPi, 1e-7);
  EXPECT_NEAR(EvaluateBsdf(m, n, -up, -up2).b, 0.25f / kPi, 1e-7);  // two-sided, as a Lambert
  EXPECT_TRUE(EvaluateBsdf(m, n, up, -up2).IsBlack());
  EXPECT_EQ(Emitted(m, n, up), Rgb(4, 5, 6));  // still from the front only
  EXPECT_TRUE(Emitted(m, n, -up).IsBlack());
  EXPECT_EQ(Albedo(m), rho);
  EXPECT_EQ(DiffuseReflectance(m, n, up, up2), rho);
  const std::optional<BsdfSample> s = SampleBsdf(m, n, up, 0.5f, {0.3f, 0.7f}, TransportMode::kImportance);
  ASSERT_TRUE(s.has_value());
  EXPECT_GT(Dot(s->wi, n), 0);
  EXPECT_EQ(s->weight, rho);  // cosine-sampled: f cos / pdf = rho
  EXPECT_NEAR(BsdfPdf(m, n, up, s->wi), Dot(s->wi, n) / kPi, 1e-6);
  const MaterialCapabilities c = CapabilitiesOf(m);
  EXPECT_TRUE(c.reflects);
  EXPECT_TRUE(c.emits);
  EXPECT_FALSE(c.specular);
  EXPECT_EQ(c.diffuse_fraction, 1);
}

TEST(Materials, FromProtoReadsEveryKind) {
  renderfarm::v1::Material p;
  p.mutable_lambert()->mutable_reflectance()->set_r(0.5);
  EXPECT_EQ(ToString(MaterialFromProto(p)), "Lambert{reflectance=rgb(0.5, 0, 0)}");
  p.mutable_dielectric()->set_ior(1.5);
  const Material glass = MaterialFromProto(p);
  EXPECT_EQ(std::get<DielectricMaterial>(glass).transmittance, Rgb(1));  // unset means 1
  EXPECT_EQ(std::get<DielectricMaterial>(glass).ior, 1.5f);
  p.mutable_conductor()->mutable_eta()->set_r(0.25);
  p.mutable_conductor()->mutable_k()->set_r(3);
  EXPECT_EQ(ToString(MaterialFromProto(p)), "Conductor{eta=rgb(0.25, 0, 0), k=rgb(3, 0, 0)}");
  p.mutable_glossy()->mutable_diffuse()->set_g(0.25);
  p.mutable_glossy()->set_exponent(10);
  const GlossyMaterial g = std::get<GlossyMaterial>(MaterialFromProto(p));
  EXPECT_EQ(g.diffuse, Rgb(0, 0.25f, 0));
  EXPECT_EQ(g.exponent, 10);
}

}  // namespace
}  // namespace farm

namespace farm {
namespace {

constexpr Vec3 kUp(0, 0, 1);

Vec3 At(float theta_degrees) {
  const float t = static_cast<float>(Radians(theta_degrees));
  return {std::sin(t), 0, std::cos(t)};
}

TEST(Materials, CapabilitiesClassifyEveryKind) {
  for (const Material& m : {Material(MirrorMaterial{Rgb(1)}), Material(DielectricMaterial{1.5f, Rgb(1), std::nullopt}),
                            Material(ConductorMaterial{Rgb(0.2f), Rgb(3)})}) {
    const MaterialCapabilities c = CapabilitiesOf(m);
    EXPECT_TRUE(c.specular) << ToString(m);
    EXPECT_FALSE(c.reflects) << ToString(m);
    EXPECT_FALSE(c.emits) << ToString(m);
    EXPECT_EQ(c.diffuse_fraction, 0) << ToString(m);
  }
  const MaterialCapabilities lambert = CapabilitiesOf(LambertMaterial{Rgb(0.5f)});
  EXPECT_FALSE(lambert.specular);
  EXPECT_TRUE(lambert.reflects);
  EXPECT_EQ(lambert.diffuse_fraction, 1.0f);
  const MaterialCapabilities glossy = CapabilitiesOf(GlossyMaterial{Rgb(0.2f), Rgb(0.6f), 20});
  EXPECT_FALSE(glossy.specular);
  EXPECT_TRUE(glossy.reflects);
  EXPECT_NEAR(glossy.diffuse_fraction, 0.25f, 1e-6);  // by luminance: 0.2 / (0.2 + 0.6)
  EXPECT_EQ(DiffuseReflectance(GlossyMaterial{Rgb(0.2f), Rgb(0.6f), 20}, kUp, At(30), At(-10)), Rgb(0.2f));
  EXPECT_EQ(DiffuseReflectance(MirrorMaterial{Rgb(1)}, kUp, At(30), At(-10)), Rgb());
  // The glossy lobe alone: Blinn-Phong's weight wi.z / max(wo.z, wi.z) times the specular.
  const std::optional<BsdfSample> lobe = SampleGlossyLobe(GlossyMaterial{Rgb(0.2f), Rgb(0.6f), 20}, kUp, At(30), {0.4f, 0.7f});
  ASSERT_TRUE(lobe);
  EXPECT_NEAR(lobe->weight.g, 0.6f * lobe->wi.z / std::max(At(30).z, lobe->wi.z), 1e-6f);
  EXPECT_FALSE(SampleGlossyLobe(LambertMaterial{Rgb(0.5f)}, kUp, At(30), {0.4f, 0.7f}));
  EXPECT_TRUE(EvaluateBsdf(MirrorMaterial{Rgb(1)}, kUp, At(30), At(-30)).IsBlack());
}

TEST(Materials, MirrorReflectsAboutTheNormalOnBothSides) {
  const Material m = MirrorMaterial{Rgb(0.9f, 0.8f, 0.7f)};
  const auto s = SampleBsdf(m, kUp, At(30), 0.5f, {0.5f, 0.5f}, TransportMode::kRadiance);
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->specular);
  EXPECT_NEAR(Distance(s->wi, At(-30)), 0, 1e-6);
  EXPECT_EQ(s->weight, Rgb(0.9f, 0.8f, 0.7f));
  const auto back = SampleBsdf(m, kUp, -At(30), 0.5f, {0.5f, 0.5f}, TransportMode::kRadiance);
  ASSERT_TRUE(back);
  EXPECT_NEAR(Distance(back->wi, -At(-30)), 0, 1e-6);
}

TEST(Materials, ConductorWeightIsItsFresnelReflectance) {
  const Material gold = ConductorMaterial{{0.143f, 0.374f, 1.442f}, {3.983f, 2.385f, 1.603f}};
  const auto s = SampleBsdf(gold, kUp, At(0), 0.5f, {0.5f, 0.5f}, TransportMode::kImportance);
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->weight.r, 0.9667f, 1e-3);
  EXPECT_GT(s->weight.r, s->weight.b);  // gold is yellow
  EXPECT_NEAR(Distance(s->wi, kUp), 0, 1e-6);
}

TEST(Materials, DielectricChoosesReflectionWithFresnelProbability) {
  const Material glass = DielectricMaterial{1.5f, Rgb(1, 0.9f, 0.8f), std::nullopt};
  for (float theta : {0.0f, 40.0f, 75.0f}) {
    for (bool from_inside : {false, true}) {
      const Vec3 wo = from_inside ? -At(theta) : At(theta);
      const float eta = from_inside ? 1 / 1.5f : 1.5f;
      const float R = FresnelDielectric(Dot(kUp, wo), 1.5f);
      const int n = 4096;
      int reflected = 0;
      for (int i = 0; i < n; ++i) {
        const float u = (i + 0.5f) / n;
        const auto s = SampleBsdf(glass, kUp, wo, u, {0.5f, 0.5f}, TransportMode::kRadiance);
        ASSERT_TRUE(s);
        ASSERT_TRUE(s->specular);
        if (Dot(s->wi, kUp) * Dot(wo, kUp) > 0) {
          ++reflected;
          EXPECT_EQ(s->weight, Rgb(1));
        } else {
          // Radiance scaled by 1/eta^2 and tinted; photons (importance) are only tinted.
          EXPECT_NEAR(s->weight.g, 0.9f / (eta * eta), 1e-6);
          const auto p = SampleBsdf(glass, kUp, wo, u, {0.5f, 0.5f}, TransportMode::kImportance);
          EXPECT_EQ(p->weight, Rgb(1, 0.9f, 0.8f));
        }
      }
      // TIR from inside past 41.8 degrees: always reflected.
      EXPECT_NEAR(double(reflected) / n, R, 1.0 / n + 1e-6) << theta << " inside " << from_inside;
    }
  }
  EXPECT_EQ(FresnelDielectric(-std::cos(float(Radians(75))), 1.5f), 1.0f);
}

TEST(Materials, SplitDielectricWeighsBothWaysByTheirFresnelShares) {
  // SplitSpecular's two branches weigh what SampleBsdf's choice gives on average: R for
  // the reflection (the mirror direction), 1 - R times the chosen refraction's weight.
  const Material glass = DielectricMaterial{1.5f, Rgb(1, 0.9f, 0.8f), std::nullopt};
  for (float theta : {0.0f, 40.0f, 75.0f}) {
    for (bool from_inside : {false, true}) {
      const Vec3 wo = from_inside ? -At(theta) : At(theta);
      const float R = FresnelDielectric(Dot(kUp, wo), 1.5f);
      const auto split = SplitSpecular(glass, kUp, wo, TransportMode::kRadiance);
      ASSERT_TRUE(split);
      const auto reflected = SampleBsdf(glass, kUp, wo, 0, {0.5f, 0.5f}, TransportMode::kRadiance);
      EXPECT_EQ(split->reflected.wi, reflected->wi);
      EXPECT_NEAR(split->reflected.weight.g, R, 1e-6) << theta << " inside " << from_inside;
      if (R == 1) {  // total internal reflection
        EXPECT_FALSE(split->transmitted);
        continue;
      }
      ASSERT_TRUE(split->transmitted);
      const auto refracted = SampleBsdf(glass, kUp, wo, 1, {0.5f, 0.5f}, TransportMode::kRadiance);
      EXPECT_EQ(split->transmitted->wi, refracted->wi);
      EXPECT_NEAR(split->transmitted->weight.b, (1 - R) * refracted->weight.b, 1e-6);
    }
  }
  // One lobe or none: nothing to split.
  EXPECT_FALSE(SplitSpecular(MirrorMaterial{Rgb(1)}, kUp, At(30), TransportMode::kRadiance));
  EXPECT_FALSE(SplitSpecular(LambertMaterial{Rgb(0.5f)}, kUp, At(30), TransportMode::kRadiance));
}

TEST(Materials, GlossyWhiteFurnaceAndPdfConsistency) {
  // kd + ks = 1: the albedo (mean sample weight) is at most 1, the sample weights agree with
  // EvaluateBsdf * cos / BsdfPdf, and the pdf integrates to the share of accepted samples.
  const Material m = GlossyMaterial{Rgb(0.4f), Rgb(0.6f), 30};
  const Vec3 n = Normalize(Vec3(0.1f, 0.2f, 1));
  for (float theta : {0.0f, 50.0f, 80.0f}) {
    const Vec3 wo = Frame::FromZ(n).FromLocal(At(theta));
    const int count = 1 << 18;
    double mean_weight = 0, pdf_integral = 0;
    int accepted = 0;
    for (int i = 0; i < count; ++i) {
      // Three independent numbers (two Sobol dimensions of one index would be correlated).
      const float u_lobe = FractionToFloat(uint32_t(Hash(i, 1)));
      const Vec2 u{FractionToFloat(uint32_t(Hash(i, 2))), FractionToFloat(uint32_t(Hash(i, 3)))};
      if (const auto s = SampleBsdf(m, n, wo, u_lobe, u, TransportMode::kRadiance)) {
        ++accepted;
        mean_weight += s->weight.g;
        const float pdf = BsdfPdf(m, n, wo, s->wi);
        ASSERT_NEAR(pdf, s->pdf, 1e-4f * pdf);
        const Rgb expected = EvaluateBsdf(m, n, wo, s->wi) * (Dot(n, s->wi) / pdf);
        ASSERT_NEAR(s->weight.g, expected.g, 1e-4f);
      }
      const Vec3 w = SampleUniformSphere({SobolSample(i, 0, 5), SobolSample(i, 1, 6)});
      pdf_integral += BsdfPdf(m, n, wo, w) / UniformSpherePdf();
    }
    mean_weight /= count;
    pdf_integral /= count;
    EXPECT_LE(mean_weight, 1.0) << theta;
    EXPECT_GT(mean_weight, 0.5) << theta;
    EXPECT_NEAR(pdf_integral, double(accepted) / count, 5e-3) << theta;
  }
}

}  // namespace
}  // namespace farm
