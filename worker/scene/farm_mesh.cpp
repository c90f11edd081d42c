#include "scene/farm_mesh.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "contract/go_text.h"
#include "contract/rules.h"

namespace farm {
namespace {

constexpr std::string_view kMagic = "FARMMESH";
constexpr std::uint32_t kVersion = 1;
constexpr std::uint64_t kHeader = 32;
constexpr std::uint32_t kNormals = 1, kTexCoords = 2, kTangents = 4;
constexpr std::uint32_t kKnownFlags = kNormals | kTexCoords | kTangents;

static_assert(std::endian::native == std::endian::little, "the farm mesh file is little-endian, as this machine");

// Reads the file front to back, as Go's streaming checker does: a read past the end is
// refused at the file's end with the reason of the section being read.
class Reader {
 public:
  explicit Reader(std::string_view bytes) : bytes_(bytes) {}
  std::uint64_t offset() const { return at_; }

  void Skip(std::uint64_t n) { at_ += n; }

  template <typename T>
  T Next(const std::string& ends_inside) {
    if (bytes_.size() - at_ < sizeof(T)) throw FarmMeshError(bytes_.size(), ends_inside);
    T value;
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }

 private:
  std::string_view bytes_;
  std::uint64_t at_ = 0;
};

template <typename T>
T Load(std::string_view bytes, std::size_t at) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof(T));
  return value;
}

// Reads the section called `name` of `count` records of N floats into out, refusing a
// float that is not finite or that check refuses (check(i, x) returns a reason, or "" to
// accept float i of the section).
template <std::size_t N, typename Record, typename Check>
void ReadFloats(Reader& r, std::uint64_t count, const std::string& name, std::vector<Record>& out, Check check) {
  static_assert(sizeof(Record) == N * sizeof(float), "a record is N packed floats");
  out.resize(count);
  const std::string ends = "the file ends inside its " + name + "s";
  for (std::uint64_t i = 0; i < N * count; ++i) {
    const std::uint64_t at = r.offset();
    const float x = r.Next<float>(ends);
    if (!std::isfinite(x)) throw FarmMeshError(at, name + " " + std::to_string(i) + " is not finite");
    if (std::string reason = check(i, x); !reason.empty()) throw FarmMeshError(at, reason);
    std::memcpy(reinterpret_cast<char*>(out.data()) + i * sizeof(float), &x, sizeof x);
  }
}

std::string AnyValue(std::uint64_t, float) { return ""; }

}  // namespace

FarmMeshError::FarmMeshError(std::uint64_t offset, const std::string& reason)
    : BadInputError("byte " + std::to_string(offset) + ": " + reason), offset_(offset), reason_(reason) {}

FarmMeshLimits FarmMeshLimits::OfScene() {
  const auto& l = contract::SceneLimits();
  return {l.max_asset_bytes(), l.max_mesh_vertices(), l.max_mesh_triangles()};
}

bool IsFarmMesh(std::string_view bytes) { return bytes.starts_with(kMagic); }

TriangleMesh ReadFarmMesh(std::string_view bytes, const FarmMeshLimits& limits) {
  using contract::GoNumber;
  // Go reads through a reader that fails past max_bytes; a file that large is refused where
  // that reader would notice (below), the header's own claims first.
  const std::uint64_t readable = std::min<std::uint64_t>(bytes.size(), limits.max_bytes);
  if (readable < kHeader) {
    if (bytes.size() > limits.max_bytes) throw FarmMeshError(readable, "the file is larger than the limit of one asset");
    throw FarmMeshError(bytes.size(), "the file ends inside its 32-byte header");
  }
  if (!IsFarmMesh(bytes)) throw FarmMeshError(0, "not a farm mesh file (no \"FARMMESH\" magic)");
  if (const auto v = Load<std::uint32_t>(bytes, 8); v != kVersion)
    throw FarmMeshError(8, "version " + std::to_string(v) + ", but this farm reads version " + std::to_string(kVersion));
  const auto flags = Load<std::uint32_t>(bytes, 12);
  if (flags & ~kKnownFlags) {
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%x", flags & ~kKnownFlags);
    throw FarmMeshError(12, std::string("unknown flags ") + hex);
  }
  const auto nv = Load<std::uint64_t>(bytes, 16), nt = Load<std::uint64_t>(bytes, 24);
  if (nv == 0) throw FarmMeshError(16, "the mesh has no vertices");
  if (nv > limits.max_vertices)
    throw FarmMeshError(16, std::to_string(nv) + " vertices, more than the " + std::to_string(limits.max_vertices) + " of one mesh");
  if (nt == 0) throw FarmMeshError(24, "the mesh has no triangles");
  if (nt > limits.max_triangles)
    throw FarmMeshError(24, std::to_string(nt) + " triangles, more than the " + std::to_string(limits.max_triangles) + " of one mesh");
  const std::uint64_t per_vertex =
      12 + (flags & kNormals ? 12 : 0) + (flags & kTexCoords ? 8 : 0) + (flags & kTangents ? 16 : 0);
  const std::uint64_t size = kHeader + nv * per_vertex + 12 * nt;  // the limits keep this in range
  if (size > limits.max_bytes)
    throw FarmMeshError(16, "the header implies " + std::to_string(size) + " bytes, more than the " +
                                std::to_string(limits.max_bytes) + " of one asset");

  // Past the header the file holds what it says: read it through a view that ends where
  // Go's reader stops.
  Reader r(bytes.substr(0, readable));
  r.Skip(kHeader);
  TriangleMesh mesh;
  const double magnitude = contract::SceneLimits().max_magnitude();
  ReadFloats<3>(r, nv, "position", mesh.positions, [&](std::uint64_t i, float x) -> std::string {
    if (std::abs(double(x)) <= magnitude) return "";
    return "position " + std::to_string(i / 3) + "'s coordinate " + GoNumber(x) + " is out of range: numbers are at most ±" +
           GoNumber(magnitude);
  });
  if (flags & kNormals) ReadFloats<3>(r, nv, "normal", mesh.normals, AnyValue);
  if (flags & kTexCoords) ReadFloats<2>(r, nv, "texture coordinate", mesh.texcoords, AnyValue);
  if (flags & kTangents) {
    ReadFloats<4>(r, nv, "tangent", mesh.tangents, [](std::uint64_t i, float x) -> std::string {
      if (i % 4 != 3 || x == 1 || x == -1) return "";
      return "tangent " + std::to_string(i / 4) + "'s w is " + contract::GoNumber(x) + ", not 1 or -1";
    });
  }
  mesh.indices.resize(3 * nt);
  for (std::uint64_t i = 0; i < 3 * nt; ++i) {
    const std::uint64_t at = r.offset();
    const auto index = r.Next<std::uint32_t>("the file ends before its last triangle");
    if (index >= nv)
      throw FarmMeshError(at, "triangle " + std::to_string(i / 3) + " refers to vertex " + std::to_string(index) +
                                  " but the mesh has " + std::to_string(nv) + " vertices");
    mesh.indices[i] = index;
  }
  if (bytes.size() > size) {
    if (size == limits.max_bytes) throw FarmMeshError(size, "the file is larger than the limit of one asset");
    throw FarmMeshError(size, "the file goes on past its last triangle");
  }
  return mesh;
}

}  // namespace farm
