#pragma once

// Spheres that photons are aimed at (the bounds of a scene's specular shapes), with what
// aiming needs in time that does not grow with their number:
//
// - from a point: a sphere picked by descending a binary hierarchy of boxes, each step
//   choosing a child in proportion to an estimate of the solid angle its spheres subtend
//   (exact for a single sphere), then a direction uniform in that sphere's cone;
//   DirectionPdf is the density of the whole mixture, summed only over the spheres whose
//   cone holds the direction, found by walking the boxes the ray passes through;
// - along a direction (light from infinitely far away): a sphere picked in proportion to
//   its cross-section, and the spheres a line passes within found the same way.
//
// Every choice depends on the point alone, never on which photon asks, so the mixture's
// density is the same function whether a direction was sampled by it or not: the estimate
// stays unbiased for every path that starts towards any sphere.

#include <algorithm>
#include <limits>
#include <optional>
#include <vector>

#include "math/bounds.h"
#include "math/vec3.h"
#include "sampling/distribution.h"

namespace farm {

class TargetSpheres {
 public:
  TargetSpheres() = default;
  explicit TargetSpheres(std::vector<BoundingSphere> spheres);

  int size() const { return static_cast<int>(spheres_.size()); }
  bool empty() const { return spheres_.empty(); }
  const BoundingSphere& operator[](int i) const { return spheres_[i]; }

  // Whether p lies in (or on) any sphere.
  bool AnyContains(const Vec3& p) const;

  struct Pick {
    int index = 0;
    double probability = 0;
  };
  // A sphere seen from p, which lies outside every sphere; none if every weight is zero.
  std::optional<Pick> PickFrom(const Vec3& p, float u) const;
  // Density of direction w (unit) from p under PickFrom followed by SampleSphereFromPoint:
  // the sum over the spheres whose cone holds w of their probability times their cone's
  // density. `picked`, the pick w was sampled from, saves finding its probability again.
  float DirectionPdf(const Vec3& p, const Vec3& w, const std::optional<Pick>& picked = std::nullopt) const;
  // The probability that PickFrom(p, .) picks sphere i.
  double Probability(int i, const Vec3& p) const;

  // A sphere picked in proportion to its cross-section (radius squared), and its pmf.
  Pick PickByCrossSection(float u) const;
  float CrossSectionPmf(int index) const { return by_cross_section_.Pmf(index); }
  // Calls visit(i) for every sphere i that the line through p along w (unit) may pass
  // within (a superset: the caller tests each sphere exactly), nearest the root first.
  template <class Visit>
  void ForEachNearLine(const Vec3& p, const Vec3& w, Visit&& visit) const {
    Walk(Slab(p, w), false, visit);
  }

 private:
  // The tree is balanced (median splits), so its depth is at most 32 for any int count, and
  // a depth-first walk holds at most depth + 1 nodes.
  static constexpr int kMaxDepth = 64;
  struct Node {
    Bounds3 box;              // of every sphere below, widened a little (see Widened)
    float cross_section = 0;  // sum of radius squared below
    int left = -1, right = -1, parent = -1;
    int sphere = -1;  // a leaf's sphere, -1 for an inner node
  };
  // A ray or line from p along w against boxes, in double: a node must never be culled when
  // a sphere below it holds the direction (the leaves then test exactly).
  struct Slab {
    Slab(const Vec3& p, const Vec3& w) {
      for (int a = 0; a < 3; ++a) {
        origin[a] = p[a];
        zero[a] = w[a] == 0;
        inverse[a] = zero[a] ? 0 : 1 / double(w[a]);
      }
    }
    bool Meets(const Bounds3& box, bool ray_only) const {
      double near = ray_only ? 0 : -std::numeric_limits<double>::infinity();
      double far = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a) {
        if (zero[a]) {
          if (origin[a] < box.min[a] || origin[a] > box.max[a]) return false;
          continue;
        }
        const double t0 = (box.min[a] - origin[a]) * inverse[a], t1 = (box.max[a] - origin[a]) * inverse[a];
        near = std::max(near, std::min(t0, t1));
        far = std::min(far, std::max(t0, t1));
        if (near > far) return false;
      }
      return true;
    }
    double origin[3], inverse[3];
    bool zero[3];
  };
  // Calls visit(i) for the sphere of every leaf under a box the ray (or line) meets.
  template <class Visit>
  void Walk(const Slab& slab, bool ray_only, Visit& visit) const {
    if (empty()) return;
    int stack[kMaxDepth];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      if (!slab.Meets(n.box, ray_only)) continue;
      if (n.sphere >= 0) {
        visit(n.sphere);
      } else {
        stack[top++] = n.right;
        stack[top++] = n.left;
      }
    }
  }
  int Build(std::vector<int>& order, int begin, int end, int parent);
  // Probability of descending to the left child of inner node n, seen from p.
  double LeftProbability(const Node& n, const Vec3& p) const;
  double Weight(const Node& n, const Vec3& p) const;

  std::vector<BoundingSphere> spheres_;
  std::vector<Node> nodes_;  // nodes_[0] is the root when there are spheres
  std::vector<int> leaf_;    // the leaf node of each sphere
  DiscreteDistribution by_cross_section_;
};

}  // namespace farm
