// Instancing against copies: a mesh placed N times by instances renders, lights, traces
// photons and aims caustics as N copied mesh files with the same transforms do, and its
// geometry is stored once.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string>

#include "photon/trace_photons.h"
#include "render/tile_renderer.h"
#include "scene/scene_data.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

// A smooth ball (latitude-longitude, with vertex normals and texture coordinates) of
// radius 0.5 about (0, 0.5, 0), as an OBJ file.
std::string BallObj(int around, int down) {
  std::string obj;
  char line[256];
  for (int j = 0; j <= down; ++j)
    for (int i = 0; i <= around; ++i) {
      const double t = M_PI * j / down, f = 2 * M_PI * i / around;
      const double x = std::sin(t) * std::cos(f), y = std::cos(t), z = std::sin(t) * std::sin(f);
      std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\nvn %.9g %.9g %.9g\nvt %.9g %.9g\n", 0.5 * x, 0.5 + 0.5 * y,
                    0.5 * z, x, y, z, double(i) / around, 1 - double(j) / down);
      obj += line;
    }
  const auto at = [&](int i, int j) { return j * (around + 1) + i + 1; };
  for (int j = 0; j < down; ++j)
    for (int i = 0; i < around; ++i) {
      const int a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      std::snprintf(line, sizeof line, "f %d/%d/%d %d/%d/%d %d/%d/%d\nf %d/%d/%d %d/%d/%d %d/%d/%d\n", a, a, a, c, c, c,
                    b, b, b, a, a, a, d, d, d, c, c, c);
      obj += line;
    }
  return obj;
}

// A small lamp floating above the ball, facing down, and a mirror plate beside it.
const std::string kLampObj = "v -0.1 1.2 -0.1\nv 0.1 1.2 -0.1\nv 0.1 1.2 0.1\nv -0.1 1.2 0.1\nf 1 2 3 4\n";
const std::string kPlateObj = "v 0.6 0 -0.2\nv 0.6 0 0.2\nv 0.6 0.4 0.2\nv 0.6 0.4 -0.2\nf 1 2 3 4\n";

// The placements: a grid of scaled, turned and sheared copies, one of them mirrored.
std::vector<std::array<double, 12>> Placements(int n) {
  std::vector<std::array<double, 12>> out;
  for (int k = 0; k < n; ++k) {
    const double a = 0.4 * k, s = 0.8 + 0.05 * k, x = (k % 4) * 1.5 - 2.25, z = (k / 4) * 1.5 - 1.5;
    const double mirror = k == 5 ? -1 : 1;
    out.push_back({mirror * s * std::cos(a), 0.1, s * std::sin(a), x, 0, s, 0, 0, -s * std::sin(a), 0, s * std::cos(a), z});
  }
  return out;
}

const std::string kBall = FakeDigest("ball"), kLamp = FakeDigest("lamp"), kPlate = FakeDigest("plate");

// The floor, the lights, and n balls with their lamps and plates: placed by instances of
// one mesh, or as copied mesh files with the same matrices.
pb::Scene Balls(int n, bool instanced) {
  pb::Scene s = MakeScene(48, 32, {0, 4, -7}, {0, 0.5, 0}, {0, 1, 0}, 45, 4, 3);
  s.mutable_sampling()->set_light_samples(8);
  AddLambert(s, "white", Rgb(0.8f));
  AddEmissive(s, "lamp", Rgb(20));
  pb::Material* mirror = s.add_materials();
  mirror->set_name("mirror");
  Set(mirror->mutable_mirror()->mutable_reflectance(), Rgb(0.9f));
  AddQuad(s, "white", {-5, 0, 5}, {10, 0, 0}, {0, 0, -10});
  AddPointLight(s, {0, 6, -2}, Rgb(30));
  const std::vector<std::pair<std::string, std::string>> parts{{kBall, "white"}, {kLamp, "lamp"}, {kPlate, "mirror"}};
  if (instanced) AddMesh(s, "ball", parts);
  for (const auto& m : Placements(n)) {
    double rows[12];
    std::copy(m.begin(), m.end(), rows);
    if (instanced) {
      AddInstance(s, "ball", rows);
      continue;
    }
    for (const auto& [digest, material] : parts) {
      pb::Shape* shape = AddMeshFile(s, material, digest);
      for (const double x : rows) shape->mutable_mesh()->mutable_transform()->add_matrix(x);
    }
  }
  return s;
}

Scene BuildBalls(int n, bool instanced) {
  return Scene::Build(Balls(n, instanced), MapLoader({{kBall, BallObj(96, 48)}, {kLamp, kLampObj}, {kPlate, kPlateObj}}));
}

constexpr int kCopies = 12;

TEST(Instancing, RendersAsCopiesOfTheMeshDo) {
  const Scene instanced = BuildBalls(kCopies, true), copied = BuildBalls(kCopies, false);
  const Image a = RenderTile(instanced, nullptr, {0, 0, 48, 32}), b = RenderTile(copied, nullptr, {0, 0, 48, 32});
  // Beauty channels R, G, B of every pixel: the instances' rays are transformed into the
  // mesh's space in float, so hits agree to float noise, not to the bit.
  double sum = 0, diff = 0, worst = 0;
  int differing = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 48; ++x)
      for (int c = 0; c < 3; ++c) {
        const double va = a.pixel(x, y)[c], vb = b.pixel(x, y)[c];
        sum += vb;
        diff += std::abs(va - vb);
        worst = std::max(worst, std::abs(va - vb) / std::max(1e-3, vb));
        differing += va != vb;
      }
  std::printf("instanced vs copied: mean |difference| %.3g of a mean %.3g, largest relative %.3g, %d of %d values differ\n",
              diff / (48 * 32 * 3), sum / (48 * 32 * 3), worst, differing, 48 * 32 * 3);
  EXPECT_GT(sum, 0);
  EXPECT_LT(diff / sum, 1e-5) << "the images differ by more than float noise";
  EXPECT_LT(worst, 1e-3);
}

TEST(Instancing, LightsPhotonsAndCausticTargetsAreThoseOfTheCopies) {
  const Scene instanced = BuildBalls(kCopies, true), copied = BuildBalls(kCopies, false);
  const SceneData &a = instanced.data(), &b = copied.data();
  ASSERT_EQ(a.lights.size(), kCopies + 1u);  // the lamps, then the point light
  ASSERT_EQ(b.lights.size(), kCopies + 1u);
  for (std::size_t i = 0; i < a.lights.size(); ++i)
    EXPECT_NEAR(Power(a.lights[i]).g, Power(b.lights[i]).g, 1e-5 * Power(b.lights[i]).g) << "light " << i;
  // A lamp's power is pi L times its placed area: 0.2 x 0.2 scaled by s^2 (the shear is
  // in the plane).
  EXPECT_NEAR(Power(a.lights[0]).g, M_PI * 20 * 0.04 * 0.8 * 0.8, 1e-4);
  ASSERT_EQ(a.specular_targets.size(), kCopies);
  ASSERT_EQ(b.specular_targets.size(), kCopies);
  for (std::size_t i = 0; i < kCopies; ++i) {
    // The copies' spheres bound their placed vertices, the instances' their placed boxes:
    // the same centre, a radius as large or larger.
    EXPECT_LT(Length(a.specular_targets[i].center - b.specular_targets[i].center), 1e-4f);
    EXPECT_GE(a.specular_targets[i].radius, b.specular_targets[i].radius * 0.9999f);
  }
  for (const PhotonMapKind kind : {PhotonMapKind::kGlobal, PhotonMapKind::kCaustic}) {
    const std::vector<ShardPhoton> pa = TracePhotons(instanced, {kind, 0, 20000, 20000});
    const std::vector<ShardPhoton> pb = TracePhotons(copied, {kind, 0, 20000, 20000});
    ASSERT_GT(pb.size(), 100u);
    // Paths agree but for the few that float noise sends another way.
    EXPECT_NEAR(double(pa.size()), double(pb.size()), 0.01 * pb.size()) << (kind == PhotonMapKind::kGlobal ? "global" : "caustic");
    double ea = 0, eb = 0;
    for (const ShardPhoton& p : pa) ea += p.power.g;
    for (const ShardPhoton& p : pb) eb += p.power.g;
    EXPECT_NEAR(ea, eb, 0.01 * eb);
  }
}

TEST(Instancing, StoresTheMeshOnce) {
  const Scene one = BuildBalls(1, false), instanced = BuildBalls(kCopies, true), copied = BuildBalls(kCopies, false);
  const std::size_t single = one.data().GeometryBytes(), inst = instanced.data().GeometryBytes(),
                    copies = copied.data().GeometryBytes();
  std::printf("geometry memory: one ball %zu bytes; %d instances %zu bytes; %d copies %zu bytes\n", single, kCopies, inst,
              kCopies, copies);
  EXPECT_LT(inst, single * 3 / 2);  // the mesh once, and a little per instance
  EXPECT_GT(copies, single * kCopies * 8 / 10);
}

// What a coverage probe reads of a hit (SceneData::IntersectFacing) is what Intersect
// finds, to the bit, on every kind of shape: instances (one of them mirrored), mesh files,
// a quad and a sphere, hit from rays in every direction.
TEST(Instancing, IntersectFacingFindsIntersectsDistanceAndNormal) {
  for (const bool instanced : {true, false}) {
    pb::Scene s = Balls(kCopies, instanced);
    AddSphere(s, "white", {0, 2, 1}, 0.4);
    const Scene scene = Scene::Build(s, MapLoader({{kBall, BallObj(96, 48)}, {kLamp, kLampObj}, {kPlate, kPlateObj}}));
    const SceneData& data = scene.data();
    std::map<std::size_t, int> hits_by_kind;  // ShapeGeometry's index
    for (int i = 0; i < 4000; ++i) {
      // Origins over a box about the balls, directions over the sphere (golden spiral).
      const float z = 1 - 2 * (i + 0.5f) / 4000, r = std::sqrt(1 - z * z), f = 2.39996323f * i;
      const Vec3 origin(-3 + 6 * ((i * 37) % 101) / 100.0f, 0.05f + 2.5f * ((i * 53) % 97) / 96.0f,
                        -3 + 6 * ((i * 71) % 89) / 88.0f);
      const Ray ray{origin, Vec3(r * std::cos(f), z, r * std::sin(f)), 100};
      const std::optional<SurfaceHit> full = data.Intersect(ray);
      const std::optional<SceneData::FacingHit> facing = data.IntersectFacing(ray);
      ASSERT_EQ(full.has_value(), facing.has_value()) << "ray " << i;
      if (!full) continue;
      EXPECT_EQ(full->t, facing->t) << "ray " << i;
      EXPECT_EQ(full->n.x, facing->n.x) << "ray " << i;
      EXPECT_EQ(full->n.y, facing->n.y) << "ray " << i;
      EXPECT_EQ(full->n.z, facing->n.z) << "ray " << i;
      ++hits_by_kind[data.shapes[std::size_t(full->shape)].geometry.index()];
    }
    // Spheres, quads and meshes, or instances, were each hit many times.
    EXPECT_GT(hits_by_kind[0], 10) << "sphere";
    EXPECT_GT(hits_by_kind[1], 100) << "quad";
    EXPECT_GT(hits_by_kind[instanced ? 3 : 2], 100) << (instanced ? "instances" : "mesh files");
  }
}

}  // namespace
}  // namespace farm
