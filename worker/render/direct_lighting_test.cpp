// End-to-end checks of direct lighting against closed forms: one-pixel images of a Lambert
// plane seen through a very narrow camera, so the pixel is one point of the plane.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "render/tile_renderer.h"
#include "math/math.h"
#include "scene/ggx.h"
#include "scene/principled.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

constexpr double kPiD = std::numbers::pi;
constexpr float kRho = 0.5f;

// A 200 x 200 Lambert floor at z = 0 (front +z), seen at the origin from (10, 0, 1) by a
// 1x1 camera with a 0.02 degree field of view.
pb::Scene FloorScene(uint32_t spp) {
  pb::Scene s = MakeScene(1, 1, {10, 0, 1}, {0, 0, 0}, {0, 0, 1}, 0.02, spp, 7);
  AddLambert(s, "floor", Rgb(kRho));
  AddEmissive(s, "lamp", Rgb(2));
  AddQuad(s, "floor", {-100, -100, 0}, {200, 0, 0}, {0, 200, 0});
  return s;
}

Rgb RenderOnePixel(const pb::Scene& s) {
  const Scene scene = Scene::Build(s, NoBlobs());
  const Image image = RenderTile(scene, nullptr, {0, 0, 1, 1});
  const float* p = image.pixel(0, 0);
  EXPECT_EQ(p[3], 1.0f);
  return {p[0], p[1], p[2]};
}

double CornerFormFactor(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * kPiD);
}

TEST(DirectLighting, LambertUnderSphereLightIsRhoOverPiTimesIrradiance) {
  // Sphere light of radiance L = 2, radius R = 1, centre 4 above the shaded point:
  // E = pi L (R/d)^2, outgoing radiance rho / pi * E = rho * L / 16.
  pb::Scene s = FloorScene(256);
  AddSphere(s, "lamp", {0, 0, 4}, 1);
  const double expected = kRho / kPiD * (kPiD * 2 * (1.0 / 16));
  const Rgb L = RenderOnePixel(s);
  EXPECT_NEAR(L.g, expected, 5e-3 * expected) << L;
  EXPECT_EQ(L.r, L.g);
}

TEST(DirectLighting, LambertUnderQuadLightMatchesTheFormFactor) {
  // A 2 x 2 quad light 1.5 above the point, facing down (cross(edge_u, edge_v) = -z).
  pb::Scene s = FloorScene(4096);
  AddQuad(s, "lamp", {-1, -1, 1.5}, {0, 2, 0}, {2, 0, 0});
  const double E = kPiD * 2 * 4 * CornerFormFactor(1, 1, 1.5);
  const double expected = kRho / kPiD * E;
  const Rgb L = RenderOnePixel(s);
  EXPECT_NEAR(L.g, expected, 1e-2 * expected) << L;
}

TEST(DirectLighting, QuadLightFacingAwayGivesNoLight) {
  pb::Scene s = FloorScene(16);
  AddQuad(s, "lamp", {-1, -1, 1.5}, {2, 0, 0}, {0, 2, 0});  // front +z: emits upwards
  EXPECT_EQ(RenderOnePixel(s), Rgb());
}

TEST(DirectLighting, BlockerCastsAFullShadow) {
  pb::Scene s = FloorScene(64);
  AddSphere(s, "lamp", {0, 0, 4}, 1);
  AddQuad(s, "floor", {-3, -3, 2}, {6, 0, 0}, {0, 6, 0});  // between floor point and light
  // The camera ray passes under the blocker (it hits the floor at grazing angle).
  EXPECT_EQ(RenderOnePixel(s), Rgb());
}

TEST(DirectLighting, CameraSeesEmitterRadianceOnItsFrontAndNothingOnItsBack) {
  pb::Scene s = MakeScene(3, 3, {0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 10, 4, 1);
  AddEmissive(s, "lamp", Rgb(1, 2, 3));
  AddQuad(s, "lamp", {-5, -5, 10}, {0, 10, 0}, {10, 0, 0});  // front -z: towards the camera
  const Image front = RenderTile(Scene::Build(s, NoBlobs()), nullptr, {0, 0, 3, 3});
  EXPECT_EQ(front.pixel(1, 1)[0], 1.0f);
  EXPECT_EQ(front.pixel(1, 1)[1], 2.0f);
  EXPECT_EQ(front.pixel(1, 1)[2], 3.0f);
  EXPECT_EQ(front.pixel(1, 1)[3], 1.0f);

  s.mutable_shapes(0)->mutable_quad()->mutable_edge_u()->set_y(0);
  s.mutable_shapes(0)->mutable_quad()->mutable_edge_u()->set_x(10);
  s.mutable_shapes(0)->mutable_quad()->mutable_edge_v()->set_x(0);
  s.mutable_shapes(0)->mutable_quad()->mutable_edge_v()->set_y(10);  // front +z: away
  const Image back = RenderTile(Scene::Build(s, NoBlobs()), nullptr, {0, 0, 3, 3});
  EXPECT_EQ(back.pixel(1, 1)[0], 0.0f);
  EXPECT_EQ(back.pixel(1, 1)[3], 1.0f);  // still a hit
}

TEST(DirectLighting, MissIsBlackWithZeroAlpha) {
  pb::Scene s = MakeScene(2, 2, {0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 10, 4, 1);
  AddLambert(s, "grey", Rgb(0.5f));
  AddSphere(s, "grey", {0, 0, -10}, 1);  // behind the camera
  AddPointLight(s, {0, 5, 0}, Rgb(1));
  const Image image = RenderTile(Scene::Build(s, NoBlobs()), nullptr, {0, 0, 2, 2});
  // Every channel is 0 but the one that counts the camera samples: 4 missed.
  const auto& names = image.channels();
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x)
      for (int c = 0; c < image.channel_count(); ++c)
        EXPECT_EQ(image.pixel(x, y)[c], names[c] == kSamplesChannel ? 4.0f : 0.0f) << names[c];
}

// A principled floor: a point light's radiance is the BRDF (principled.h) times I / d^2.
TEST(DirectLighting, PrincipledUnderAPointLightIsItsBrdfTimesTheIrradiance) {
  pb::Scene s = FloorScene(4);
  pb::Principled* p = s.mutable_materials(0)->mutable_principled();  // replaces the Lambert
  Set(p->mutable_base_color(), Rgb(0.5f, 0.25f, 1));
  p->set_metallic(0.3);
  p->set_roughness(0.5);
  AddPointLight(s, {0, 0, 4}, Rgb(16));
  const PrincipledLobes lobes{Rgb(0.5f, 0.25f, 1), 0.3f, 0.25f, false};
  const Rgb expected = PrincipledValue(lobes, Normalize(Vec3(10, 0, 1)), Vec3(0, 0, 1));  // times 16 / 4^2
  const Rgb L = RenderOnePixel(s);
  EXPECT_NEAR(L.r, expected.r, 1e-3f * expected.r) << L;
  EXPECT_NEAR(L.b, expected.b, 1e-3f * expected.b) << L;
}

// A smooth full metal is a mirror tinted by Schlick's Fresnel of its base colour: it shows
// the emitter in the mirror direction with radiance L F(cos theta).
TEST(DirectLighting, ASmoothMetalReflectsTheEmitterWithSchlicksFresnel) {
  pb::Scene s = FloorScene(16);
  pb::Principled* p = s.mutable_materials(0)->mutable_principled();
  Set(p->mutable_base_color(), Rgb(0.8f, 0.5f, 0.2f));
  p->set_metallic(1);
  AddSphere(s, "lamp", {-10, 0, 1}, 0.5);  // radiance 2, where the camera's mirror image looks
  const float cos = 1 / std::sqrt(101.0f), schlick = std::pow(1 - cos, 5.0f);
  const Rgb L = RenderOnePixel(s);
  EXPECT_NEAR(L.r, 2 * (0.8f + 0.2f * schlick), 2e-3f) << L;
  EXPECT_NEAR(L.b, 2 * (0.2f + 0.8f * schlick), 2e-3f) << L;
}

// A smooth dielectric is both: its diffuse base is shaded (the point light) and its lobe
// followed (the emitter in the mirror direction, with Schlick's Fresnel of 0.04); the two
// add up.
TEST(DirectLighting, ASmoothDielectricAddsItsBaseAndItsReflection) {
  pb::Scene s = FloorScene(256);
  pb::Principled* p = s.mutable_materials(0)->mutable_principled();
  Set(p->mutable_base_color(), Rgb(0.5f));
  AddPointLight(s, {0, 0, 4}, Rgb(16));
  AddSphere(s, "lamp", {-10, 0, 1}, 0.5);
  const Vec3 wo = Normalize(Vec3(10, 0, 1)), mirror(-wo.x, -wo.y, wo.z);
  const PrincipledLobes lobes{Rgb(0.5f), 0, kMinGgxAlpha, true};
  const float base = PrincipledValue(lobes, wo, Vec3(0, 0, 1)).g;  // times 16 / 4^2
  const float reflection = 2 * (0.04f + 0.96f * std::pow(1 - wo.z, 5.0f));
  // The sphere lights the base too: E = pi L sin^2 (its half angle) cos theta, small.
  const float sphere = PrincipledDiffuseWeight(lobes, wo, mirror).g / kPi * (kPi * 2 * (0.25f / 101) * wo.z);
  const Rgb L = RenderOnePixel(s);
  EXPECT_NEAR(L.g, base + reflection + sphere, 2e-3f * (base + reflection)) << L << " base " << base;
}

}  // namespace
}  // namespace farm
