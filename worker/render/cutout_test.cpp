// The alpha-test hook: a test-only cut-out, a checkerboard of holes over a fence, must let
// camera rays, shadow rays and photons through its holes and nowhere else, on shapes and
// on instanced mesh parts alike.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "photon/trace_photons.h"
#include "scene/scene_data.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

constexpr int kCells = 4;  // per side of the fence

// The checkerboard's holes: cells of odd (column + row) in texture space.
bool Hole(Vec2 uv) { return (int(std::floor(uv.x * kCells)) + int(std::floor(uv.y * kCells))) % 2 != 0; }

SceneOptions CheckerOnFences() {
  SceneOptions options;
  options.cutout_of = [](const pb::Material& m, int) -> CutoutTest {
    if (m.name() != "fence") return {};
    return [](const SurfaceHit& hit) { return Hole(hit.uv); };
  };
  return options;
}

// A 2 x 2 fence at y = 1 over a wide floor at y = 0, a point light above: the fence a quad
// (u along x from -1, v along z from -1), or a mesh of the same square placed by an
// instance.
pb::Scene FenceScene(bool instanced) {
  pb::Scene s = MakeScene(8, 8, {0, 6, -1}, {0, 0, 0}, {0, 1, 0}, 40);
  AddLambert(s, "floor", Rgb(0.5f));
  AddLambert(s, "fence", Rgb(0.5f));
  AddQuad(s, "floor", {-10, 0, 10}, {20, 0, 0}, {0, 0, -20});
  if (instanced) {
    AddMesh(s, "fence", {{FakeDigest("fence"), "fence"}});
    const double lift[12] = {1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 0};
    AddInstance(s, "fence", lift);
  } else {
    AddQuad(s, "fence", {-1, 1, -1}, {2, 0, 0}, {0, 0, 2});  // front: cross(x, z) = -y, down
  }
  AddPointLight(s, {0.1, 5, 0.2}, Rgb(50));
  return s;
}

// The fence's square in its own space, y = 0, with the quad's texture coordinates.
std::string FenceMesh() {
  TriangleMesh m;
  m.positions = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}};
  m.texcoords = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.indices = {0, 2, 1, 0, 3, 2};
  return FarmMeshBytes(m);
}

Scene BuildFence(bool instanced, const SceneOptions& options) {
  return Scene::Build(FenceScene(instanced), MapLoader({{FakeDigest("fence"), FenceMesh()}}), options);
}

// Where on the fence (u, v) a point of the fence's plane lies.
Vec2 FenceUv(const Vec3& p) { return {(p.x + 1) / 2, (p.z + 1) / 2}; }

// Cell centres of the fence, a little inset so that no ray grazes a cell's edge.
std::vector<Vec2> CellPoints() {
  std::vector<Vec2> points;
  for (int i = 0; i < kCells; ++i)
    for (int j = 0; j < kCells; ++j)
      for (const float d : {0.2f, 0.5f, 0.8f}) points.push_back({(i + d) / kCells, (j + 0.5f) / kCells});
  return points;
}

Vec3 FencePoint(Vec2 uv, float y) { return {2 * uv.x - 1, y, 2 * uv.y - 1}; }

TEST(Cutouts, CameraRaysPassThroughTheHoles) {
  for (const bool instanced : {false, true}) {
    SCOPED_TRACE(instanced ? "instanced fence" : "fence quad");
    const Scene scene = BuildFence(instanced, CheckerOnFences());
    const Scene solid = BuildFence(instanced, {});
    for (const Vec2 uv : CellPoints()) {
      const Ray down{FencePoint(uv, 3), {0, -1, 0}};
      const std::optional<SurfaceHit> hit = scene.data().Intersect(down);
      ASSERT_TRUE(hit);
      EXPECT_EQ(hit->p.y, Hole(uv) ? 0.0f : 1.0f) << "at uv " << ToString(uv);
      EXPECT_EQ(scene.data().material_names[hit->material], Hole(uv) ? "floor" : "fence");
      EXPECT_EQ(solid.data().Intersect(down)->p.y, 1.0f);  // without the cut-out, no holes
    }
  }
}

TEST(Cutouts, ShadowRaysPassThroughTheHoles) {
  for (const bool instanced : {false, true}) {
    SCOPED_TRACE(instanced ? "instanced fence" : "fence quad");
    const Scene scene = BuildFence(instanced, CheckerOnFences());
    const Vec3 up(0, 1, 0), light(0, 3, 0);
    for (const Vec2 uv : CellPoints()) {
      // A floor point below the cell along the line from the light through the cell.
      const Vec3 through = FencePoint(uv, 1);
      const Vec3 floor = light + (through - light) * 1.5f;
      EXPECT_EQ(scene.data().Visible(floor, up, light, Vec3()), Hole(uv)) << "at uv " << ToString(uv);
    }
  }
}

TEST(Cutouts, PhotonsPassThroughTheHoles) {
  for (const bool instanced : {false, true}) {
    SCOPED_TRACE(instanced ? "instanced fence" : "fence quad");
    const Scene scene = BuildFence(instanced, CheckerOnFences());
    const std::vector<ShardPhoton> photons =
        TracePhotons(scene, {PhotonMapKind::kGlobal, 0, 20000, 20000}, {.store_direct = true});
    const Vec3 light(0.1f, 5, 0.2f);
    int under = 0, on_fence = 0;
    for (const ShardPhoton& p : photons) {
      if (std::abs(p.position.y - 1) < 1e-4f) {  // stored on the fence: never in a hole
        ++on_fence;
        EXPECT_FALSE(Hole(FenceUv(p.position))) << ToString(p.position);
        continue;
      }
      if (std::abs(p.position.y) > 1e-4f || Length(p.wi - Normalize(light - p.position)) > 1e-3f) continue;
      // Came straight from the light to the floor: where it crossed the fence's plane.
      const Vec3 crossing = light + (p.position - light) * ((5 - 1) / (5 - p.position.y));
      const Vec2 uv = FenceUv(crossing);
      if (uv.x < 0 || uv.x > 1 || uv.y < 0 || uv.y > 1) continue;
      ++under;
      // How far inside its cell, in cells (a photon along a cell's edge may go either way).
      const float inset = std::min(std::abs(uv.x * kCells - std::round(uv.x * kCells)),
                                   std::abs(uv.y * kCells - std::round(uv.y * kCells)));
      if (inset > 0.01f) {
        EXPECT_TRUE(Hole(uv)) << "a photon crossed a solid cell at " << ToString(uv);
      }
    }
    std::printf("%d photons through the fence's holes, %d on it\n", under, on_fence);
    EXPECT_GT(under, 100);
    EXPECT_GT(on_fence, 100);
  }
}

}  // namespace
}  // namespace farm
