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

// Each case's change of the scene `base` makes.
void ExpectRefusals(const std::vector<Case>& cases, pb::Scene (*base)() = Valid) {
  for (const Case& c : cases) {
    pb::Scene s = base();
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
       "materials[2].name: duplicate material name \"grey\" (also materials[0])"},
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

constexpr const char* kNoLight =
    "lights: the scene needs a light: a point, spot or sun light with a positive component, a shape whose material "
    "emits (emissive with a positive radiance, or principled with a positive emission), or an environment that is "
    "not black";

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
       kNoLight},
      {"no lights, an emissive material no shape uses", [](pb::Scene& s) { s.clear_lights(); },
       kNoLight},
      {"an emissive shape", [](pb::Scene& s) { s.clear_lights(); s.mutable_shapes(1)->set_material("lamp"); },
       "accepted"},
      {"a sun", [](pb::Scene& s) {
         s.clear_lights();
         pb::SunLight* sun = s.add_lights()->mutable_sun();
         sun->mutable_direction()->set_y(-1e-200);  // tiny but not zero
         sun->mutable_irradiance()->set_b(0.5);
       },
       "accepted"},
      {"a spot light", [](pb::Scene& s) {
         s.clear_lights();
         pb::SpotLight* spot = s.add_lights()->mutable_spot();
         spot->mutable_position();
         spot->mutable_direction()->set_y(-1);
         spot->mutable_intensity()->set_g(1);
         spot->set_inner_cone_degrees(30);
         spot->set_outer_cone_degrees(30);
       },
       "accepted"},
      {"a spot light's cones the wrong way round", [](pb::Scene& s) {
         pb::SpotLight* spot = s.add_lights()->mutable_spot();
         spot->mutable_position();
         spot->mutable_direction()->set_y(-1);
         spot->mutable_intensity();
         spot->set_inner_cone_degrees(30.5);
         spot->set_outer_cone_degrees(30);
       },
       "lights[1].spot.inner_cone_degrees: must be at most outer_cone_degrees 30, got 30.5"},
      {"a spot light without direction", [](pb::Scene& s) {
         pb::SpotLight* spot = s.add_lights()->mutable_spot();
         spot->mutable_position();
         spot->mutable_direction();
         spot->mutable_intensity();
         spot->set_outer_cone_degrees(30);
       },
       "lights[1].spot.direction: must be non-zero"},
      {"principled emission", [](pb::Scene& s) {
         s.clear_lights();
         pb::Material* m = s.add_materials();
         m->set_name("glow");
         m->mutable_principled()->mutable_emission()->set_r(1e-300);  // below float, but positive
         s.mutable_shapes(0)->set_material("glow");
       },
       "accepted"},
      {"an environment map", [](pb::Scene& s) {
         s.clear_lights();
         pb::Texture* t = s.add_textures();
         t->set_name("sky");
         t->set_digest("sha256:" + std::string(64, '0'));
         s.mutable_environment()->mutable_map()->set_texture("sky");
       },
       "accepted"},
      {"an environment map times black", [](pb::Scene& s) {
         s.clear_lights();
         pb::Texture* t = s.add_textures();
         t->set_name("sky");
         t->set_digest("sha256:" + std::string(64, '0'));
         s.mutable_environment()->mutable_map()->set_texture("sky");
         s.mutable_environment()->mutable_radiance();
       },
       kNoLight},
  });
}

// A scene with a mesh "crate" of one grey part placed by shapes[2].
pb::Scene WithCrate() {
  pb::Scene s = Valid();
  pb::Mesh* mesh = s.add_meshes();
  mesh->set_name("crate");
  pb::MeshPart* part = mesh->add_parts();
  part->set_digest("sha256:" + std::string(64, '0'));
  part->set_material("grey");
  s.add_shapes()->mutable_instance()->set_mesh("crate");
  return s;
}

TEST(CheckScene, InstancesAndTheirMeshes) {
  ExpectRefusals({
      {"as built", [](pb::Scene&) {}, "accepted"},
      {"an instance with a material", [](pb::Scene& s) { s.mutable_shapes(2)->set_material("grey"); },
       "shapes[2].material: must be empty for an instance, whose mesh's parts name their materials; got \"grey\""},
      {"a shape without a material", [](pb::Scene& s) { s.mutable_shapes(1)->clear_material(); },
       "shapes[1].material: missing; a shape names one of the scene's materials"},
      {"an instance of no mesh", [](pb::Scene& s) { s.mutable_shapes(2)->mutable_instance()->set_mesh("barrel"); },
       "shapes[2].instance.mesh: no mesh named \"barrel\""},
      {"a part of no material", [](pb::Scene& s) { s.mutable_meshes(0)->mutable_parts(0)->set_material("chrome"); },
       "meshes[0].parts[0].material: no material named \"chrome\""},
      {"two meshes of one name", [](pb::Scene& s) { *s.add_meshes() = s.meshes(0); },
       "meshes[1].name: duplicate mesh name \"crate\" (also meshes[0])"},
      {"a duplicate material name comes before a glossy material's energy",
       [](pb::Scene& s) {
         pb::Material* shiny = s.add_materials();
         shiny->set_name("shiny");
         shiny->mutable_glossy()->mutable_diffuse()->set_r(1);
         shiny->mutable_glossy()->mutable_specular()->set_r(1);
         shiny->mutable_glossy()->set_exponent(10);
         s.add_materials()->CopyFrom(s.materials(0));
       },
       "materials[3].name: duplicate material name \"grey\" (also materials[0])"},
      {"an emissive part is the only light",
       [](pb::Scene& s) {
         s.clear_lights();
         s.mutable_meshes(0)->mutable_parts(0)->set_material("lamp");
       },
       "accepted"},
  }, WithCrate);
}

TEST(CheckScene, TexturesAndTheirReferences) {
  ExpectRefusals({
      {"two textures of one name",
       [](pb::Scene& s) {
         for (int i = 0; i < 2; ++i) {
           pb::Texture* t = s.add_textures();
           t->set_name("wood");
           t->set_digest("sha256:" + std::string(64, '0'));
         }
       },
       "textures[1].name: duplicate texture name \"wood\" (also textures[0])"},
      {"a normal map of no texture",
       [](pb::Scene& s) {
         pb::Material* m = s.add_materials();
         m->set_name("varnish");
         m->mutable_principled()->mutable_normal_texture()->set_texture("bumps");
       },
       "materials[2].principled.normal_texture.texture: no texture named \"bumps\""},
      {"an environment of no texture", [](pb::Scene& s) { s.mutable_environment()->mutable_map()->set_texture("sky"); },
       "environment.map.texture: no texture named \"sky\""},
  });
}

// Places the crate of WithCrate by the first `values` values of the identity matrix.
void SetMatrix(pb::Scene& s, int values) {
  constexpr double kIdentity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  pb::Transform* t = s.mutable_shapes(2)->mutable_instance()->mutable_transform();
  for (int i = 0; i < values; ++i) t->add_matrix(kIdentity[i]);
}

TEST(CheckScene, MatrixTransforms) {
  ExpectRefusals({
      {"the identity", [](pb::Scene& s) { SetMatrix(s, 12); }, "accepted"},
      {"11 values", [](pb::Scene& s) { SetMatrix(s, 11); },
       "shapes[2].instance.transform.matrix: must have 12 values (3 rows of 4: an affine matrix without its last row), "
       "got 11"},
      {"a matrix and a scale",
       [](pb::Scene& s) {
         SetMatrix(s, 12);
         s.mutable_shapes(2)->mutable_instance()->mutable_transform()->mutable_scale()->set_x(1);
       },
       "shapes[2].instance.transform.matrix: must be the only part of the transform set, but scale is set too"},
      {"a singular matrix",
       [](pb::Scene& s) {
         SetMatrix(s, 12);
         s.mutable_shapes(2)->mutable_instance()->mutable_transform()->set_matrix(5, 0);
       },
       "shapes[2].instance.transform.matrix: must be invertible, but the determinant of its 3x3 part is 0"},
      {"a mirror", [](pb::Scene& s) {
         SetMatrix(s, 12);
         s.mutable_shapes(2)->mutable_instance()->mutable_transform()->set_matrix(0, -1);
       },
       "accepted"},
  }, WithCrate);
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
