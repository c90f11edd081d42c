#include "scene/mesh_file.h"

#include <utility>

#include "scene/farm_mesh.h"
#include "scene/obj_mesh.h"

namespace farm {

TriangleMesh ReadMeshFile(std::string_view bytes) {
  return IsFarmMesh(bytes) ? ReadFarmMesh(bytes) : ParseObjMesh(bytes);
}

std::optional<TriangleMesh> PlaceMesh(const TriangleMesh& mesh, const Placement& placement) {
  TriangleMesh placed = mesh;
  for (Vec3& p : placed.positions) {
    p = placement.Point(p);
    if (!IsFinite(p)) return std::nullopt;
  }
  // Normals and tangents are directions: a non-finite one (a huge scale) is dropped to
  // zero, which shading reads as "none here".
  const auto finite_or_zero = [](const Vec3& v) { return IsFinite(v) ? v : Vec3(); };
  for (Vec3& n : placed.normals) n = finite_or_zero(placement.Normal(n));
  for (Tangent& t : placed.tangents) {
    t.xyz = finite_or_zero(placement.Vector(t.xyz));
    if (placement.mirrors) t.w = -t.w;
  }
  if (placement.mirrors)
    for (std::size_t i = 0; i < placed.indices.size(); i += 3) std::swap(placed.indices[i + 1], placed.indices[i + 2]);
  return placed;
}

}  // namespace farm
