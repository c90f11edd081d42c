#include "scene/obj_mesh.h"

#include <gtest/gtest.h>

#include <set>
#include <tuple>

namespace farm {
namespace {

// A unit square in z = 0 of two triangles whose corners name texture coordinates and
// normals: corner 1 twice with different texture coordinates (a seam).
constexpr const char* kSquare =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
    "vn 0 0 1\nvn 0 0.6 0.8\n"
    "f 1/1/1 2/2/1 3/3/2\n"
    "f 1/5/1 3/3/2 4/4/1\n";

TEST(ParseObjMesh, KeepsNormalsAndTextureCoordinatesWhenEveryCornerHasThem) {
  const TriangleMesh m = ParseObjMesh(kSquare);
  ASSERT_EQ(m.triangle_count(), 2);
  // Five distinct (v, vt, vn): corner 1 with vt 1 and with vt 5, corners 2, 3 and 4.
  EXPECT_EQ(m.positions.size(), 5u);
  ASSERT_EQ(m.normals.size(), 5u);
  ASSERT_EQ(m.texcoords.size(), 5u);
  for (std::size_t corner = 0; corner < 6; ++corner) {
    const uint32_t v = m.indices[corner];
    SCOPED_TRACE(corner);
    // The file's corners, in order: (position, texture coordinate, normal).
    const Vec3 positions[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const Vec2 uvs[] = {{0, 0}, {1, 0}, {1, 1}, {0.5f, 0.5f}, {1, 1}, {0, 1}};
    const Vec3 normals[] = {{0, 0, 1}, {0, 0, 1}, {0, 0.6f, 0.8f}, {0, 0, 1}, {0, 0.6f, 0.8f}, {0, 0, 1}};
    EXPECT_EQ(m.positions[v], positions[corner]);
    EXPECT_EQ(m.texcoords[v], (Vec2{uvs[corner].x, 1 - uvs[corner].y}));  // v flipped: downwards in the image
    EXPECT_EQ(m.normals[v], normals[corner]);
  }
}

TEST(ParseObjMesh, DropsAnAttributeSomeCornerLacks) {
  const TriangleMesh m = ParseObjMesh(
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
      "f 1/1/1 2/1/1 3/1/1\n"
      "f 1/1 3/1 4/1\n");  // no normals here
  EXPECT_TRUE(m.normals.empty());
  EXPECT_EQ(m.texcoords.size(), 4u);
  const TriangleMesh plain = ParseObjMesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1 2 3\n");
  EXPECT_TRUE(plain.normals.empty() && plain.texcoords.empty());
  EXPECT_EQ(plain.indices, (std::vector<uint32_t>{0, 1, 2}));
}

}  // namespace
}  // namespace farm
