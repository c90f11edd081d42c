// The alpha-test hook: a checkerboard of holes over a fence must let camera rays, shadow
// rays and photons through its holes and nowhere else, on shapes and on instanced mesh
// parts alike; whether the holes are a test-only cut-out given to Scene::Build or what the
// scene says (an alpha-masked principled fence whose base colour texture's alpha is 0 in
// the holes, which Scene::Build connects to the hook by itself).

// Before OIIO's headers (texture/texture_system.cpp says why).
#include "scene/test_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "photon/trace_photons.h"
#include "scene/scene_data.h"
#include "texture/test_images.h"
#include "texture/texture_system.h"

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
    return [](const CutoutHit& hit) { return Hole(hit.uv); };
  };
  return options;
}

// How the fence gets its holes.
enum class Holes {
  kHook,       // a Lambert fence, the holes cut by CheckerOnFences given to Scene::Build
  kAlphaMask,  // an alpha-masked principled fence whose texture's alpha is 0 in the holes
};

constexpr int kTexels = 64;  // per side of the mask's texture: 16 a cell, so that the
                             // filtered alpha crosses the cutoff at the cells' edges

// A 2 x 2 fence at y = 1 over a wide floor at y = 0, a point light above: the fence a quad
// (u along x from -1, v along z from -1), or a mesh of the same square placed by an
// instance.
pb::Scene FenceScene(bool instanced, Holes holes) {
  pb::Scene s = MakeScene(8, 8, {0, 6, -1}, {0, 0, 0}, {0, 1, 0}, 40);
  AddLambert(s, "floor", Rgb(0.5f));
  if (holes == Holes::kHook) {
    AddLambert(s, "fence", Rgb(0.5f));
  } else {
    pb::Material* m = s.add_materials();
    m->set_name("fence");
    pb::Principled* p = m->mutable_principled();
    Set(p->mutable_base_color(), Rgb(0.5f));
    p->set_roughness(1);
    p->mutable_base_color_texture()->set_texture("holes");
    p->set_alpha_mode(pb::ALPHA_MODE_MASK);
    p->set_alpha_cutoff(0.5);
    pb::Texture* t = s.add_textures();
    t->set_name("holes");
    t->set_path("holes.png");
    t->set_digest(FakeDigest("holes"));
    t->set_wrap(pb::TEXTURE_WRAP_CLAMP);
  }
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

// Builds fences: with the holes cut one way or the other, or solid (the Lambert fence
// without the hook). The alpha-masked fence's texture is a PNG (texture space's v runs down
// the image) in a scratch folder, read by a texture system of the builder's own.
class FenceBuilder {
 public:
  explicit FenceBuilder(Holes holes) : holes_(holes) {
    if (holes != Holes::kAlphaMask) return;
    dir_ = FreshTestDir("cutout_test", ::testing::UnitTest::GetInstance()->current_test_info()->name());
    textures_ = std::make_unique<TextureSystem>(TextureSystemOptions{16, dir_ / "prepared"});
    WriteTestImage(dir_ / "holes", "png", kTexels, kTexels, 4, OIIO::TypeDesc::UINT8, [](int x, int y, int c) {
      return c < 3 ? 1.0f : Hole({(x + 0.5f) / kTexels, (y + 0.5f) / kTexels}) ? 0.0f : 1.0f;
    });
  }
  ~FenceBuilder() {
    textures_.reset();
    if (!dir_.empty()) std::filesystem::remove_all(dir_);
  }

  Scene Build(bool instanced) const {
    SceneOptions options;
    if (holes_ == Holes::kHook) options = CheckerOnFences();
    options.textures = textures_.get();
    options.load_file = [this](const std::string&) { return dir_ / "holes"; };
    return Scene::Build(FenceScene(instanced, holes_), FenceBlobs(), options);
  }

  static Scene Solid(bool instanced) { return Scene::Build(FenceScene(instanced, Holes::kHook), FenceBlobs()); }

 private:
  static BlobLoader FenceBlobs() { return MapLoader({{FakeDigest("fence"), FenceMesh()}}); }

  Holes holes_;
  std::filesystem::path dir_;
  std::unique_ptr<TextureSystem> textures_;
};

// Every combination the tests run: the fence a quad or an instance, its holes cut by the
// hook or by its alpha mask.
struct FenceCase {
  bool instanced;
  Holes holes;
  std::string Name() const {
    return std::string(instanced ? "instanced fence" : "fence quad") + (holes == Holes::kHook ? ", test hook" : ", alpha mask");
  }
};

std::vector<FenceCase> FenceCases() {
  std::vector<FenceCase> cases;
  for (const Holes holes : {Holes::kHook, Holes::kAlphaMask})
    for (const bool instanced : {false, true}) cases.push_back({instanced, holes});
  return cases;
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
  for (const FenceCase& c : FenceCases()) {
    SCOPED_TRACE(c.Name());
    const FenceBuilder builder(c.holes);  // outlives the scene: it holds the texture system
    const Scene scene = builder.Build(c.instanced);
    const Scene solid = FenceBuilder::Solid(c.instanced);
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
  for (const FenceCase& c : FenceCases()) {
    SCOPED_TRACE(c.Name());
    const FenceBuilder builder(c.holes);
    const Scene scene = builder.Build(c.instanced);
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
  for (const FenceCase& c : FenceCases()) {
    SCOPED_TRACE(c.Name());
    const FenceBuilder builder(c.holes);
    const Scene scene = builder.Build(c.instanced);
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
