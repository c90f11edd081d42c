#pragma once

// Wavefront OBJ meshes, parsed from bytes (the daemon hands us the blob's contents; no file
// system is shared with the client).
//
// tinyobjloader parses the file; before it does, every line is checked for what it lets
// through silently (it reads "v abc 0 0" and "v nan 0 0" as 0, a missing coordinate as 0,
// "f 1 2 3.5" as "f 1 2 3", drops faces of fewer than 3 vertices with only a warning, and
// accepts relative indices before the first vertex and indices past the last one), so
// that a broken file is refused with the line that breaks it:
//
//   v   three or more numbers, every one finite
//   f   three or more vertex references v, v/vt, v//vn or v/vt/vn, each part an integer
//       that is not 0; a positive v at most the file's vertex count, a negative one
//       (relative) reaching no further back than the first vertex defined so far
//   the file at most SceneLimits().max_asset_bytes, at most max_mesh_vertices vertices and
//   max_mesh_triangles triangles (a face of n vertices makes n - 2), and at least one face
//
// Other lines (vn, vt, o, g, s, usemtl, comments, ...) are not checked: shading uses
// geometric normals and the shape's material.

#include <cstddef>
#include <string>
#include <string_view>

#include "contract/failure.h"
#include "scene/shapes.h"

namespace farm {

// An OBJ file that breaks the rules above: bad input.
class ObjError : public BadInputError {
 public:
  // line 0: the file as a whole (its size, no faces).
  ObjError(std::size_t line, const std::string& reason);
  std::size_t line() const { return line_; }
  const std::string& reason() const { return reason_; }

 private:
  std::size_t line_;
  std::string reason_;
};

// Positions and triangles of every object and group in the file (polygons are
// triangulated). Throws ObjError.
TriangleMesh ParseObjMesh(std::string_view bytes);

}  // namespace farm
