// DiscCoverage against the shares of a disc that simple geometry leaves: the open middle of
// a floor, the foot of a wall, a corner, a block's rim, the curved inside of a sphere.

#include "scene/disc_coverage.h"

#include <gtest/gtest.h>

#include <cmath>

#include "math/math.h"
#include "scene/scene.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

// The floor [0, 4]^2 at z = 0 with walls rising along x = 0 and y = 0, and a block
// [2, 3]^2 x [0, 1] standing on it (its top is a rim all round).
Scene Room() {
  pb::Scene s = MakeScene(4, 4, {3, 3, 3}, {0, 0, 0}, {0, 0, 1}, 40);
  AddLambert(s, "white", Rgb(0.5f));
  AddQuad(s, "white", {0, 0, 0}, {4, 0, 0}, {0, 4, 0});  // floor
  AddQuad(s, "white", {0, 0, 0}, {0, 4, 0}, {0, 0, 4});  // wall x = 0
  AddQuad(s, "white", {0, 0, 0}, {0, 0, 4}, {4, 0, 0});  // wall y = 0
  AddQuad(s, "white", {2, 2, 1}, {1, 0, 0}, {0, 1, 0});  // the block's top
  AddQuad(s, "white", {2, 2, 0}, {1, 0, 0}, {0, 0, 1});  // its sides
  AddQuad(s, "white", {2, 3, 0}, {1, 0, 0}, {0, 0, 1});
  AddQuad(s, "white", {2, 2, 0}, {0, 1, 0}, {0, 0, 1});
  AddQuad(s, "white", {3, 2, 0}, {0, 1, 0}, {0, 0, 1});
  AddPointLight(s, {1, 1, 3}, Rgb(1));
  return Scene::Build(s, NoBlobs());
}

// The share of a disc left when a straight edge cuts off the part beyond distance d r from
// its centre.
float ShareInside(float d) { return 1 - (std::acos(d) - d * std::sqrt(1 - d * d)) / kPi; }

// The mean over many seeds: each is a stratified 16-point estimate of the share.
float MeanCoverage(const SceneData& scene, const Vec3& p, const Vec3& n, float r) {
  double sum = 0;
  const int seeds = 64;
  for (int seed = 0; seed < seeds; ++seed) sum += DiscCoverage(scene, p, n, r, uint32_t(seed));
  return float(sum / seeds);
}

TEST(DiscCoverage, IsTheShareOfTheDiscThatIsSurface) {
  const Scene room = Room();
  const SceneData& d = room.data();
  const Vec3 up(0, 0, 1);
  EXPECT_EQ(DiscCoverage(d, {1.2f, 3, 0}, up, 0.3f, 1), 1.0f);        // the open floor
  // Points a fiftieth of the radius from the edges (a photon is never exactly on one).
  const float e = 0.006f, half = ShareInside(e / 0.3f);
  EXPECT_NEAR(MeanCoverage(d, {e, 3, 0}, up, 0.3f), half, 0.04f);            // the foot of a wall
  EXPECT_NEAR(MeanCoverage(d, {e, e, 0}, up, 0.3f), half * half, 0.04f);     // a corner
  EXPECT_NEAR(MeanCoverage(d, {3 - e, 2.5f, 1}, up, 0.3f), half, 0.04f);     // the block's rim
  EXPECT_NEAR(MeanCoverage(d, {3 - e, 3 - e, 1}, up, 0.3f), half * half, 0.04f);  // its top's corner
  EXPECT_NEAR(MeanCoverage(d, {2 - e, 2.5f, 0}, up, 0.3f), half, 0.04f);     // where it meets the floor
  // A wall's foot seen from the wall, a third of the radius up: its disc hangs below the floor.
  EXPECT_NEAR(MeanCoverage(d, {0, 3, 0.1f}, Vec3(1, 0, 0), 0.3f), ShareInside(1.0f / 3), 0.04f);
  // Halfway out from the wall, a circular segment of the disc is lost.
  EXPECT_NEAR(MeanCoverage(d, {0.15f, 3, 0}, up, 0.3f), ShareInside(0.5f), 0.04f);
}

TEST(DiscCoverage, TheInsideOfASphereIsCoveredAllOver) {
  pb::Scene s = MakeScene(4, 4, {0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 40);
  AddLambert(s, "white", Rgb(0.5f));
  AddSphere(s, "white", {0, 0, 0}, 1);
  AddPointLight(s, {0, 0, 0}, Rgb(1));
  const Scene scene = Scene::Build(s, NoBlobs());
  for (uint32_t seed = 0; seed < 8; ++seed)
    EXPECT_EQ(DiscCoverage(scene.data(), {0, 0, 1}, {0, 0, -1}, 0.1f, seed), 1.0f);
}

TEST(DiscCoverage, WeightsProbesByTheKernel) {
  const Scene room = Room();
  // A kernel that counts only the inner half of the radius: at a wall's foot a disc of
  // half the radius hangs over the edge just as much, so the share is still a half.
  const float inner = DiscCoverage(room.data(), {0.006f, 3, 0}, {0, 0, 1}, 0.3f, 5,
                                   [](float u) { return u < 0.5f ? 1.0f : 0.0f; });
  EXPECT_NEAR(inner, 0.5f, 0.2f);
  // Halfway out from the wall, that inner disc is all surface.
  EXPECT_EQ(DiscCoverage(room.data(), {0.16f, 3, 0}, {0, 0, 1}, 0.3f, 5,
                         [](float u) { return u < 0.5f ? 1.0f : 0.0f; }),
            1.0f);
}

}  // namespace
}  // namespace farm
