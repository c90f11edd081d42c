#pragma once

// Spheres that photons are aimed at (the bounds of a scene's specular shapes), with what
// aiming needs in time that grows at most with the logarithm of their number:
//
// - from a point: a sphere picked by descending a balanced hierarchy of boxes, each step
//   choosing one of up to eight children in proportion to an estimate of the solid angle
//   its spheres subtend (exact for single spheres), with the probability of the pick;
// - along a direction (light from infinitely far away): a sphere picked in proportion to
//   its cross-section.
//
// Probabilities depend on the point alone, never on which photon asks. The photon tracer
// keeps a path only if the path's first hit is the shape of the sphere it was aimed at
// (photon_emission.h): each path then has exactly one strategy that owns it, so the weight
// is that strategy's density alone, with no sum over the other spheres' cones.

#include <optional>
#include <utility>
#include <vector>

#include "math/bounds.h"
#include "math/vec3.h"
#include "sampling/alias_table.h"

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

  // The spheres by the solid angle each subtends seen from p, for a light whose every
  // photon starts near p (a point or spot light, a small lamp): a pick from it is one table
  // read, not a descent. None if every sphere has radius 0.
  std::optional<AliasTable> TableFrom(const Vec3& p) const;

  // A sphere picked in proportion to its cross-section (radius squared), and its pmf: in
  // constant time; probability 0 when every sphere has radius 0.
  Pick PickByCrossSection(float u) const;

 private:
  // Up to eight children a node; the tree is balanced (median splits), so a depth-first walk
  // holds at most 7 entries a level, and there are at most 11 levels for any int count.
  static constexpr int kWidth = 8;
  static constexpr int kMaxStack = 7 * 11 + 1;
  // An inner node holds its children's boxes (widened a little, see Widened) and
  // cross-sections (sum of radius squared), so that a step of the descent reads one node.
  // A child is an inner node's index, or a leaf: -1 - its sphere's index.
  struct Node {
    Bounds3 box[kWidth];
    float cross_section[kWidth] = {};
    int child[kWidth] = {};
    int count = 0;
  };
  static bool IsLeaf(int ref) { return ref < 0; }
  static int LeafRef(int sphere) { return -1 - sphere; }
  static int SphereOf(int ref) { return -1 - ref; }
  void Split(std::vector<int>& order, int begin, int end, int levels, std::vector<std::pair<int, int>>& ranges) const;
  int Build(std::vector<int>& order, int begin, int end, Bounds3& box, float& cross_section);
  // Weight of child c of n seen from p: what picks it, in proportion.
  double Weight(const Node& n, int c, const Vec3& p) const;

  std::vector<BoundingSphere> spheres_;
  std::vector<Node> nodes_;  // the inner nodes
  int root_ = 0;             // a child reference: a leaf when there is one sphere
  Bounds3 root_box_;
  AliasTable by_cross_section_;
};

}  // namespace farm
