#include "scene/farm_mesh.h"

#include <gtest/gtest.h>

#include "scene/mesh_file.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

// The quad of the farm mesh vectors: two triangles with every section.
TriangleMesh Quad() {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.normals = {{0, 0, 1}, {0, 0, 2}, {0, 0, 1}, {0, 0, 0}};
  m.texcoords = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  m.tangents = {{{1, 0, 0}, 1}, {{1, 0, 0}, -1}, {{1, 0, 0}, 1}, {{1, 0, 0}, 1}};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

void ExpectSameMesh(const TriangleMesh& a, const TriangleMesh& b) {
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.texcoords, b.texcoords);
  ASSERT_EQ(a.tangents.size(), b.tangents.size());
  for (std::size_t i = 0; i < a.tangents.size(); ++i) {
    EXPECT_EQ(a.tangents[i].xyz, b.tangents[i].xyz);
    EXPECT_EQ(a.tangents[i].w, b.tangents[i].w);
  }
  EXPECT_EQ(a.indices, b.indices);
}

TEST(ReadFarmMesh, ReadsEverySectionAsStored) {
  const TriangleMesh quad = Quad();
  ExpectSameMesh(ReadFarmMesh(testing::FarmMeshBytes(quad)), quad);
  TriangleMesh bare;
  bare.positions = quad.positions;
  bare.indices = quad.indices;
  const TriangleMesh read = ReadFarmMesh(testing::FarmMeshBytes(bare));
  ExpectSameMesh(read, bare);
  EXPECT_TRUE(read.normals.empty() && read.texcoords.empty() && read.tangents.empty());
}

TEST(ReadMeshFile, TellsFarmMeshFilesFromObjByTheirMagic) {
  EXPECT_EQ(ReadMeshFile(testing::FarmMeshBytes(Quad())).triangle_count(), 2);
  EXPECT_EQ(ReadMeshFile("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").triangle_count(), 1);
  EXPECT_THROW(ReadMeshFile("FARMMESH\n"), FarmMeshError);
}

// The same limits and files as contract/assets' TestFarmMeshLimits, refused alike.
TEST(ReadFarmMesh, RefusesFilesPastItsLimitsWhereGoDoes) {
  const std::string good = testing::FarmMeshBytes(Quad());  // 32 + 4 * 48 + 2 * 12 = 248 bytes
  ASSERT_EQ(good.size(), 248u);
  const struct {
    const char* name;
    std::string file;
    FarmMeshLimits limits;
    std::uint64_t offset;
    std::string reason;
  } cases[] = {
      {"a header past the byte limit", good, {247, 10, 10}, 16, "the header implies 248 bytes, more than the 247 of one asset"},
      {"a file exactly at the limit", good, {248, 10, 10}, 0, ""},
      {"a byte past the limit", good + "x", {248, 10, 10}, 248, "the file is larger than the limit of one asset"},
      {"a byte past the header", good, {20, 10, 10}, 20, "the file is larger than the limit of one asset"},
      {"a byte past the limit, below the header's size", good + "x", {250, 10, 10}, 248, "the file goes on past its last triangle"},
      {"too many vertices", good, {1000, 3, 10}, 16, "4 vertices, more than the 3 of one mesh"},
      {"too many triangles", good, {1000, 10, 1}, 24, "2 triangles, more than the 1 of one mesh"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    if (c.reason.empty()) {
      EXPECT_NO_THROW(ReadFarmMesh(c.file, c.limits));
      continue;
    }
    try {
      ReadFarmMesh(c.file, c.limits);
      ADD_FAILURE() << "accepted";
    } catch (const FarmMeshError& e) {
      EXPECT_EQ(e.offset(), c.offset) << e.what();
      EXPECT_EQ(e.reason(), c.reason);
      EXPECT_EQ(std::string(e.what()), "byte " + std::to_string(c.offset) + ": " + c.reason);
    }
  }
}

}  // namespace
}  // namespace farm
