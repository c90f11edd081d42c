#include "scene/scene_rules.h"

#include <gtest/gtest.h>

#include "contract/test_json.h"
#include "scene/scene.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

// A scene that keeps every rule: a grey sphere on a quad floor under a point light.
pb::Scene Valid() {
  return testing::FromJson<pb::Scene>(R"({
    "camera": {"position": {"z": -5}, "lookAt": {}, "up": {"y": 1}, "verticalFovDegrees": 40},
    "film": {"width": 64, "height": 48},
    "materials": [
      {"name": "grey", "lambert": {"reflectance": {"r": 0.5, "g": 0.5, "b": 0.5}}},
      {"name": "lamp", "emissive": {"radiance": {"r": 1, "g": 1, "b": 1}}}
    ],
    "shapes": [
      {"material": "grey", "sphere": {"center": {}, "radius": 1}},
      {"material": "grey", "quad": {"origin": {"x": -5, "y": -1, "z": -5}, "edgeU": {"x": 10}, "edgeV": {"z": 10}}}
    ],
    "lights": [{"point": {"position": {"y": 3}, "intensity": {"r": 1, "g": 1, "b": 1}}}]
  })");
}

std::string Refusal(const pb::Scene& s) {
  try {
    CheckScene(s);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(CheckScene, AcceptsAValidScene) { EXPECT_EQ(Refusal(Valid()), "accepted"); }

TEST(CheckScene, FieldRulesComeFirst) {
  pb::Scene s = Valid();
  s.mutable_sampling()->set_light_samples(4096);  // the worker allowed this before the contract
  s.mutable_camera()->mutable_look_at()->set_z(-5);  // and this breaks a structural rule
  EXPECT_EQ(Refusal(s), "sampling.light_samples: must be <= 1024 (0 selects 16), got 4096");
}

struct Case {
  const char* name;
  void (*change)(pb::Scene&);
  const char* want;  // the whole refusal, or "accepted"
};

void ExpectRefusals(const std::vector<Case>& cases) {
  for (const Case& c : cases) {
    pb::Scene s = Valid();
    c.change(s);
    EXPECT_EQ(Refusal(s), c.want) << c.name;
  }
}

TEST(CheckScene, Camera) {
  ExpectRefusals({
      {"look_at at the position", [](pb::Scene& s) { s.mutable_camera()->mutable_look_at()->set_z(-5); },
       "camera.look_at: must differ from camera.position, both are (0, 0, -5)"},
      {"zero up", [](pb::Scene& s) { s.mutable_camera()->mutable_up()->set_y(0); }, "camera.up: must be non-zero"},
      {"up along the view", [](pb::Scene& s) { s.mutable_camera()->mutable_up()->set_z(2); s.mutable_camera()->mutable_up()->set_y(0); },
       "camera.up: must not be parallel to the view direction look_at - position = (0, 0, 5), got (0, 0, 2)"},
      {"up nearly along the view, past 1e-9", [](pb::Scene& s) { s.mutable_camera()->mutable_up()->set_z(1); s.mutable_camera()->mutable_up()->set_y(1e-8); },
       "accepted"},
  });
}

TEST(CheckScene, TilesPerRound) {
  ExpectRefusals({
      {"default tiles", [](pb::Scene& s) { s.mutable_film()->set_width(16384); s.mutable_film()->set_height(512); },
       "accepted"},  // 512 x 16 tiles of 32
      {"small tiles", [](pb::Scene& s) { s.mutable_film()->set_width(16384); s.mutable_film()->set_height(4096); s.mutable_film()->set_tile_size(8); },
       "film.tile_size: makes 1048576 tiles (2048 x 512 of 8 pixels) in the 16384x4096 film, more than the 65536 a "
       "round may have"},
      {"exactly the limit", [](pb::Scene& s) { s.mutable_film()->set_width(2048); s.mutable_film()->set_height(2041); s.mutable_film()->set_tile_size(8); },
       "accepted"},  // 256 x 256 (2041 / 8 rounds up)
  });
}

TEST(CheckScene, FilmPixels) {
  ExpectRefusals({
      {"at the limit", [](pb::Scene& s) { s.mutable_film()->set_width(4096); s.mutable_film()->set_height(2048); },
       "accepted"},
      {"one row more", [](pb::Scene& s) { s.mutable_film()->set_width(4096); s.mutable_film()->set_height(2049); },
       "film.height: a 4096x2049 film has 8392704 pixels, more than the 8388608 a film may have"},
  });
}

TEST(CheckScene, Materials) {
  ExpectRefusals({
      {"duplicate name", [](pb::Scene& s) { *s.add_materials() = s.materials(0); },
       "materials[2].name: duplicate material name \"grey\""},
      {"glossy too bright", [](pb::Scene& s) {
         pb::Glossy* g = s.mutable_materials(0)->mutable_glossy();
         g->mutable_diffuse()->set_g(0.75);
         g->mutable_specular()->set_g(0.5);
         g->set_exponent(10);
       },
       "materials[0].glossy.specular.g: diffuse + specular must be <= 1 (energy conservation), got 0.75 + 0.5"},
  });
}

TEST(CheckScene, Quads) {
  ExpectRefusals({
      {"unknown material", [](pb::Scene& s) { s.mutable_shapes(1)->set_material("chrome"); },
       "shapes[1].material: no material named \"chrome\""},
      {"zero edge_u", [](pb::Scene& s) { s.mutable_shapes(1)->mutable_quad()->mutable_edge_u()->set_x(0); },
       "shapes[1].quad.edge_u: must be non-zero"},
      {"zero edge_v", [](pb::Scene& s) { s.mutable_shapes(1)->mutable_quad()->mutable_edge_v()->set_z(0); },
       "shapes[1].quad.edge_v: must be non-zero"},
      {"parallel edges",
       [](pb::Scene& s) {
         pb::Vec3* v = s.mutable_shapes(1)->mutable_quad()->mutable_edge_v();
         v->set_x(-3);
         v->set_z(0);
       },
       "shapes[1].quad.edge_v: must not be parallel to edge_u (10, 0, 0), got (-3, 0, 0)"},
  });
}

void SetTriangles(pb::Scene& s, std::initializer_list<std::uint32_t> indices) {
  pb::TriangleMesh* t = s.mutable_shapes(1)->mutable_triangles();
  for (int i = 0; i < 3; ++i) {
    pb::Vec3* p = t->add_positions();
    p->set_x(i == 1);
    p->set_y(i == 2);
  }
  for (std::uint32_t i : indices) t->add_indices(i);
}

TEST(CheckScene, InlineTriangles) {
  ExpectRefusals({
      {"one triangle", [](pb::Scene& s) { SetTriangles(s, {0, 1, 2}); }, "accepted"},
      {"no indices", [](pb::Scene& s) { SetTriangles(s, {}); },
       "shapes[1].triangles.indices: count must be a non-zero multiple of 3, got 0"},
      {"not a multiple of 3", [](pb::Scene& s) { SetTriangles(s, {0, 1, 2, 0}); },
       "shapes[1].triangles.indices: count must be a non-zero multiple of 3, got 4"},
      {"past the positions", [](pb::Scene& s) { SetTriangles(s, {0, 1, 2, 2, 1, 3}); },
       "shapes[1].triangles.indices[5]: must be < 3 (the number of positions), got 3"},
  });
}

void SetMesh(pb::Scene& s) {
  pb::MeshFile* m = s.mutable_shapes(1)->mutable_mesh();
  m->set_path("bunny.obj");
  m->set_digest("sha256:" + std::string(64, 'a'));
}

TEST(CheckScene, MeshTransforms) {
  ExpectRefusals({
      {"no transform", [](pb::Scene& s) { SetMesh(s); }, "accepted"},
      {"zero scale component",
       [](pb::Scene& s) {
         SetMesh(s);
         pb::Vec3* scale = s.mutable_shapes(1)->mutable_mesh()->mutable_transform()->mutable_scale();
         scale->set_x(2);
         scale->set_y(2);
       },
       "shapes[1].mesh.transform.scale.z: must be non-zero"},
      {"rotation about no axis",
       [](pb::Scene& s) {
         SetMesh(s);
         s.mutable_shapes(1)->mutable_mesh()->mutable_transform()->set_rotation_degrees(90);
       },
       "shapes[1].mesh.transform.rotation_axis: must be non-zero when rotation_degrees is 90"},
      {"no rotation, no axis",
       [](pb::Scene& s) {
         SetMesh(s);
         s.mutable_shapes(1)->mutable_mesh()->mutable_transform()->mutable_translation()->set_x(1);
       },
       "accepted"},
  });
}

TEST(CheckScene, Lights) {
  ExpectRefusals({
      {"zero sun direction",
       [](pb::Scene& s) {
         pb::SunLight* sun = s.add_lights()->mutable_sun();
         sun->mutable_direction();
         sun->mutable_irradiance()->set_r(1);
       },
       "lights[1].sun.direction: must be non-zero"},
      {"a black point light only", [](pb::Scene& s) { s.mutable_lights(0)->mutable_point()->clear_intensity(); s.mutable_lights(0)->mutable_point()->mutable_intensity(); },
       "lights: the scene needs a light: a point or sun light with a positive power, or a shape whose material is "
       "emissive with a positive radiance"},
      {"no lights, an emissive material no shape uses", [](pb::Scene& s) { s.clear_lights(); },
       "lights: the scene needs a light: a point or sun light with a positive power, or a shape whose material is "
       "emissive with a positive radiance"},
      {"an emissive shape", [](pb::Scene& s) { s.clear_lights(); s.mutable_shapes(1)->set_material("lamp"); },
       "accepted"},
      {"a sun", [](pb::Scene& s) {
         s.clear_lights();
         pb::SunLight* sun = s.add_lights()->mutable_sun();
         sun->mutable_direction()->set_y(-1e-200);  // tiny but not zero
         sun->mutable_irradiance()->set_b(0.5);
       },
       "accepted"},
  });
}

TEST(CheckScene, ShardsPerMap) {
  ExpectRefusals({
      {"the limit", [](pb::Scene& s) {
         s.mutable_photons()->set_global_photons(10'000'000);
         s.mutable_photons()->set_photons_per_shard(1000);
       },
       "accepted"},
      {"past the limit", [](pb::Scene& s) {
         s.mutable_photons()->set_global_photons(10'000'001);
         s.mutable_photons()->set_photons_per_shard(1000);
       },
       "photons.photons_per_shard: makes 10001 shards of the global map's 10000001 photon paths, more than the "
       "10000 a map may have"},
      {"a caustic map the scene does not use", [](pb::Scene& s) {
         s.mutable_photons()->set_caustic_photons(50'000'000);
         s.mutable_photons()->set_photons_per_shard(1000);
       },
       // A rule on the settings: counted whether or not the scene gets the map.
       "photons.photons_per_shard: makes 50000 shards of the caustic map's 50000000 photon paths, more than the "
       "10000 a map may have"},
  });
}

TEST(CheckScene, ReferenceImage) {
  ExpectRefusals({
      {"path without digest", [](pb::Scene& s) { s.mutable_progressive()->mutable_reference()->set_path("ref.exr"); },
       "progressive.reference.digest: missing: the client uploads the file at path \"ref.exr\" and sets its digest"},
      {"both", [](pb::Scene& s) {
         s.mutable_progressive()->mutable_reference()->set_path("ref.exr");
         s.mutable_progressive()->mutable_reference()->set_digest("sha256:" + std::string(64, '0'));
       },
       "accepted"},
  });
}

}  // namespace
}  // namespace farm
