#include "scene/scene.h"

#include <gtest/gtest.h>

#include "scene/scene_data.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

pb::Scene BaseScene() {
  pb::Scene s = MakeScene(8, 8, {0, 0, -10}, {0, 0, 0}, {0, 1, 0}, 30);
  AddLambert(s, "grey", Rgb(0.5f));
  AddEmissive(s, "lamp", Rgb(1));
  AddPointLight(s, {0, 50, -50}, Rgb(1));
  return s;
}

std::string BuildError(const pb::Scene& s, const BlobLoader& loader = NoBlobs()) {
  try {
    Scene::Build(s, loader);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

void ExpectNear(const Vec3& a, const Vec3& b, float tolerance) {
  EXPECT_LE(Length(a - b), tolerance) << ToString(a) << " vs " << ToString(b);
}

// A 2x2 square in the plane z = 0 centred on the origin, front +z, as two triangles.
constexpr char kSquareObj[] =
    "# square\n"
    "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
    "vn 0 0 1\n"
    "f 1//1 2//1 3//1\nf 1//1 3//1 4//1\n";

TEST(Scene, AppliesFilmAndSamplingDefaults) {
  pb::Scene s = BaseScene();
  s.mutable_sampling()->set_samples_per_pixel(0);
  const Scene scene = Scene::Build(s, NoBlobs());
  EXPECT_EQ(scene.width(), 8);
  EXPECT_EQ(scene.height(), 8);
  EXPECT_EQ(scene.tile_size(), 32);
  EXPECT_EQ(scene.data().samples_per_pixel, 1u);  // edge pixels get more: antialiasing
  EXPECT_EQ(scene.data().antialiasing.mode, AntialiasingMode::kEdges);
  EXPECT_EQ(scene.data().antialiasing.edge_samples, 32u);
}

TEST(Scene, RayHitsSphereAtTheAnalyticDistance) {
  pb::Scene s = BaseScene();
  AddSphere(s, "grey", {0, 0, 10}, 2);
  const Scene scene = Scene::Build(s, NoBlobs());
  const auto hit = scene.data().Intersect(Ray{{0, 0, 0}, {0, 0, 1}});
  ASSERT_TRUE(hit);
  SCOPED_TRACE(ToString(*hit));
  EXPECT_NEAR(hit->t, 8, 1e-4);
  ExpectNear(hit->p, {0, 0, 8}, 1e-5f);
  ExpectNear(hit->n, {0, 0, -1}, 1e-6f);  // outward
  // An off-centre ray: |o + t d - c| = r with d = normalize(1, 0, 10) gives t below.
  const Vec3 d = Normalize(Vec3(1, 0, 10));
  const double b = 10 * d.z, t = b - std::sqrt(b * b - (100 - 4));
  const auto off = scene.data().Intersect(Ray{{0, 0, 0}, d});
  ASSERT_TRUE(off);
  EXPECT_NEAR(off->t, t, 1e-4);
  EXPECT_NEAR(Distance(off->p, Vec3(0, 0, 10)), 2, 1e-5);
  // From inside, the ray leaves through the far side.
  const auto inside = scene.data().Intersect(Ray{{0, 0, 10}, {0, 1, 0}});
  ASSERT_TRUE(inside);
  EXPECT_NEAR(inside->t, 2, 1e-4);
}

TEST(Scene, RayHitsQuadAtTheAnalyticDistanceWithItsFrontNormal) {
  pb::Scene s = BaseScene();
  AddQuad(s, "grey", {-1, -1, 5}, {2, 0, 0}, {0, 2, 0});  // front = cross(u, v) = +z
  const Scene scene = Scene::Build(s, NoBlobs());
  const auto hit = scene.data().Intersect(Ray{{0.5f, 0.25f, 0}, {0, 0, 1}});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 5, 1e-5);
  ExpectNear(hit->n, {0, 0, 1}, 1e-6f);
  // Outside the parallelogram: a miss.
  EXPECT_FALSE(scene.data().Intersect(Ray{{1.5f, 0, 0}, {0, 0, 1}}));
}

TEST(Scene, RayHitsInlineTriangles) {
  pb::Scene s = BaseScene();
  pb::Shape* shape = s.add_shapes();
  shape->set_material("grey");
  for (const Vec3d& p : {Vec3d(0, 0, 3), Vec3d(4, 0, 3), Vec3d(0, 4, 3)})
    Set(shape->mutable_triangles()->add_positions(), p);
  for (uint32_t i : {0u, 1u, 2u}) shape->mutable_triangles()->add_indices(i);
  const Scene scene = Scene::Build(s, NoBlobs());
  const auto hit = scene.data().Intersect(Ray{{1, 1, -2}, {0, 0, 1}});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 5, 1e-5);
  ExpectNear(hit->n, {0, 0, 1}, 1e-6f);  // counter-clockwise seen from +z
  EXPECT_FALSE(scene.data().Intersect(Ray{{3, 3, -2}, {0, 0, 1}}));  // beyond the hypotenuse
}

TEST(Scene, ObjMeshIsLoadedByDigestAndTransformed) {
  pb::Scene s = BaseScene();
  pb::Shape* shape = AddMeshFile(s, "grey", FakeDigest("square"));
  pb::Transform* t = shape->mutable_mesh()->mutable_transform();
  // Scale 3, then rotate 90 degrees about +y (x -> -z, z -> x), then move to x = 5:
  // the square becomes the plane x = 5, |y| <= 3, |z| <= 3, facing +x.
  Set(t->mutable_scale(), {3, 3, 3});
  Set(t->mutable_rotation_axis(), {0, 1, 0});
  t->set_rotation_degrees(90);
  Set(t->mutable_translation(), {5, 0, 0});
  const Scene scene = Scene::Build(s, MapLoader({{FakeDigest("square"), kSquareObj}}));

  const auto hit = scene.data().Intersect(Ray{{0, 2.9f, -2.9f}, {1, 0, 0}});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 5, 1e-4);
  ExpectNear(hit->n, {1, 0, 0}, 1e-5f);
  EXPECT_FALSE(scene.data().Intersect(Ray{{0, 3.1f, 0}, {1, 0, 0}}));  // scaled to 3, not 1
  EXPECT_FALSE(scene.data().Intersect(Ray{{0, 0, 0}, {0, 0, 1}}));     // no longer at z = 0
}

TEST(Scene, MalformedObjIsASceneErrorNamingTheShapeTheFileAndTheLine) {
  pb::Scene s = BaseScene();
  AddSphere(s, "grey", {0, 0, 0}, 1);
  pb::Shape* teapot = AddMeshFile(s, "grey", FakeDigest("bad"));
  teapot->set_name("teapot");
  teapot->mutable_mesh()->set_path("meshes/teapot.obj");
  try {
    Scene::Build(s, MapLoader({{FakeDigest("bad"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf a b c\n"}}));
    FAIL() << "built";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()),
              "shapes[1].mesh: OBJ file \"meshes/teapot.obj\" line 4: \"a\" is not a vertex reference (v, "
              "v/vt, v//vn or v/vt/vn, whole numbers) (shape \"teapot\")");
    EXPECT_EQ(e.kind(), pb::FAILURE_KIND_BAD_INPUT);
  }
}

TEST(Scene, ObjFaceOutOfRangeAndEmptyObjAreSceneErrors) {
  pb::Scene s = BaseScene();
  AddMeshFile(s, "grey", FakeDigest("mesh"));
  const std::string file = "OBJ file \"" + FakeDigest("mesh") + "\"";  // no path: the digest
  EXPECT_EQ(BuildError(s, MapLoader({{FakeDigest("mesh"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"}})),
            "shapes[0].mesh: " + file + " line 4: face refers to vertex 9 but the file has 3 vertices");
  EXPECT_EQ(BuildError(s, MapLoader({{FakeDigest("mesh"), "v 0 0 0\n"}})),
            "shapes[0].mesh: " + file + " line 1: the mesh has no triangles (the file has no face)");
}

TEST(Scene, AMeshThatCannotBeLoadedFailsWithTheLoadersKind) {
  pb::Scene s = BaseScene();
  AddMeshFile(s, "grey", FakeDigest("mesh"))->mutable_mesh()->set_path("a.obj");
  try {
    Scene::Build(s, NoBlobs());
    FAIL() << "built";
  } catch (const TaskError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("shapes[0].mesh.digest: cannot load mesh \"a.obj\": no blob", 0), 0u)
        << e.what();
    EXPECT_EQ(e.kind(), pb::FAILURE_KIND_TRANSIENT);  // the blob store's fault, not the scene's
  }
}

TEST(Scene, BuildChecksTheContractFirst) {
  pb::Scene s = BaseScene();
  s.mutable_film()->set_width(0);
  EXPECT_EQ(BuildError(s), "film.width: must be in [1, 16384], got 0");
  s = BaseScene();
  AddSphere(s, "chrome", {0, 0, 0}, 1);
  EXPECT_EQ(BuildError(s), "shapes[0].material: no material named \"chrome\"");
}

TEST(Scene, EmissiveShapesBecomeLightsPickedByPower) {
  pb::Scene s = BaseScene();
  s.clear_lights();
  AddQuad(s, "lamp", {0, 0, 0}, {1, 0, 0}, {0, 1, 0});   // area 1
  AddSphere(s, "grey", {5, 0, 0}, 1);                   // not a light
  AddQuad(s, "lamp", {0, 0, 5}, {3, 0, 0}, {0, 1, 0});   // area 3
  const Scene scene = Scene::Build(s, NoBlobs());
  const SceneData& d = scene.data();
  SCOPED_TRACE(d.ToString());
  ASSERT_EQ(d.lights.size(), 2u);  // the two lamps, in shape order
  EXPECT_EQ(std::get<QuadLight>(d.lights[0]).quad.origin, Vec3(0, 0, 0));
  EXPECT_EQ(std::get<QuadLight>(d.lights[1]).quad.origin, Vec3(0, 0, 5));
  EXPECT_NEAR(d.light_power.Pmf(0), 0.25, 1e-6);
  EXPECT_NEAR(d.light_power.Pmf(1), 0.75, 1e-6);
  EXPECT_NEAR(Power(d.lights[1]).g, 3 * std::numbers::pi, 1e-5);
}

// A ray that meets an emitter finds the light that light sampling draws it from: emissive
// shapes and the emissive parts of instances (each part its own light), and nothing on a
// shape or part that does not emit.
TEST(Scene, AHitFindsTheAreaLightItLiesOn) {
  pb::Scene s = BaseScene();
  AddQuad(s, "lamp", {-1, -1, 0}, {2, 0, 0}, {0, 2, 0});  // light 0
  AddSphere(s, "grey", {0, 0, 5}, 1);                      // none
  AddSphere(s, "lamp", {0, 0, 10}, 1);                     // light 1
  // A grey square 1 above an emissive one (light 2), lifted to z = 20.
  const std::string raised = "v -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\nf 1 2 3\nf 1 3 4\n";
  AddMesh(s, "lantern", {{FakeDigest("raised"), "grey"}, {FakeDigest("square"), "lamp"}});
  const double lift[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 20};
  AddInstance(s, "lantern", lift);
  const Scene scene =
      Scene::Build(s, MapLoader({{FakeDigest("square"), std::string(kSquareObj)}, {FakeDigest("raised"), raised}}));
  const SceneData& d = scene.data();
  SCOPED_TRACE(d.ToString());
  ASSERT_EQ(d.lights.size(), 4u);  // three area lights, then the point light
  const auto light_from = [&](float z, float dz) {
    const std::optional<SurfaceHit> hit = d.Intersect(Ray{{0.2f, 0.1f, z}, {0, 0, dz}});
    return hit ? d.AreaLightOf(*hit) : -2;
  };
  EXPECT_EQ(light_from(-5, 1), 0);
  EXPECT_EQ(light_from(2, 1), -1);
  EXPECT_EQ(light_from(7, 1), 1);
  EXPECT_EQ(light_from(15, 1), 2);
  EXPECT_EQ(light_from(30, -1), -1) << "the instance's grey part";
}

TEST(Scene, IsMovable) {
  pb::Scene s = BaseScene();
  AddSphere(s, "grey", {0, 0, 10}, 2);
  Scene a = Scene::Build(s, NoBlobs());
  Scene b = std::move(a);
  Scene c = Scene::Build(BaseScene(), NoBlobs());
  c = std::move(b);
  EXPECT_TRUE(c.data().Intersect(Ray{{0, 0, 0}, {0, 0, 1}}));
}

}  // namespace
}  // namespace farm
