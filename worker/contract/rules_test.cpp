#include "contract/rules.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "contract/test_json.h"
#include "renderfarm/v1/worker.pb.h"

namespace farm::contract {
namespace {

// A scene that breaks no field rule.
pb::Scene Valid() {
  return testing::FromJson<pb::Scene>(R"({
    "camera": {"position": {"z": -5}, "lookAt": {}, "up": {"y": 1}, "verticalFovDegrees": 40},
    "film": {"width": 64, "height": 48},
    "materials": [{"name": "white", "lambert": {"reflectance": {"r": 0.8, "g": 0.8, "b": 0.8}}}],
    "shapes": [{"material": "white", "sphere": {"center": {}, "radius": 1}}],
    "lights": [{"point": {"position": {"y": 3}, "intensity": {"r": 1, "g": 1, "b": 1}}}]
  })");
}

std::string Refusal(const google::protobuf::Message& m) {
  const std::optional<FieldError> err = CheckRules(m);
  return err ? err->ToString() : "accepted";
}

TEST(CheckRules, AcceptsAValidSceneAndUnsetFieldsWithDefaults) {
  EXPECT_EQ(Refusal(Valid()), "accepted");
  EXPECT_EQ(Refusal(pb::Film()), "width: must be in [1, 16384], got 0");
}

TEST(CheckRules, NamesTheFirstFieldInDeclarationOrderDepthFirst) {
  struct Case {
    const char* name;
    void (*change)(pb::Scene&);
    const char* want;
  } cases[] = {
      {"missing required message", [](pb::Scene& s) { s.clear_camera(); }, "camera: missing"},
      {"camera before film", [](pb::Scene& s) { s.clear_camera(); s.clear_film(); }, "camera: missing"},
      {"number bounds", [](pb::Scene& s) { s.mutable_film()->set_width(20000); },
       "film.width: must be in [1, 16384], got 20000"},
      {"bounds with a default", [](pb::Scene& s) { s.mutable_film()->set_tile_size(4); },
       "film.tile_size: must be in [8, 256] (0 selects 32), got 4"},
      {"upper bound only", [](pb::Scene& s) { s.mutable_sampling()->set_light_samples(1025); },
       "sampling.light_samples: must be <= 1024 (0 selects 16), got 1025"},
      {"exclusive bounds", [](pb::Scene& s) { s.mutable_camera()->set_vertical_fov_degrees(180); },
       "camera.vertical_fov_degrees: must be in (0, 180), got 180"},
      {"not finite", [](pb::Scene& s) { s.mutable_camera()->mutable_position()->set_x(NAN); },
       "camera.position.x: must be a finite number, got NaN"},
      {"infinite", [](pb::Scene& s) { s.mutable_shapes(0)->mutable_sphere()->set_radius(-INFINITY); },
       "shapes[0].sphere.radius: must be a finite number, got -Inf"},
      {"magnitude", [](pb::Scene& s) { s.mutable_camera()->mutable_up()->set_z(2e12); },
       "camera.up.z: must be within ±1e+12, got 2e+12"},
      {"component bounds from the holding field",
       [](pb::Scene& s) { s.mutable_materials(0)->mutable_lambert()->mutable_reflectance()->set_g(1.5); },
       "materials[0].lambert.reflectance.g: must be in [0, 1], got 1.5"},
      {"required string", [](pb::Scene& s) { s.mutable_materials(0)->clear_name(); }, "materials[0].name: missing"},
      {"string length", [](pb::Scene& s) { s.set_name(std::string(257, 'x')); }, "name: must be at most 256 bytes, got 257"},
      {"oneof nothing set", [](pb::Scene& s) { s.mutable_lights(0)->clear_point(); },
       "lights[0]: exactly one of point, sun, spot must be set"},
      {"oneof fields before the oneof check",
       [](pb::Scene& s) {
         s.mutable_materials(0)->clear_lambert();
         s.mutable_materials(0)->set_name(std::string(300, 'm'));
       },
       "materials[0].name: must be at most 256 bytes, got 300"},
      {"unknown enum value", [](pb::Scene& s) { s.mutable_indirect()->set_mode(static_cast<pb::IndirectMode>(7)); },
       "indirect.mode: unknown IndirectMode value 7"},
      {"digest", [](pb::Scene& s) { s.mutable_shapes(0)->mutable_mesh()->set_digest("sha256:XYZ"); },
       R"(shapes[0].mesh.digest: must be "sha256:" followed by 64 lowercase hex digits, got "sha256:XYZ")"},
      {"required digest", [](pb::Scene& s) { s.mutable_shapes(0)->mutable_mesh()->set_path("a.obj"); },
       "shapes[0].mesh.digest: missing"},
      {"min items", [](pb::Scene& s) { s.mutable_shapes(0)->mutable_triangles()->add_positions(); },
       "shapes[0].triangles.positions: must have at least 3 entries, got 1"},
      {"conductor eta past 100 (the old Go drift)",
       [](pb::Scene& s) {
         pb::Conductor* c = s.mutable_materials(0)->mutable_conductor();
         c->mutable_eta()->set_r(200);
         c->mutable_k();
       },
       "materials[0].conductor.eta.r: must be in (0, 100], got 200"},
      {"conductor k past 100",
       [](pb::Scene& s) {
         pb::Conductor* c = s.mutable_materials(0)->mutable_conductor();
         c->mutable_eta()->set_r(1);
         c->mutable_eta()->set_g(1);
         c->mutable_eta()->set_b(1);
         c->mutable_k()->set_b(500);
       },
       "materials[0].conductor.k.b: must be in [0, 100], got 500"},
  };
  for (const Case& c : cases) {
    pb::Scene s = Valid();
    c.change(s);
    EXPECT_EQ(Refusal(s), c.want) << c.name;
  }
}

TEST(CheckRules, ListsCheckTheirLengthBeforeTheirElements) {
  pb::Scene s = Valid();
  s.mutable_lights(0)->clear_point();  // an element that would be refused
  while (s.lights_size() <= 4096) *s.add_lights() = s.lights(0);
  EXPECT_EQ(Refusal(s), "lights: must have at most 4096 entries, got 4097");
}

TEST(CheckRules, PathsStartWithTheGivenPrefix) {
  pb::Film film;
  film.set_width(8);
  film.set_height(0);
  const auto err = CheckRules(film, "film");
  ASSERT_TRUE(err);
  EXPECT_EQ(err->field, "film.height");
  EXPECT_EQ(err->message, "must be in [1, 16384], got 0");
}

TEST(CheckRules, MapValuesAreCheckedInKeyOrderUnderTheirKeys) {
  pb::RoundMetrics m;
  (*m.mutable_layer_reference_rmse())["indirect"] = INFINITY;
  (*m.mutable_layer_reference_rmse())["direct"] = NAN;
  EXPECT_EQ(Refusal(m), "layer_reference_rmse[direct]: must be a finite number, got NaN");
}

TEST(CheckRules, AMapTakesOnlyItsRulesKeysInKeyOrderAsGoChecksThem) {
  pb::RoundMetrics m;
  (*m.mutable_layer_reference_rmse())["volume"] = NAN;
  (*m.mutable_layer_reference_rmse())["caustic"] = INFINITY;
  (*m.mutable_layer_reference_rmse())["bias"] = 0.1;
  EXPECT_EQ(Refusal(m), "layer_reference_rmse[bias]: is not a key it may have (direct, indirect, caustic, volume)");
  m.mutable_layer_reference_rmse()->erase("bias");
  EXPECT_EQ(Refusal(m), "layer_reference_rmse[caustic]: must be a finite number, got +Inf");
  pb::RoundMetrics declared;
  for (const char* layer : {"direct", "indirect", "caustic", "volume"})
    (*declared.mutable_layer_reference_rmse())[layer] = 1;
  EXPECT_FALSE(CheckRules(declared));
}

TEST(Describe, SaysWhichNumbersARuleAllows) {
  pb::FieldRule r;
  r.set_gte(1);
  EXPECT_EQ(Describe(r), "must be >= 1");
  r.set_gt(0);  // an exclusive bound wins over an inclusive one
  EXPECT_EQ(Describe(r), "must be > 0");
  r.set_lt(1e6);
  EXPECT_EQ(Describe(r), "must be in (0, 1e+06)");
  r.set_default_value(1.1);
  EXPECT_EQ(Describe(r), "must be in (0, 1e+06) (0 selects 1.1)");
}

TEST(Accessors, ReadDefaultsAndBoundsFromTheOptions) {
  EXPECT_EQ(Default<pb::Sampling>("light_samples"), 16);
  EXPECT_EQ(Max<pb::Sampling>("light_samples"), 1024);
  EXPECT_EQ(Max<pb::Indirect>("gather_rays"), 4096);
  EXPECT_EQ(Default<pb::Film>("tile_size"), 32);
  EXPECT_EQ(OrDefault<pb::Film>(0u, "tile_size"), 32u);
  EXPECT_EQ(OrDefault<pb::Film>(64u, "tile_size"), 64u);
  EXPECT_EQ(OrDefault<pb::Antialiasing>(pb::ANTIALIASING_MODE_UNSPECIFIED, "mode"), pb::ANTIALIASING_MODE_EDGES);
  EXPECT_EQ(OrDefault<pb::Antialiasing>(0.0, "edge_threshold"), 0.1);
  EXPECT_THROW(Default<pb::Film>("width"), std::logic_error);   // no default_value
  EXPECT_THROW(Max<pb::Camera>("position"), std::logic_error);  // no lte
  EXPECT_THROW(Default<pb::Film>("widht"), std::logic_error);   // no such field
  EXPECT_EQ(Keys<pb::RoundMetrics>("layer_reference_rmse"),
            (std::vector<std::string>{"direct", "indirect", "caustic", "volume"}));
  EXPECT_THROW(Keys<pb::Film>("width"), std::logic_error);  // no keys
}

TEST(Accessors, ReadTheSceneAndRpcLimits) {
  EXPECT_EQ(SceneLimits().max_magnitude(), 1e12);
  EXPECT_EQ(SceneLimits().max_tiles_per_round(), 65536u);
  EXPECT_EQ(SceneLimits().max_shards_per_map(), 10000u);
  EXPECT_EQ(SceneLimits().max_mesh_vertices(), 10'000'000u);
  EXPECT_EQ(SceneLimits().max_film_pixels(), 8'388'608u);
  EXPECT_EQ(SceneLimits().max_snapshot_photons(), 105'000'000u);
  EXPECT_EQ(SceneLimits().max_shard_photons(), 32'000'000u);
  EXPECT_EQ(RpcLimits().max_message_bytes(), 64u << 20);
  EXPECT_EQ(RpcLimits().max_blob_bytes(), std::uint64_t{4} << 30);
  EXPECT_EQ(RpcLimits().max_upload_chunk_bytes(), 4u << 20);
  EXPECT_EQ(RpcLimits().max_error_bytes(), 4096u);
}

}  // namespace
}  // namespace farm::contract
