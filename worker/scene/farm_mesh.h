#pragma once

// The farm mesh file (docs/mesh-format.md): triangles in binary with optional normals,
// texture coordinates and tangents, read from bytes. The checks are contract/assets'
// (farmmesh.go) in the same order, refusing at the same byte offset with the same words,
// so that the worker refuses exactly what the client and the coordinator refuse
// (tests/vectors/meshes/*.farmmesh).

#include <cstdint>
#include <string>
#include <string_view>

#include "contract/failure.h"
#include "scene/shapes.h"

namespace farm {

// A farm mesh file that breaks the format's rules: bad input, at a byte offset.
class FarmMeshError : public BadInputError {
 public:
  FarmMeshError(std::uint64_t offset, const std::string& reason);  // what(): "byte N: reason"
  std::uint64_t offset() const { return offset_; }
  const std::string& reason() const { return reason_; }

 private:
  std::uint64_t offset_;
  std::string reason_;
};

// The limits a file is held to: Scene's max_asset_bytes, max_mesh_vertices and
// max_mesh_triangles unless a test says otherwise.
struct FarmMeshLimits {
  std::uint64_t max_bytes = 0, max_vertices = 0, max_triangles = 0;
  static FarmMeshLimits OfScene();
};

// Whether the bytes start with the farm mesh magic, "FARMMESH".
bool IsFarmMesh(std::string_view bytes);

// The mesh the file holds, its attributes as stored. Throws FarmMeshError.
TriangleMesh ReadFarmMesh(std::string_view bytes, const FarmMeshLimits& limits = FarmMeshLimits::OfScene());

}  // namespace farm
