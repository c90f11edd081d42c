#pragma once

// Wavefront OBJ meshes, parsed from bytes (the daemon hands us the blob's contents; no file
// system is shared with the client).
//
// The file is checked line by line first (obj_check.h: the farm's rules for OBJ files,
// the coordinator's too), then read by tinyobjloader. Other statements than v and f (vn,
// vt, o, g, s, usemtl, ...) do not reach the mesh: shading uses geometric normals and the
// shape's material.

#include <cstddef>
#include <string>
#include <string_view>

#include "scene/obj_check.h"
#include "scene/shapes.h"

namespace farm {

// Positions and triangles of every object and group in the file (polygons are
// triangulated). Throws ObjError.
TriangleMesh ParseObjMesh(std::string_view bytes);

}  // namespace farm
