#include "photonmap/kd_photon_map.h"

#include <algorithm>
#include <cstring>

#include "photonmap/byte_io.h"
#include "photonmap/oct_direction.h"
#include "photonmap/rgb9e5.h"

namespace farm {
namespace {

bool Closer(const PhotonNeighbour& a, const PhotonNeighbour& b) {
  return a.distance_squared < b.distance_squared;
}

}  // namespace

unsigned KdPhotonMap::split_axis(std::size_t i) const {
  return byte_io::Load<std::uint16_t>(records_ + kSnapshotRecordSize * i + 18) & 3u;
}

std::uint32_t KdPhotonMap::packed_power(std::size_t i) const {
  return byte_io::Load<std::uint32_t>(records_ + kSnapshotRecordSize * i + 12);
}

std::uint16_t KdPhotonMap::wi_code(std::size_t i) const {
  return byte_io::Load<std::uint16_t>(records_ + kSnapshotRecordSize * i + 16);
}

std::uint16_t KdPhotonMap::normal_code(std::size_t i) const {
  return byte_io::Load<std::uint16_t>(records_ + kSnapshotRecordSize * i + 18) & ~3u;
}

Rgb KdPhotonMap::irradiance(std::size_t i) const {
  if (!irradiance_) return {};
  return DecodeRgb9e5(byte_io::Load<std::uint32_t>(irradiance_ + 4 * i)) * irradiance_scale_;
}

DecodedPhoton KdPhotonMap::photon(std::size_t i) const {
  const unsigned char* rec = records_ + kSnapshotRecordSize * i;
  DecodedPhoton p;
  p.position = {byte_io::Load<float>(rec), byte_io::Load<float>(rec + 4),
                byte_io::Load<float>(rec + 8)};
  p.power = DecodeRgb9e5(packed_power(i)) * power_scale_;
  p.wi = DecodeOct8(wi_code(i));
  p.normal = DecodeOct7Normal(normal_code(i));
  return p;
}

// Iterative descent with an explicit stack of far subtrees and a bounded max-heap of the
// best k so far (in out). Squared distances throughout; a far subtree is skipped when the
// split plane alone is at least as far as the current k-th neighbour. Pruning is exact in
// float: a photon beyond the plane is never nearer (after rounding) than the plane itself,
// so results equal a brute-force search with the same "d2 < r2" rule.
void KdPhotonMap::NearestK(const Vec3& p, int k, float max_radius,
                           std::vector<PhotonNeighbour>& out) const {
  out.clear();
  if (k <= 0 || count_ == 0 || !(max_radius > 0)) return;
  const std::size_t kk = static_cast<std::size_t>(k);
  float max_d2 = max_radius * max_radius;

  // The stack holds at most one far sibling per level of the current path, and a
  // left-balanced tree of < 2^31 nodes has at most 31 levels.
  struct Pending {
    std::uint32_t node;
    float plane_d2;
  };
  Pending stack[64];
  int top = 0;
  std::uint32_t node = 0;
  for (;;) {
    while (node < count_) {
      const unsigned char* rec = records_ + kSnapshotRecordSize * node;
      float pos[3];
      std::memcpy(pos, rec, sizeof pos);
      const unsigned axis = byte_io::Load<std::uint16_t>(rec + 18) & 3u;
      const float diff[3] = {p.x - pos[0], p.y - pos[1], p.z - pos[2]};
      const float d2 = diff[0] * diff[0] + diff[1] * diff[1] + diff[2] * diff[2];
      if (d2 < max_d2) {
        if (out.size() < kk) {
          out.push_back({node, d2});
          std::push_heap(out.begin(), out.end(), Closer);
          if (out.size() == kk) max_d2 = out.front().distance_squared;
        } else {
          std::pop_heap(out.begin(), out.end(), Closer);
          out.back() = {node, d2};
          std::push_heap(out.begin(), out.end(), Closer);
          max_d2 = out.front().distance_squared;
        }
      }
      if (axis == kLeafAxis) break;
      const float d = diff[axis];
      const std::uint32_t near = d < 0 ? 2 * node + 1 : 2 * node + 2;
      const std::uint32_t far = d < 0 ? 2 * node + 2 : 2 * node + 1;
      if (far < count_ && d * d < max_d2) stack[top++] = {far, d * d};
      node = near;
    }
    do {
      if (top == 0) return;
      --top;
    } while (!(stack[top].plane_d2 < max_d2));
    node = stack[top].node;
  }
}

}  // namespace farm
