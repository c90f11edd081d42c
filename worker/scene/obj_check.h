#pragma once

// The rules every OBJ mesh file of the farm obeys, checked line by line before
// tinyobjloader reads the file: the same rules, in the same order, with the same line
// numbers as the coordinator's checker (contract/assets/obj.go, whose package comment
// states them), so that the worker refuses exactly what the client and the coordinator
// refuse (tests/vectors/meshes). tinyobjloader alone lets much through: it reads "v abc"
// and "v nan" as 0, a missing coordinate as 0, "f 1 2 3.5" as "f 1 2 3", drops faces of
// fewer than 3 vertices with a warning, and accepts indices before the first vertex or
// past the last.
//
// In short: lines end in "\n" (a "\r" before it is dropped), are at most
// SceneLimits().max_mesh_line_bytes long with the break, and are UTF-8 text without
// control characters but tab; "v" takes 3, 4 or 6 numbers, "vt" 1 to 3, "vn" 3, each
// decimal, finite and within max_magnitude; "f" takes 3 or more references v, v/vt, v//vn
// or v/vt/vn of whole numbers, positive ones at most the file's count of that kind,
// negative ones reaching no further back than those declared before the face, never 0;
// other statements are ignored; the file holds at most max_asset_bytes, max_mesh_vertices
// and max_mesh_triangles, and at least one triangle.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "contract/failure.h"

namespace farm {

// An OBJ file that breaks the rules above: bad input, at a line.
class ObjError : public BadInputError {
 public:
  // line 0: the file as a whole (its size).
  ObjError(std::size_t line, const std::string& reason);
  std::size_t line() const { return line_; }
  const std::string& reason() const { return reason_; }

 private:
  std::size_t line_;
  std::string reason_;
};

// What checking learnt of a file.
struct ObjCounts {
  std::uint64_t vertices = 0;
  std::uint64_t triangles = 0;
};

// Checks the file's text against the rules; throws ObjError naming the first line that
// breaks one.
ObjCounts CheckObj(std::string_view text);

}  // namespace farm
