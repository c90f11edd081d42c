// Camera paths through specular surfaces and delta lights, against closed forms.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "render/tile_renderer.h"
#include "scene/fresnel.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

constexpr double kPiD = std::numbers::pi;

Rgb CentrePixel(const pb::Scene& s) {
  const Scene scene = Scene::Build(s, NoBlobs());
  const Image image = RenderTile(scene, nullptr, {0, 0, 1, 1});
  const float* p = image.pixel(0, 0);
  return {p[0], p[1], p[2]};
}

// A camera at the origin looking down +z through a 0.5 degree field of view.
pb::Scene Narrow(uint32_t spp) { return MakeScene(1, 1, {0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 0.5, spp, 3); }

void AddMaterial(pb::Scene& s, const std::string& name,
                 const std::function<void(pb::Material*)>& fill) {
  pb::Material* m = s.add_materials();
  m->set_name(name);
  fill(m);
}

TEST(SpecularPaths, MirrorShowsTheEmitterScaledByItsReflectance) {
  // Camera -> mirror tilted 45 degrees -> emitter to the side.
  pb::Scene s = Narrow(4);
  AddEmissive(s, "lamp", Rgb(2, 3, 4));
  AddMaterial(s, "mirror", [](pb::Material* m) { Set(m->mutable_mirror()->mutable_reflectance(), Rgb(0.5f)); });
  // Mirror through (0, 0, 5) with normal (1, 0, -1)/sqrt2: the ray turns to +x.
  AddQuad(s, "mirror", {-1, -1, 4}, {0, 2, 0}, {2, 0, 2});
  AddQuad(s, "lamp", {10, -5, 0}, {0, 0, 10}, {0, 10, 0});  // x = 10, facing -x
  const Rgb L = CentrePixel(s);
  EXPECT_NEAR(L.r, 1.0f, 1e-5);
  EXPECT_NEAR(L.b, 2.0f, 1e-5);
}

TEST(SpecularPaths, GlassSlabTransmitsEmitterRadianceUnscaledOnTheWayOut) {
  // A slab between the camera and an emitter, at normal incidence: the radiance scales by
  // 1/eta^2 going in and eta^2 coming out, and the stochastic Fresnel choices at the two
  // faces sum the inter-reflections to (1 - R) / (1 + R) of the emitter's radiance.
  pb::Scene s = Narrow(4096);
  AddEmissive(s, "lamp", Rgb(1));
  AddMaterial(s, "glass", [](pb::Material* m) { m->mutable_dielectric()->set_ior(1.5); });
  AddQuad(s, "glass", {-5, -5, 5}, {0, 10, 0}, {10, 0, 0});    // entry face, front -z
  AddQuad(s, "glass", {-5, -5, 5.5}, {10, 0, 0}, {0, 10, 0});  // exit face, front +z
  AddQuad(s, "lamp", {-50, -50, 10}, {0, 100, 0}, {100, 0, 0});  // facing -z
  const double R = FresnelDielectric(1, 1.5f);
  const double expected = (1 - R) / (1 + R);
  const Rgb L = CentrePixel(s);
  EXPECT_NEAR(L.g, expected, 0.01) << "R = " << R;
}

TEST(SpecularPaths, GoldReflectsItsFresnelColour) {
  pb::Scene s = Narrow(4);
  AddEmissive(s, "lamp", Rgb(1));
  AddMaterial(s, "gold", [](pb::Material* m) {
    Set(m->mutable_conductor()->mutable_eta(), Rgb(0.143f, 0.374f, 1.442f));
    Set(m->mutable_conductor()->mutable_k(), Rgb(3.983f, 2.385f, 1.603f));
  });
  AddQuad(s, "gold", {-1, -1, 4}, {0, 2, 0}, {2, 0, 2});
  AddQuad(s, "lamp", {10, -5, 0}, {0, 0, 10}, {0, 10, 0});
  const Rgb L = CentrePixel(s);
  const float c = std::cos(static_cast<float>(kPiD / 4));
  EXPECT_NEAR(L.r, FresnelConductor(c, 0.143f, 3.983f), 1e-4);
  EXPECT_NEAR(L.b, FresnelConductor(c, 1.442f, 1.603f), 1e-4);
}

// A Lambert floor at z = 0 seen at the origin from above.
pb::Scene FloorFromAbove() {
  pb::Scene s = MakeScene(1, 1, {0.5, 0, 10}, {0, 0, 0}, {0, 0, 1}, 0.02, 4, 5);
  AddLambert(s, "floor", Rgb(0.5f));
  AddQuad(s, "floor", {-100, -100, 0}, {200, 0, 0}, {0, 200, 0});
  return s;
}

TEST(SpecularPaths, PointAndSunLightDirectLightingMatchClosedForms) {
  {
    pb::Scene s = FloorFromAbove();
    auto* p = s.add_lights()->mutable_point();
    Set(p->mutable_position(), {3, 0, 4});
    Set(p->mutable_intensity(), Rgb(50));
    // rho / pi * I cos / d^2 with d = 5, cos = 4/5.
    EXPECT_NEAR(CentrePixel(s).g, 0.5 / kPiD * 50 * 0.8 / 25, 1e-3);
  }
  {
    pb::Scene s = FloorFromAbove();
    auto* sun = s.add_lights()->mutable_sun();
    Set(sun->mutable_direction(), {-1, 0, -1});
    Set(sun->mutable_irradiance(), Rgb(2));
    EXPECT_NEAR(CentrePixel(s).g, 0.5 / kPiD * 2 * std::sqrt(0.5), 1e-4);
    // A blocker between the floor point and the sun (not in the camera's way) casts a hard
    // shadow.
    AddQuad(s, "floor", {0.5, -1, 1}, {2, 0, 0}, {0, 2, 0});
    EXPECT_EQ(CentrePixel(s).g, 0.0f);
  }
}

}  // namespace
}  // namespace farm
