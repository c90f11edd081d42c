#pragma once

// Wavefront OBJ meshes, parsed from bytes (the daemon hands us the blob's contents; no file
// system is shared with the client).
//
// The file is checked line by line first (obj_check.h: the farm's rules for OBJ files,
// the coordinator's too), then read by tinyobjloader. Normals (vn) and texture
// coordinates (vt) are kept when every face corner names one, each distinct (v, vt, vn) of
// the file then becoming a vertex; a vt's v is flipped (1 - v), since the farm's texture
// coordinates grow downwards in the image as glTF's do. Other statements (o, g, s, usemtl,
// ...) do not reach the mesh: the scene assigns the material.

#include <cstddef>
#include <string>
#include <string_view>

#include "scene/obj_check.h"
#include "scene/shapes.h"

namespace farm {

// Positions, triangles and the attributes above of every object and group in the file
// (polygons are triangulated). Throws ObjError.
TriangleMesh ParseObjMesh(std::string_view bytes);

}  // namespace farm
