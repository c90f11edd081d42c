#include "scene/obj_mesh.h"

#include <tiny_obj_loader.h>

#include <array>
#include <sstream>
#include <unordered_map>
#include <vector>

namespace farm {
namespace {

// tinyobj's messages end in newlines and name lines; keep them on one line of ours.
std::string OneLine(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

// The corners of the triangles tinyobj made, in order (faces of other sizes are degenerate
// leftovers of triangulation, skipped).
std::vector<tinyobj::index_t> TriangleCorners(const std::vector<tinyobj::shape_t>& shapes) {
  std::vector<tinyobj::index_t> corners;
  for (const tinyobj::shape_t& shape : shapes) {
    std::size_t offset = 0;
    for (const unsigned char n : shape.mesh.num_face_vertices) {
      if (n == 3) corners.insert(corners.end(), shape.mesh.indices.begin() + offset, shape.mesh.indices.begin() + offset + 3);
      offset += n;
    }
  }
  return corners;
}

struct CornerHash {
  std::size_t operator()(const std::array<int, 3>& k) const {
    std::uint64_t h = 0;
    for (const int x : k) h = (h ^ static_cast<std::uint32_t>(x)) * 0x9E3779B97F4A7C15ull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

}  // namespace

TriangleMesh ParseObjMesh(std::string_view bytes) {
  CheckObj(bytes);

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  std::istringstream in{std::string(bytes)};
  // No material reader: `mtllib` lines are ignored (the scene assigns the material).
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &in,
                                   /*readMatFn=*/nullptr, /*triangulate=*/true);
  if (!ok) throw ObjError(0, "tinyobjloader: " + OneLine(err));

  const std::size_t vertex_count = attrib.vertices.size() / 3;
  std::vector<Vec3> positions(vertex_count);
  for (std::size_t i = 0; i < vertex_count; ++i) {
    positions[i] = Vec3(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
    // Finite as text, but past float's range.
    if (!IsFinite(positions[i])) throw ObjError(0, "vertex " + std::to_string(i + 1) + " is out of float range");
  }
  const std::vector<tinyobj::index_t> corners = TriangleCorners(shapes);
  if (corners.empty())
    throw ObjError(0, "no triangle is left after triangulation" +
                          (warn.empty() ? std::string() : " (" + OneLine(warn) + ")"));

  // Normals and texture coordinates are kept only if every corner names one: a mesh is
  // smooth and textured all over or not at all.
  bool normals = !attrib.normals.empty(), texcoords = !attrib.texcoords.empty();
  for (const tinyobj::index_t& c : corners) {
    normals = normals && c.normal_index >= 0;
    texcoords = texcoords && c.texcoord_index >= 0;
  }
  TriangleMesh mesh;
  mesh.indices.reserve(corners.size());
  if (!normals && !texcoords) {
    mesh.positions = std::move(positions);
    for (const tinyobj::index_t& c : corners) mesh.indices.push_back(static_cast<uint32_t>(c.vertex_index));
    return mesh;
  }
  // OBJ indexes each attribute apart; the mesh has one index per vertex, so each distinct
  // (position, texture coordinate, normal) becomes a vertex.
  std::unordered_map<std::array<int, 3>, uint32_t, CornerHash> vertex_of;
  for (const tinyobj::index_t& c : corners) {
    const std::array<int, 3> key{c.vertex_index, texcoords ? c.texcoord_index : -1, normals ? c.normal_index : -1};
    const auto [it, fresh] = vertex_of.emplace(key, static_cast<uint32_t>(mesh.positions.size()));
    if (fresh) {
      mesh.positions.push_back(positions[c.vertex_index]);
      if (normals) {
        const float* n = &attrib.normals[3 * std::size_t(c.normal_index)];
        mesh.normals.push_back({n[0], n[1], n[2]});
      }
      if (texcoords) {
        // OBJ's v grows upwards in the image, the farm's (glTF's) downwards.
        const float* t = &attrib.texcoords[2 * std::size_t(c.texcoord_index)];
        mesh.texcoords.push_back({t[0], 1 - t[1]});
      }
    }
    mesh.indices.push_back(it->second);
  }
  return mesh;
}

}  // namespace farm
