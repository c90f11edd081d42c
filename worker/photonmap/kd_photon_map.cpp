#include "photonmap/kd_photon_map.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>

#include "photonmap/byte_io.h"
#include "photonmap/oct_direction.h"
#include "photonmap/rgb9e5.h"

namespace farm {
namespace {

// A neighbour as one integer, (bits of distance_squared) << 32 | index: squared distances
// here are finite and >= 0, and such floats order as their bits do, so comparing keys
// compares (distance_squared, index), the lower index winning a tie in distance.
using Key = std::uint64_t;
static_assert(sizeof(PhotonNeighbour) == sizeof(Key) && offsetof(PhotonNeighbour, index) == 0 &&
              offsetof(PhotonNeighbour, distance_squared) == 4);
Key KeyOf(PhotonNeighbour n) { return std::bit_cast<Key>(n); }  // little-endian: byte_io.h

// The one expression for photon distances and for the lower bounds that prune subtrees: the
// pruning is exact because both round the same way (see NearestSearch).
float SquaredLength(const float v[3]) { return v[0] * v[0] + v[1] * v[1] + v[2] * v[2]; }

// Moves v down from h[i] to its place in the max-heap h[0, n) of keys (h[i]'s children
// already heaps): one pass, where pop_heap + push_heap would take two.
inline void SiftDown(PhotonNeighbour* h, std::uint32_t n, std::uint32_t i, PhotonNeighbour v) {
  const Key key = KeyOf(v);
  for (std::uint32_t c = 2 * i + 1; c < n; i = c, c = 2 * i + 1) {
    if (c + 1 < n && KeyOf(h[c]) < KeyOf(h[c + 1])) ++c;
    if (!(key < KeyOf(h[c]))) break;
    h[i] = h[c];
  }
  h[i] = v;
}

// Subtrees at most this many levels high are scanned whole: a photon costs about what a
// pruning test costs, and the scan reads contiguous records without pushing or popping.
inline constexpr unsigned kScanHeight = 2;

// One k-nearest search over the implicit left-balanced tree (node i's children at 2i + 1
// and 2i + 2; the descendants of i at depth j are the 2^j records from (i + 1) 2^j - 1 on,
// contiguous, so a small subtree is a few runs of records).
//
// Arya and Mount's incremental distances: a pending subtree carries, per axis, the
// query's offset from the nearest face of its cell (the split planes of its ancestors),
// and is skipped when the squared length of that offset exceeds the k-th distance found.
// The bound is exact in float: rounding is monotonic, so a photon in the cell, at least as
// far as the planes on every axis, never rounds to a distance below the bound's.
class NearestSearch {
 public:
  NearestSearch(const unsigned char* records, std::uint32_t count, const Vec3& p,
                float radius_squared, PhotonNeighbour* heap, std::uint32_t k)
      : records_(records),
        count_(count),
        query_{p.x, p.y, p.z},
        heap_(heap),
        k_(k),
        // Below radius_squared, the largest such float: "d2 <= bound_" is "d2 < r2".
        bound_(std::nextafter(radius_squared, 0.0f)) {}

  // Returns how many neighbours heap_ holds (at most k).
  std::uint32_t Run() {
    // The farther child of each node on the current path, while its nearer one is searched.
    // A tree of fewer than 2^31 nodes is at most 31 levels deep; one spare slot is written
    // and not kept.
    struct Pending {
      std::uint32_t node;
      float bound;
      float offset[3];
    };
    Pending stack[33];
    int top = 0;
    std::uint32_t node = 0;
    float offset[3] = {0, 0, 0};
    for (;;) {
      // Descend, nearer child first; the scanned subtree ends the descent.
      while (((std::uint64_t(node) + 1) << (kScanHeight + 1)) - 1 < count_) {
        PrefetchDescendants(node, 2);
        PrefetchDescendants(node, 3);
        float diff[3];
        Visit(node, diff);
        // Both children exist, and a node with children has axis 0-2 (the snapshot's
        // reader checked every node's).
        const unsigned axis = split_axis(node);
        const float d = diff[axis];
        const std::uint32_t near = 2 * node + 1 + (d >= 0 ? 1 : 0);
        Pending& far = stack[top];
        far.node = 4 * node + 3 - near;
        std::memcpy(far.offset, offset, sizeof offset);
        far.offset[axis] = d;
        far.bound = SquaredLength(far.offset);
        top += far.bound <= bound_ ? 1 : 0;
        node = near;
      }
      VisitSubtree(node);
      do {
        if (top == 0) return found_;
        --top;
      } while (!(stack[top].bound <= bound_));
      node = stack[top].node;
      std::memcpy(offset, stack[top].offset, sizeof offset);
    }
  }

 private:
  unsigned split_axis(std::uint32_t i) const {
    return byte_io::Load<std::uint16_t>(records_ + kSnapshotRecordSize * i + 18) & 3u;
  }

  // Asks for the cache lines of node's descendants `depth` levels down, which the
  // descent reaches after `depth` more photons: the search waits on memory, not arithmetic.
  // The lines past the last record a prefetch may name are only a hint, never read.
  void PrefetchDescendants(std::uint32_t node, unsigned depth) const {
    const std::uint64_t first = ((std::uint64_t(node) + 1) << depth) - 1;
    if (first >= count_) return;
    const auto begin = reinterpret_cast<std::uintptr_t>(records_ + kSnapshotRecordSize * first);
    const std::uintptr_t end = begin + (kSnapshotRecordSize << depth);
    for (std::uintptr_t line = begin & ~std::uintptr_t{63}; line < end; line += 64)
      __builtin_prefetch(reinterpret_cast<const void*>(line));
  }

  // Every photon of node's subtree, level by level.
  void VisitSubtree(std::uint32_t node) {
    float diff[3];
    for (std::uint64_t first = node, width = 1; first < count_; first = 2 * first + 1, width *= 2) {
      const std::uint64_t end = std::min<std::uint64_t>(first + width, count_);
      for (std::uint64_t i = first; i < end; ++i) Visit(std::uint32_t(i), diff);
    }
  }

  // Offers photon i to the k best (diff: query minus its position, for the caller).
  void Visit(std::uint32_t i, float diff[3]) {
    float pos[3];
    std::memcpy(pos, records_ + kSnapshotRecordSize * i, sizeof pos);
    for (int c = 0; c < 3; ++c) diff[c] = query_[c] - pos[c];
    const float d2 = SquaredLength(diff);
    if (!(d2 <= bound_)) return;
    const PhotonNeighbour candidate{i, d2};
    if (found_ < k_) {
      // Until k are found the radius is the bound and the order does not matter: the heap
      // is made once, when full.
      heap_[found_++] = candidate;
      if (found_ < k_) return;
      for (std::uint32_t j = k_ / 2; j-- > 0;) SiftDown(heap_, k_, j, heap_[j]);
    } else {
      if (!(KeyOf(candidate) < KeyOf(heap_[0]))) return;  // the k-th wins a tie of lower index
      SiftDown(heap_, k_, 0, candidate);
    }
    bound_ = heap_[0].distance_squared;
  }

  const unsigned char* records_;
  std::uint32_t count_;
  float query_[3];
  PhotonNeighbour* heap_;  // a max-heap of keys once found_ == k_
  std::uint32_t k_;
  std::uint32_t found_ = 0;
  float bound_;  // a photon is offered when its d2 <= bound_
};

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

void KdPhotonMap::NearestK(const Vec3& p, int k, float max_radius,
                           std::vector<PhotonNeighbour>& out) const {
  out.clear();
  if (k <= 0 || count_ == 0 || !(max_radius > 0)) return;
  const float radius_squared = max_radius * max_radius;
  if (!(radius_squared > 0)) return;  // underflowed: no distance is below it
  out.resize(std::min<std::uint32_t>(static_cast<std::uint32_t>(k), count_));
  NearestSearch search(records_, count_, p, radius_squared, out.data(),
                       static_cast<std::uint32_t>(out.size()));
  out.resize(search.Run());
}

}  // namespace farm
