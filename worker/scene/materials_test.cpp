#include "scene/materials.h"

#include <gtest/gtest.h>

#include <cmath>

#include "math/frame.h"
#include "math/math.h"
#include "renderfarm/v1/scene.pb.h"
#include "sampling/sobol.h"
#include "sampling/warps.h"
#include "scene/scene.h"

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
  EXPECT_TRUE(Reflects(m));
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
  const Material m = EmissiveMaterial{Rgb(4, 5, 6)};
  const Vec3 n(0, 1, 0);
  EXPECT_EQ(Emitted(m, n, Vec3(0, 1, 0)), Rgb(4, 5, 6));
  EXPECT_TRUE(Emitted(m, n, Vec3(0, -1, 0)).IsBlack());
  EXPECT_TRUE(EvaluateBsdf(m, n, n, n).IsBlack());
  EXPECT_FALSE(Reflects(m));
  EXPECT_EQ(ToString(m), "Emissive{radiance=rgb(4, 5, 6)}");
}

TEST(Materials, FromProtoValidatesAndNamesTheField) {
  renderfarm::v1::Material p;
  p.set_name("m");
  try {
    MaterialFromProto(p, "materials[4]");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("materials[4]"), std::string::npos);
  }
  p.mutable_lambert()->mutable_reflectance()->set_r(1.5);
  try {
    MaterialFromProto(p, "materials[4]");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("materials[4].lambert.reflectance"), std::string::npos);
  }
  p.mutable_lambert()->mutable_reflectance()->set_r(0.5);
  EXPECT_EQ(ToString(MaterialFromProto(p, "x")), "Lambert{reflectance=rgb(0.5, 0, 0)}");
}

}  // namespace
}  // namespace farm
