#pragma once

// Helpers for tests (not linked into the worker): build renderfarm.v1.Scene messages in a
// line or two, and a blob loader over an in-memory map.

#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "math/bounds.h"
#include "math/rgb.h"
#include "math/vec3.h"
#include "renderfarm/v1/scene.pb.h"
#include "scene/scene.h"
#include "scene/shapes.h"

namespace farm::testing {

namespace pb = renderfarm::v1;

inline void Set(pb::Vec3* out, const Vec3d& v) {
  out->set_x(v.x);
  out->set_y(v.y);
  out->set_z(v.z);
}

inline void Set(pb::Color* out, const Rgb& c) {
  out->set_r(c.r);
  out->set_g(c.g);
  out->set_b(c.b);
}

// A scene with film, camera and sampling set and no materials or shapes.
inline pb::Scene MakeScene(int width, int height, const Vec3d& position, const Vec3d& look_at,
                           const Vec3d& up, double fov_degrees, uint32_t spp = 4,
                           uint64_t seed = 1) {
  pb::Scene s;
  s.mutable_film()->set_width(width);
  s.mutable_film()->set_height(height);
  Set(s.mutable_camera()->mutable_position(), position);
  Set(s.mutable_camera()->mutable_look_at(), look_at);
  Set(s.mutable_camera()->mutable_up(), up);
  s.mutable_camera()->set_vertical_fov_degrees(fov_degrees);
  s.mutable_sampling()->set_samples_per_pixel(spp);
  s.mutable_sampling()->set_seed(seed);
  return s;
}

inline void AddLambert(pb::Scene& s, const std::string& name, const Rgb& reflectance) {
  pb::Material* m = s.add_materials();
  m->set_name(name);
  Set(m->mutable_lambert()->mutable_reflectance(), reflectance);
}

// An emissive material; a non-black reflectance makes it reflect as a Lambert of it too.
inline void AddEmissive(pb::Scene& s, const std::string& name, const Rgb& radiance,
                        const Rgb& reflectance = Rgb()) {
  pb::Material* m = s.add_materials();
  m->set_name(name);
  Set(m->mutable_emissive()->mutable_radiance(), radiance);
  if (!reflectance.IsBlack()) Set(m->mutable_emissive()->mutable_reflectance(), reflectance);
}

inline pb::Shape* AddSphere(pb::Scene& s, const std::string& material, const Vec3d& center,
                            double radius) {
  pb::Shape* shape = s.add_shapes();
  shape->set_material(material);
  Set(shape->mutable_sphere()->mutable_center(), center);
  shape->mutable_sphere()->set_radius(radius);
  return shape;
}

inline pb::Shape* AddQuad(pb::Scene& s, const std::string& material, const Vec3d& origin,
                          const Vec3d& edge_u, const Vec3d& edge_v) {
  pb::Shape* shape = s.add_shapes();
  shape->set_material(material);
  Set(shape->mutable_quad()->mutable_origin(), origin);
  Set(shape->mutable_quad()->mutable_edge_u(), edge_u);
  Set(shape->mutable_quad()->mutable_edge_v(), edge_v);
  return shape;
}

// The unit cube [0, 1]^3 as six quads facing inwards, all of `material`.
inline void AddInwardCube(pb::Scene& s, const std::string& material) {
  const Vec3d x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  AddQuad(s, material, {0, 0, 0}, z, x);  // y = 0, facing +y
  AddQuad(s, material, {0, 1, 0}, x, z);  // y = 1, facing -y
  AddQuad(s, material, {0, 0, 0}, y, z);  // x = 0, facing +x
  AddQuad(s, material, {1, 0, 0}, z, y);  // x = 1, facing -x
  AddQuad(s, material, {0, 0, 0}, x, y);  // z = 0, facing +z
  AddQuad(s, material, {0, 0, 1}, y, x);  // z = 1, facing -z
}

inline pb::Light* AddPointLight(pb::Scene& s, const Vec3d& position, const Rgb& intensity) {
  pb::Light* light = s.add_lights();
  Set(light->mutable_point()->mutable_position(), position);
  Set(light->mutable_point()->mutable_intensity(), intensity);
  return light;
}

// A digest of the contract's form ("sha256:" and 64 hex digits) naming a test blob; not
// the blob's hash (MapLoader does not check it).
inline std::string FakeDigest(std::string_view name) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string digest = "sha256:";
  for (std::size_t i = 0; i < 32; ++i) {
    const auto c = static_cast<unsigned char>(i < name.size() ? name[i] : 0);
    digest += kHex[c >> 4];
    digest += kHex[c & 15];
  }
  return digest;
}

inline pb::Shape* AddMeshFile(pb::Scene& s, const std::string& material,
                              const std::string& digest) {
  pb::Shape* shape = s.add_shapes();
  shape->set_material(material);
  shape->mutable_mesh()->set_digest(digest);
  return shape;
}

// The farm mesh file (docs/mesh-format.md) of a mesh, with the sections it has.
inline std::string FarmMeshBytes(const TriangleMesh& m) {
  std::string out = "FARMMESH";
  const auto put = [&out](const void* data, std::size_t bytes) { out.append(static_cast<const char*>(data), bytes); };
  const uint32_t version = 1;
  const uint32_t flags = (m.normals.empty() ? 0 : 1) | (m.texcoords.empty() ? 0 : 2) | (m.tangents.empty() ? 0 : 4);
  const uint64_t vertices = m.positions.size(), triangles = m.indices.size() / 3;
  put(&version, 4);
  put(&flags, 4);
  put(&vertices, 8);
  put(&triangles, 8);
  put(m.positions.data(), m.positions.size() * sizeof(Vec3));
  put(m.normals.data(), m.normals.size() * sizeof(Vec3));
  put(m.texcoords.data(), m.texcoords.size() * sizeof(Vec2));
  put(m.tangents.data(), m.tangents.size() * sizeof(Tangent));
  put(m.indices.data(), m.indices.size() * sizeof(uint32_t));
  return out;
}

// The farm grid file (docs/grid-format.md) of nx x ny x nz densities (x fastest) over box.
inline std::string FarmGridBytes(uint32_t nx, uint32_t ny, uint32_t nz, const Bounds3& box,
                                 const std::vector<float>& densities) {
  std::string out = "FARMGRID";
  const auto put = [&out](const void* data, std::size_t bytes) { out.append(static_cast<const char*>(data), bytes); };
  const uint32_t header[4] = {1, nx, ny, nz};
  put(header, sizeof header);
  put(&box.min, sizeof(Vec3));
  put(&box.max, sizeof(Vec3));
  put(densities.data(), densities.size() * sizeof(float));
  return out;
}

// Makes `medium` a grid medium of the blob `digest` with albedo and density scale.
inline pb::MediumGrid* SetGridMedium(pb::Medium* medium, const std::string& digest, const Rgb& albedo,
                                     float density_scale, float g) {
  pb::MediumGrid* grid = medium->mutable_grid();
  grid->set_digest(digest);
  Set(grid->mutable_albedo(), albedo);
  grid->set_density_scale(density_scale);
  medium->set_g(g);
  return grid;
}

// A shape placing mesh `mesh` of the scene (Scene.meshes) by a 12-value matrix (row-major).
inline pb::Shape* AddInstance(pb::Scene& s, const std::string& mesh, const double (&matrix)[12]) {
  pb::Shape* shape = s.add_shapes();
  shape->mutable_instance()->set_mesh(mesh);
  for (const double x : matrix) shape->mutable_instance()->mutable_transform()->add_matrix(x);
  return shape;
}

// A mesh of Scene.meshes with one part per (digest, material).
inline pb::Mesh* AddMesh(pb::Scene& s, const std::string& name,
                         const std::vector<std::pair<std::string, std::string>>& parts) {
  pb::Mesh* mesh = s.add_meshes();
  mesh->set_name(name);
  for (const auto& [digest, material] : parts) {
    pb::MeshPart* part = mesh->add_parts();
    part->set_digest(digest);
    part->set_material(material);
  }
  return mesh;
}

// Serves blobs from a map; throws for unknown digests, as the daemon's loader does.
inline BlobLoader MapLoader(std::map<std::string, std::string> blobs) {
  return [blobs = std::move(blobs)](const std::string& digest) {
    const auto it = blobs.find(digest);
    if (it == blobs.end()) throw std::runtime_error("no blob " + digest);
    return it->second;
  };
}

inline BlobLoader NoBlobs() { return MapLoader({}); }

}  // namespace farm::testing
