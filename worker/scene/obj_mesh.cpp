#include "scene/obj_mesh.h"

#include <tiny_obj_loader.h>

#include <cmath>
#include <sstream>

#include "scene/scene.h"

namespace farm {
namespace {

// tinyobj's messages end in newlines and name lines; keep them on one line of ours.
std::string OneLine(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

}  // namespace

TriangleMesh ParseObjMesh(std::string_view bytes, const std::string& field) {
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  std::istringstream in{std::string(bytes)};
  // No material reader: `mtllib` lines are ignored (the scene assigns the material).
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &in,
                                   /*readMatFn=*/nullptr, /*triangulate=*/true);
  if (!ok) throw SceneError(field + ": OBJ parse error: " + OneLine(err));

  TriangleMesh mesh;
  const std::size_t vertex_count = attrib.vertices.size() / 3;
  mesh.positions.reserve(vertex_count);
  for (std::size_t i = 0; i < vertex_count; ++i) {
    const Vec3 p(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
    if (!IsFinite(p))
      throw SceneError(field + ": OBJ parse error: vertex " + std::to_string(i + 1) +
                       " is not finite");
    mesh.positions.push_back(p);
  }
  for (const tinyobj::shape_t& shape : shapes) {
    std::size_t offset = 0;
    for (std::size_t face = 0; face < shape.mesh.num_face_vertices.size(); ++face) {
      const int n = shape.mesh.num_face_vertices[face];
      if (n == 3) {  // after triangulation only degenerate leftovers differ; skip those
        for (int k = 0; k < 3; ++k) {
          const int v = shape.mesh.indices[offset + k].vertex_index;
          if (v < 0 || static_cast<std::size_t>(v) >= vertex_count)
            throw SceneError(field + ": OBJ parse error: face " + std::to_string(face + 1) +
                             " of object \"" + shape.name + "\" refers to vertex " +
                             std::to_string(v + 1) + " but the file has " +
                             std::to_string(vertex_count) + " vertices");
          mesh.indices.push_back(static_cast<uint32_t>(v));
        }
      }
      offset += n;
    }
  }
  if (mesh.indices.empty())
    throw SceneError(field + ": OBJ mesh has no triangles" +
                     (warn.empty() ? std::string() : " (" + OneLine(warn) + ")"));
  return mesh;
}

}  // namespace farm
