#include "scene/surface_shading.h"

// Before OIIO's headers (texture/texture_system.cpp says why).
#include "scene/test_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "contract/rules.h"
#include "scene/scene.h"
#include "texture/test_images.h"

namespace farm {
namespace {

using namespace farm::testing;

// A floor quad (normal +y) with one principled material whose every texture is a small
// float image (linear whatever its use), and a texture no material names.
class SurfaceShadingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = FreshTestDir("surface_shading_test", ::testing::UnitTest::GetInstance()->current_test_info()->name());
    textures_ = std::make_unique<TextureSystem>(TextureSystemOptions{16, dir_ / "prepared"});
    description_ = MakeScene(8, 8, {0, 2, -2}, {0, 0, 0}, {0, 1, 0}, 40);
    // Base colour: RGB (0.5, 0.25, 1); opacity 0 in the left column, 1 in the right one.
    Image("base", 2, 1, 4, [](int x, int, int c) { return c == 3 ? float(x) : (c == 0 ? 0.5f : c == 1 ? 0.25f : 1); });
    Image("mr", 1, 1, 3, [](int, int, int c) { return c == 1 ? 0.5f : c == 2 ? 0.25f : 0; });  // roughness, metallic
    Image("normal", 1, 1, 3, [](int, int, int c) { return c == 0 ? 1.0f : c == 1 ? 0.5f : 1.0f; });  // +X, tilted
    Image("glow", 1, 1, 3, [](int, int, int c) { return c == 0 ? 2.0f : 0.5f; });
    Image("unused", 1, 1, 3, [](int, int, int) { return 1.0f; });
    pb::Material* m = description_.add_materials();
    m->set_name("painted");
    pb::Principled* p = m->mutable_principled();
    Set(p->mutable_base_color(), Rgb(0.5f, 1, 1));
    p->set_metallic(0.8);
    p->set_roughness(0.6);
    p->mutable_base_color_texture()->set_texture("base");
    p->mutable_metallic_roughness_texture()->set_texture("mr");
    p->mutable_normal_texture()->set_texture("normal");
    p->set_normal_scale(0.5);
    Set(p->mutable_emission(), Rgb(1, 2, 4));
    p->mutable_emission_texture()->set_texture("glow");
    p->set_alpha_mode(pb::ALPHA_MODE_MASK);
    p->set_transparency(0.2);
    p->set_alpha_cutoff(0.5);
    AddQuad(description_, "painted", {-1, 0, -1}, {0, 0, 2}, {2, 0, 0});  // front +y
    AddPointLight(description_, {0, 3, 0}, Rgb(1));
  }
  void TearDown() override {
    textures_.reset();
    std::filesystem::remove_all(dir_);
  }

  void Image(const std::string& name, int width, int height, int channels, const std::function<float(int, int, int)>& value) {
    const std::string digest = FakeDigest(name);
    WriteTestImage(dir_ / name, "exr", width, height, channels, OIIO::TypeDesc::FLOAT, value);
    files_[digest] = dir_ / name;
    pb::Texture* t = description_.add_textures();
    t->set_name(name);
    t->set_path(name + ".exr");
    t->set_digest(digest);
    t->set_wrap(pb::TEXTURE_WRAP_CLAMP);
  }

  // cutouts: whether the accelerator runs the materials' cut-out tests, as a worker's does;
  // without them rays meet the floor everywhere, for the tests that read a hit's material.
  Scene Build(bool cutouts = false) {
    SceneOptions options;
    if (!cutouts) options.cutout_of = [](const pb::Material&, int) { return CutoutTest(); };
    options.textures = textures_.get();
    options.load_file = [this](const std::string& digest) {
      fetched_.insert(digest);
      return files_.at(digest);
    };
    return Scene::Build(description_, NoBlobs(), options);
  }

  // The floor's hit straight below the camera's look-at point, with texture coordinates
  // (as the geometry gives them where it has them).
  static SurfaceHit FloorHit(const SceneData& data, Vec2 uv) {
    std::optional<SurfaceHit> hit = data.Intersect(Ray{Vec3(0, 1, 0), Vec3(0, -1, 0)});
    EXPECT_TRUE(hit);
    hit->uv = uv;
    hit->has_uv = true;
    hit->dpdu = Vec3(2, 0, 0);
    hit->dpdv = Vec3(0, 0, 2);
    return *hit;
  }

  // What the cut-out test gets of a hit.
  static CutoutHit Candidate(const SurfaceHit& hit) { return {hit.material, hit.uv, hit.has_uv}; }

  std::filesystem::path dir_;
  std::unique_ptr<TextureSystem> textures_;
  pb::Scene description_;
  std::map<std::string, std::filesystem::path> files_;
  std::set<std::string> fetched_;
};

TEST_F(SurfaceShadingTest, TexturesMultiplyTheFactors) {
  const Scene scene = Build();
  const SurfaceHit hit = FloorHit(scene.data(), {0.75f, 0.5f});
  const Material at = MaterialAt(scene.data(), hit, Vec3(0, -1, 0), TextureRead{0.01f});
  const auto& m = std::get<PrincipledMaterial>(at);
  EXPECT_NEAR(m.lobes.base_color.r, 0.25f, 1e-6f);
  EXPECT_NEAR(m.lobes.base_color.g, 0.25f, 1e-6f);
  EXPECT_NEAR(m.lobes.base_color.b, 1.0f, 1e-6f);
  EXPECT_NEAR(m.lobes.metallic, 0.2f, 1e-6f) << "blue channel";
  EXPECT_NEAR(m.roughness, 0.3f, 1e-6f) << "green channel";
  EXPECT_NEAR(m.lobes.alpha, 0.09f, 1e-6f);
  EXPECT_NEAR(m.emission.r, 2.0f, 1e-6f);
  EXPECT_NEAR(m.emission.b, 2.0f, 1e-6f);
  // The normal map's (1, 0.5, 1) is (1, 0, 1) in tangent space, X scaled by 0.5: tilted
  // towards dp/du (+x) by atan(0.5).
  EXPECT_NEAR(m.shading_normal.x, 0.5f / std::sqrt(1.25f), 1e-5f);
  EXPECT_NEAR(m.shading_normal.y, 1 / std::sqrt(1.25f), 1e-5f);
  EXPECT_NEAR(m.shading_normal.z, 0, 1e-6f);
  // The declared material is left as it was.
  EXPECT_EQ(std::get<PrincipledMaterial>(scene.data().material_of(hit)).lobes.base_color, Rgb(0.5f, 1, 1));
}

TEST_F(SurfaceShadingTest, OnlyTheNamedTexturesAreFetchedEachOnce) {
  const Scene scene = Build();
  EXPECT_EQ(fetched_, (std::set<std::string>{FakeDigest("base"), FakeDigest("mr"), FakeDigest("normal"), FakeDigest("glow")}));
  EXPECT_EQ(scene.data().textures.size(), 4u);
  fetched_.clear();
  Build();
  EXPECT_TRUE(fetched_.empty()) << "prepared textures are not fetched again";
}

TEST_F(SurfaceShadingTest, AGlossyMaterialStaysGlossyWhateverItsTexturedRoughness) {
  const double threshold = contract::SceneLimits().principled_specular_roughness();
  description_.mutable_materials(0)->mutable_principled()->set_roughness(1.5 * threshold);  // 0.75 of it textured
  const Scene scene = Build();
  const auto m = std::get<PrincipledMaterial>(MaterialAt(scene.data(), FloorHit(scene.data(), {0.5f, 0.5f}), Vec3(0, -1, 0), TextureRead{}));
  EXPECT_FALSE(m.lobes.specular);
  EXPECT_NEAR(m.roughness, threshold, 1e-6f) << "raised to principled_specular_roughness";
}

TEST_F(SurfaceShadingTest, AlphaMaskCutsWhereOpacityIsBelowTheCutoff) {
  const Scene scene = Build();
  // Opacity 0.8 times the texture's 0 (left) or 1 (right), against a cutoff of 0.5.
  EXPECT_TRUE(IsCutOut(scene.data(), Candidate(FloorHit(scene.data(), {0.25f, 0.5f}))));
  EXPECT_FALSE(IsCutOut(scene.data(), Candidate(FloorHit(scene.data(), {0.75f, 0.5f}))));
  description_.mutable_materials(0)->mutable_principled()->set_transparency(0.6);  // 0.4 < 0.5
  const Scene thin = Build();
  EXPECT_TRUE(IsCutOut(thin.data(), Candidate(FloorHit(thin.data(), {0.75f, 0.5f}))));
  const auto cutout = CutoutOf(thin.data(), 0);
  ASSERT_TRUE(cutout);
  EXPECT_TRUE(cutout(Candidate(FloorHit(thin.data(), {0.75f, 0.5f}))));
  description_.mutable_materials(0)->mutable_principled()->set_alpha_mode(pb::ALPHA_MODE_OPAQUE);
  const Scene opaque = Build();
  EXPECT_FALSE(IsCutOut(opaque.data(), Candidate(FloorHit(opaque.data(), {0.25f, 0.5f}))));
  EXPECT_FALSE(CutoutOf(opaque.data(), 0)) << "an opaque material installs no test";
}

TEST_F(SurfaceShadingTest, RaysPassWhereTheAlphaMaskCuts) {
  const Scene scene = Build(/*cutouts=*/true);
  // u runs along z from -1: the left column (u < 0.5, opacity 0) is cut, the right one
  // (opacity 0.8 against the cutoff 0.5) is there.
  EXPECT_FALSE(scene.data().Intersect(Ray{Vec3(0, 1, -0.5f), Vec3(0, -1, 0)}));
  EXPECT_TRUE(scene.data().Intersect(Ray{Vec3(0, 1, 0.5f), Vec3(0, -1, 0)}));
}

TEST_F(SurfaceShadingTest, ATexturedEmitterIsSampledWithItsMeanRadiance) {
  const Scene scene = Build();
  ASSERT_EQ(scene.data().lights.size(), 2u) << "the floor is an area light";
  const Rgb radiance = AreaLightRadiance(scene.data(), scene.data().materials[0]);
  EXPECT_NEAR(radiance.r, 2.0f, 1e-5f);
  EXPECT_NEAR(radiance.g, 1.0f, 1e-5f);
  EXPECT_NEAR(radiance.b, 2.0f, 1e-5f);
}

TEST_F(SurfaceShadingTest, WithoutTextureCoordinatesTheFactorsApply) {
  const Scene scene = Build();
  SurfaceHit hit = FloorHit(scene.data(), {0.75f, 0.5f});
  hit.has_uv = false;
  const auto m = std::get<PrincipledMaterial>(MaterialAt(scene.data(), hit, Vec3(0, -1, 0), TextureRead{}));
  EXPECT_EQ(m.lobes.base_color, Rgb(0.5f, 1, 1));
  EXPECT_EQ(m.shading_normal, hit.ns);
}

TEST_F(SurfaceShadingTest, ABrokenTextureIsRefusedNamingTheFieldAndTheFile) {
  std::ofstream(files_.at(FakeDigest("mr"))) << "not an image";
  try {
    Build();
    FAIL() << "a text file was read as a texture";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("materials[0].principled.metallic_roughness_texture: texture \"mr.exr\""),
              std::string::npos)
        << e.what();
  }
}

TEST_F(SurfaceShadingTest, AWorkerWithoutATextureSystemSaysSo) {
  try {
    Scene::Build(description_, NoBlobs());
    FAIL() << "built without a texture system";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("without a texture system"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace farm
