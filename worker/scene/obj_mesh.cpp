#include "scene/obj_mesh.h"

#include <tiny_obj_loader.h>

#include <sstream>
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

  TriangleMesh mesh;
  const std::size_t vertex_count = attrib.vertices.size() / 3;
  mesh.positions.reserve(vertex_count);
  for (std::size_t i = 0; i < vertex_count; ++i) {
    const Vec3 p(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
    // Finite as text, but past float's range.
    if (!IsFinite(p)) throw ObjError(0, "vertex " + std::to_string(i + 1) + " is out of float range");
    mesh.positions.push_back(p);
  }
  for (const tinyobj::shape_t& shape : shapes) {
    std::size_t offset = 0;
    for (const unsigned char n : shape.mesh.num_face_vertices) {
      if (n == 3) {  // after triangulation only degenerate leftovers differ; skip those
        for (std::size_t k = 0; k < 3; ++k)
          mesh.indices.push_back(static_cast<uint32_t>(shape.mesh.indices[offset + k].vertex_index));
      }
      offset += n;
    }
  }
  if (mesh.indices.empty())
    throw ObjError(0, "no triangle is left after triangulation" +
                          (warn.empty() ? std::string() : " (" + OneLine(warn) + ")"));
  return mesh;
}

}  // namespace farm
