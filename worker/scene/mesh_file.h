#pragma once

// The mesh files a scene names (MeshFile, MeshPart): an OBJ file or a farm mesh file,
// told apart by the farm mesh file's magic as contract/assets.CheckMesh does, and placed
// in the world.

#include <optional>
#include <string_view>

#include "math/transform.h"
#include "scene/shapes.h"

namespace farm {

// The mesh a file holds. Throws ObjError or FarmMeshError.
TriangleMesh ReadMeshFile(std::string_view bytes);

// `mesh` moved into the world: positions by the placement, normals by its inverse
// transpose, tangents by its linear part, with a mirror's triangles turned back to
// counter-clockwise and its tangents' bitangent signs flipped (math/transform.h).
// Nothing if a moved vertex leaves float's range.
std::optional<TriangleMesh> PlaceMesh(const TriangleMesh& mesh, const Placement& placement);

}  // namespace farm
