#pragma once

// Spheres that photons are aimed at (the bounds of a scene's specular shapes), with what
// aiming needs in time that grows at most with the logarithm of their number:
//
// - from a point: a sphere picked by descending a balanced binary hierarchy of boxes, each
//   step choosing a child in proportion to an estimate of the solid angle its spheres
//   subtend (exact between two single spheres), with the probability of the pick;
// - along a direction (light from infinitely far away): a sphere picked in proportion to
//   its cross-section.
//
// Probabilities depend on the point alone, never on which photon asks. The photon tracer
// keeps a path only if the path's first hit is the shape of the sphere it was aimed at
// (photon_emission.h): each path then has exactly one strategy that owns it, so the weight
// is that strategy's density alone, with no sum over the other spheres' cones.

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

  // A sphere picked in proportion to its cross-section (radius squared), and its pmf.
  Pick PickByCrossSection(float u) const;

 private:
  // The tree is balanced (median splits), so its depth is at most 32 for any int count, and
  // a depth-first walk holds at most depth + 1 nodes.
  static constexpr int kMaxDepth = 64;
  struct Node {
    Bounds3 box;              // of every sphere below, widened a little (see Widened)
    float cross_section = 0;  // sum of radius squared below
    int left = -1, right = -1;
    int sphere = -1;  // a leaf's sphere, -1 for an inner node
  };
  int Build(std::vector<int>& order, int begin, int end);
  // Probability of descending to the left child of inner node n, seen from p.
  double LeftProbability(const Node& n, const Vec3& p) const;
  double Weight(const Node& n, const Vec3& p) const;

  std::vector<BoundingSphere> spheres_;
  std::vector<Node> nodes_;  // nodes_[0] is the root when there are spheres
  DiscreteDistribution by_cross_section_;
};

}  // namespace farm
