#pragma once

// Wavefront OBJ meshes, parsed from bytes (the daemon hands us the blob's contents; no file
// system is shared with the client).

#include <string>
#include <string_view>

#include "scene/shapes.h"

namespace farm {

// Positions and triangles of every object and group in the file (polygons are
// triangulated; normals, texture coordinates and materials are ignored: shading uses
// geometric normals and the shape's material). Throws SceneError naming `field` if the text
// does not parse, a face refers to a vertex that does not exist, a coordinate is not
// finite, or there are no triangles.
TriangleMesh ParseObjMesh(std::string_view bytes, const std::string& field);

}  // namespace farm
