#pragma once

// The bounding spheres of the specular shapes as caustic emission reads them
// (photon/photon_emission.h): which sphere a photon is aimed at, and which spheres a ray
// may pass through, in time that grows with the logarithm of their number, not with it.
//
// Choosing. A photon of light i picks sphere k with a probability fixed per light
// (ForLight), not per emission point, so that the choice is one look-up in an alias table
// rather than a pass over every sphere. A light with an origin (area, point, spot) weighs
// each sphere by the solid angle it subtends from the nearest point of the light's
// bounding sphere (for a point or spot light, exactly the cone seen from the light; 2 pi
// where the spheres overlap); light from infinitely far away weighs each sphere by its
// cross-section r^2 (the area of its shadow on the light's disc). Any weights that are
// positive for every sphere keep the estimate unbiased; these put photons where the
// spheres look large. Past kMaxTableEntries entries (lights x spheres) every light shares
// the cross-section table, so memory stays linear in both.
//
// Densities. The mixture's density at a direction sums only the spheres its ray passes
// through. ForEachNearRay (ForEachNearLine for a distant light's line) visits a superset
// of them: a median-split hierarchy collapsed into nodes of four boxes, whose slab tests
// run four at once, and then a distance test per sphere, both widened (by an angle times
// the distance and a relative margin) beyond the rounding of the exact per-sphere tests
// the caller applies, so the sum is that of a pass over every sphere. The order of visits
// is fixed by the scene, so photons are the same whatever the sharding.

#include <algorithm>
#include <cstring>
#include <limits>
#include <span>
#include <vector>

#include "math/bounds.h"
#include "math/math.h"
#include "math/vec3.h"
#include "sampling/alias_table.h"
#include "scene/lights.h"

namespace farm {

class CausticTargets {
 public:
  // Above this many entries over all lights' tables, lights share the cross-section table.
  static constexpr std::size_t kMaxTableEntries = std::size_t{1} << 20;

  // The angular slack of the hierarchy's ray tests. Along a ray from a light the caller's
  // test is SphereFromPointPdf's float cone test, which may accept a direction up to
  // sqrt(2 eps) d ~ 8e-4 d beyond a sphere at distance d (eps ~ 3e-7, the rounding of two
  // cosines near 1); 1.5e-3 covers it. Along a distant light's line the test is a float
  // distance on the disc, whose rounding is relative to the distances involved: 1e-5.
  static constexpr float kConeSlack = 1.5e-3f;
  static constexpr float kLineSlack = 1e-5f;
  static constexpr float kRelativeMargin = 1e-4f;  // of boxes and radii

  CausticTargets() = default;
  // The spheres of specular_targets, and the scene's lights in their order.
  CausticTargets(std::span<const BoundingSphere> spheres, std::span<const Light> lights);

  bool empty() const { return spheres_.empty(); }
  int size() const { return static_cast<int>(spheres_.size()); }
  // Sphere k in the hierarchy's order (not the order of SceneData::specular_targets).
  const BoundingSphere& sphere(int k) const { return spheres_[k]; }
  // The probabilities of aiming light `light`'s photons at each sphere (its total is 0
  // only if every sphere has radius 0).
  const AliasTable& ForLight(int light) const { return tables_[table_of_light_[light]]; }

  // Calls visit(k) for every sphere the ray o + t w, t >= 0 (unit w), might pass through,
  // and for some that it does not, in a fixed order.
  template <typename Visit>
  void ForEachNearRay(const Vec3& o, const Vec3& w, Visit&& visit) const {
    const RayQuery q = Query(o, w, 0, kConeSlack);
    Traverse([&](const WideNode& n) { return q.Near(n); }, [&](int k) {
      if (q.Near(spheres_[k])) visit(k);
    });
  }
  // The same for the whole line through o along w, with the slack of a distance on a
  // distant light's disc.
  template <typename Visit>
  void ForEachNearLine(const Vec3& o, const Vec3& w, Visit&& visit) const {
    const RayQuery q = Query(o, w, -std::numeric_limits<float>::infinity(), kLineSlack);
    Traverse([&](const WideNode& n) { return q.Near(n); }, [&](int k) {
      if (q.Near(spheres_[k])) visit(k);
    });
  }
  // Whether a point of light `light` may lie inside a sphere (its bounds meet one); if not,
  // AnyContains is false for every point of it.
  bool MayContainPointsOf(int light) const { return may_contain_[light]; }
  // Whether p is inside or on some sphere (the test SampleSphereFromPoint makes).
  bool AnyContains(const Vec3& p) const;

 private:
  // Four children side by side, their boxes by axis then child, so that one load brings
  // four boxes and their slab tests run together. A box is grown by a margin against
  // rounding; an empty slot has count -1 and an empty box (lo > hi).
  struct alignas(64) WideNode {  // two cache lines
    float lo[3][4], hi[3][4];
    int first[4];  // a leaf child: its first sphere; an inner child: its wide node
    int count[4];  // a leaf child's spheres; 0 for an inner child; -1 for an empty slot
  };
  struct BinaryNode;  // the median-split tree the wide nodes are collapsed from

  // Slab tests against the nodes' boxes and distance tests against the spheres, both grown
  // by slack times the farthest any point of the root's box is from o (so by more than the
  // slack at the distance of any sphere), without square roots per node.
  struct RayQuery {
    float origin[3], inv[3];
    Vec3 o, w;
    bool near_is_max[3];  // per axis: whether the ray meets a box's max plane first
    float t_min = 0, grow = 0;

    // Bit c: whether the ray meets child c's box. Four lanes at once (GCC's and Clang's
    // vector extensions: SSE on x86-64, NEON on ARM), the children side by side.
    int Near(const WideNode& n) const {
      using Lanes = float __attribute__((vector_size(16)));
      Lanes t0 = {t_min, t_min, t_min, t_min};
      constexpr float inf = std::numeric_limits<float>::infinity();
      Lanes t1 = {inf, inf, inf, inf};
      for (int a = 0; a < 3; ++a) {
        Lanes enter_plane, leave_plane;
        std::memcpy(&enter_plane, near_is_max[a] ? n.hi[a] : n.lo[a], sizeof enter_plane);
        std::memcpy(&leave_plane, near_is_max[a] ? n.lo[a] : n.hi[a], sizeof leave_plane);
        const float out = near_is_max[a] ? grow : -grow;  // the growth of the entry plane
        const Lanes enter = (enter_plane + (out - origin[a])) * inv[a];
        const Lanes leave = (leave_plane - (out + origin[a])) * inv[a];
        t0 = enter > t0 ? enter : t0;
        t1 = leave < t1 ? leave : t1;
      }
      const auto hit = t0 <= t1;
      return (hit[0] & 1) | (hit[1] & 2) | (hit[2] & 4) | (hit[3] & 8);
    }
    // The ray's distance from the centre, from the vector to its nearest point (no
    // cancellation of two squares).
    bool Near(const BoundingSphere& s) const {
      const Vec3 c = s.center - o;
      const float along = std::max(Dot(c, w), t_min);
      return LengthSquared(c - w * along) <= Sqr(s.radius * (1 + kRelativeMargin) + grow);
    }
  };
  RayQuery Query(const Vec3& o, const Vec3& w, float t_min, float slack) const;

  static int BuildBinary(std::vector<BoundingSphere>& spheres, int begin, int end, std::vector<BinaryNode>& tree);
  int Collapse(const std::vector<BinaryNode>& tree, int index);

  // enter(node) gives the mask of the children to enter; visit(k) is called for the
  // spheres of every leaf entered, in a fixed order.
  template <typename Enter, typename Visit>
  void Traverse(Enter&& enter, Visit&& visit) const {
    if (nodes_.empty()) return;
    // At most 3 a level: a median split of 2^31 spheres collapses to 16 levels of wide nodes.
    int stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const WideNode& n = nodes_[stack[--top]];
      const int mask = enter(n);
      for (int c = 0; c < 4; ++c) {
        if (!(mask & (1 << c)) || n.count[c] < 0) continue;
        if (n.count[c] == 0) {
          const char* next = reinterpret_cast<const char*>(&nodes_[n.first[c]]);
          __builtin_prefetch(next);
          __builtin_prefetch(next + 64);
          stack[top++] = n.first[c];
        } else {
          for (int k = n.first[c]; k < n.first[c] + n.count[c]; ++k) visit(k);
        }
      }
    }
  }

  std::vector<BoundingSphere> spheres_;
  std::vector<WideNode> nodes_;
  Bounds3 root_box_;
  std::vector<AliasTable> tables_;  // [0]: by cross-section
  std::vector<int> table_of_light_;
  std::vector<bool> may_contain_;  // by light
};

}  // namespace farm
