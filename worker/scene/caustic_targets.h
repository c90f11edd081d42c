#pragma once

// The bounding spheres of the specular shapes as caustic emission reads them
// (photon/photon_emission.h): which sphere a photon is aimed at, and which spheres a ray
// may pass through, in time that grows with the logarithm of their number, not with it.
//
// Choosing. A photon of light i picks sphere k with a probability fixed per light
// (ForLight), not per emission point, so that the choice is one look-up in an alias
// table rather than a pass over every sphere. A light with an origin (area,
// point, spot) weighs each sphere by the solid angle it subtends from the nearest point of
// the light's bounding sphere (for a point or spot light, exactly the cone seen from the
// light; 2 pi where the spheres overlap); light from infinitely far away weighs each
// sphere by its cross-section r^2 (the area of its shadow on the light's disc). Any
// weights that are positive for every sphere keep the estimate unbiased; these put photons
// where the spheres look large. Past kMaxTableEntries entries (lights x spheres) every
// light shares the cross-section table, so memory stays linear in both.
//
// Densities. The mixture's density at a direction sums only the spheres its ray passes
// through. ForEachNearRay visits a superset of them through a bounding-sphere hierarchy
// whose tests are widened (by an angle and a relative margin) beyond the rounding of
// the exact per-sphere tests the caller applies, so the sum is that of a pass over every
// sphere. The order of visits is fixed by the scene, so photons are the same whatever the
// sharding.

#include <algorithm>
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
    Traverse([&](const Node& n) { return q.Near(n); }, [&](int k) {
      if (q.Near(spheres_[k])) visit(k);
    });
  }
  // The same for the whole line through o along w, with the slack of a distance on a
  // distant light's disc.
  template <typename Visit>
  void ForEachNearLine(const Vec3& o, const Vec3& w, Visit&& visit) const {
    const RayQuery q = Query(o, w, -std::numeric_limits<float>::infinity(), kLineSlack);
    Traverse([&](const Node& n) { return q.Near(n); }, [&](int k) {
      if (q.Near(spheres_[k])) visit(k);
    });
  }
  // Whether a point of light `light` may lie inside a sphere (its bounds meet one); if not,
  // AnyContains is false for every point of it.
  bool MayContainPointsOf(int light) const { return may_contain_[light]; }
  // Whether p is inside or on some sphere (the test SampleSphereFromPoint makes).
  bool AnyContains(const Vec3& p) const;

 private:
  struct Node {
    Bounds3 box;       // of the spheres below, grown by a margin against rounding
    float radius = 0;  // half the box's diagonal
    int first = 0;     // a leaf: its first sphere; an inner node: its second child
    int count = 0;     // spheres of a leaf; 0 for an inner node (first child: the next node)
  };

  // Slab tests against the nodes' boxes and distance tests against the spheres, both grown
  // by slack times the farthest any point of the root's box is from o (so by more than the
  // slack at the distance of any sphere), without square roots.
  struct RayQuery {
    Vec3 o, w;
    float inv[3];
    int near_is_max[3];  // per axis: whether the ray meets the box's max plane first
    float t_min = 0, grow = 0;

    bool Near(const Node& n) const {
      const float lo[3] = {n.box.min.x - grow, n.box.min.y - grow, n.box.min.z - grow};
      const float hi[3] = {n.box.max.x + grow, n.box.max.y + grow, n.box.max.z + grow};
      const float origin[3] = {o.x, o.y, o.z};
      float t0 = t_min, t1 = std::numeric_limits<float>::infinity();
      for (int a = 0; a < 3; ++a) {
        const float enter = ((near_is_max[a] ? hi[a] : lo[a]) - origin[a]) * inv[a];
        const float leave = ((near_is_max[a] ? lo[a] : hi[a]) - origin[a]) * inv[a];
        t0 = enter > t0 ? enter : t0;
        t1 = leave < t1 ? leave : t1;
      }
      return t0 <= t1;
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

  int Build(int begin, int end);

  template <typename Enter, typename Visit>
  void Traverse(Enter&& enter, Visit&& visit) const {
    if (nodes_.empty()) return;
    int stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const int index = stack[--top];
      const Node& n = nodes_[index];
      if (!enter(n)) continue;
      if (n.count > 0) {
        for (int k = n.first; k < n.first + n.count; ++k) visit(k);
      } else {
        stack[top++] = n.first;
        stack[top++] = index + 1;  // the first child, next
      }
    }
  }

  std::vector<BoundingSphere> spheres_;
  std::vector<Node> nodes_;
  std::vector<AliasTable> tables_;  // [0]: by cross-section
  std::vector<int> table_of_light_;
  std::vector<bool> may_contain_;  // by light
};

}  // namespace farm
