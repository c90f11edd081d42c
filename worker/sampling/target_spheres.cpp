#include "sampling/target_spheres.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "math/math.h"

namespace farm {
namespace {

constexpr double kFullSphere = 4 * kPi;

// Solid angle of a sphere seen from p: the whole sphere of directions from inside it;
// without cancellation for distant spheres.
double SolidAngle(const BoundingSphere& s, const Vec3& p) {
  const double d2 = LengthSquared(s.center - p), r2 = double(s.radius) * s.radius;
  if (d2 <= r2) return kFullSphere;
  const double sin2 = r2 / d2;
  return 2 * kPi * (sin2 < 1e-3 ? sin2 / 2 : 1 - std::sqrt(1 - sin2));
}

// A sphere's box, widened by a thousandth of its size and a few ulps of its position, so
// that rounding never leaves a point of the sphere outside.
Bounds3 Widened(const BoundingSphere& s) {
  const float margin = s.radius * 1.001f + 1e-6f * MaxComponent(Abs(s.center)) + 1e-30f;
  const Vec3 m(margin, margin, margin);
  return {s.center - m, s.center + m};
}

float SquaredDistanceToBox(const Bounds3& b, const Vec3& p) {
  const Vec3 out = Max(Max(b.min - p, p - b.max), Vec3(0, 0, 0));
  return LengthSquared(out);
}

}  // namespace

TargetSpheres::TargetSpheres(std::vector<BoundingSphere> spheres) : spheres_(std::move(spheres)) {
  if (spheres_.empty()) return;
  std::vector<float> cross_sections;
  cross_sections.reserve(spheres_.size());
  for (const BoundingSphere& s : spheres_) cross_sections.push_back(s.radius * s.radius);
  by_cross_section_ = DiscreteDistribution(cross_sections);
  std::vector<int> order(spheres_.size());
  std::iota(order.begin(), order.end(), 0);
  nodes_.reserve(2 * spheres_.size() - 1);
  Build(order, 0, static_cast<int>(order.size()));
}

// Splits at the median centre along the widest axis of the centres: balanced, so a
// descent is O(log n) steps; ties broken by index so the tree is the same on every host.
int TargetSpheres::Build(std::vector<int>& order, int begin, int end) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  if (end - begin == 1) {
    const BoundingSphere& s = spheres_[order[begin]];
    nodes_[index] = Node{Widened(s), s.radius * s.radius, -1, -1, order[begin]};
    return index;
  }
  Bounds3 centers;
  for (int i = begin; i < end; ++i) centers.Extend(spheres_[order[i]].center);
  const Vec3 extent = centers.max - centers.min;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  const int middle = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end, [&](int a, int b) {
    const float ca = spheres_[a].center[axis], cb = spheres_[b].center[axis];
    return ca < cb || (ca == cb && a < b);
  });
  const int left = Build(order, begin, middle);
  const int right = Build(order, middle, end);
  Bounds3 box = nodes_[left].box;
  box.Extend(nodes_[right].box);
  nodes_[index] = Node{box, nodes_[left].cross_section + nodes_[right].cross_section, left, right, -1};
  return index;
}

// A leaf's exact solid angle; for a cluster, its spheres' cross-section over the squared
// distance to the nearest point of its box (what they would subtend there, never much less
// than they do), at most the whole sphere of directions.
double TargetSpheres::Weight(const Node& n, const Vec3& p) const {
  if (n.sphere >= 0) return SolidAngle(spheres_[n.sphere], p);
  const float d2 = SquaredDistanceToBox(n.box, p);
  return d2 > 0 ? std::min(kFullSphere, kPi * n.cross_section / double(d2)) : kFullSphere;
}

double TargetSpheres::LeftProbability(const Node& n, const Vec3& p) const {
  const Node &a = nodes_[n.left], &b = nodes_[n.right];
  if (a.sphere < 0 && b.sphere < 0) {
    // Two clusters away from p, neither capped (the common case, all the way down but the
    // last step): the same ratio as Weight's, cross-multiplied, without a division each.
    const float da = SquaredDistanceToBox(a.box, p), db = SquaredDistanceToBox(b.box, p);
    if (a.cross_section < 4 * da && b.cross_section < 4 * db) {
      const float left = a.cross_section * db, sum = left + b.cross_section * da;
      return sum > 0 ? left / sum : -1;
    }
  }
  const double left = Weight(a, p), right = Weight(b, p);
  const double sum = left + right;
  return sum > 0 ? left / sum : -1;
}

bool TargetSpheres::AnyContains(const Vec3& p) const {
  if (empty()) return false;
  int stack[kMaxDepth];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (n.sphere >= 0) {
      const BoundingSphere& s = spheres_[n.sphere];
      if (LengthSquared(s.center - p) <= s.radius * s.radius) return true;
    } else if (SquaredDistanceToBox(n.box, p) == 0) {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
  return false;
}

std::optional<TargetSpheres::Pick> TargetSpheres::PickFrom(const Vec3& p, float u) const {
  if (empty()) return std::nullopt;
  double remaining = u, probability = 1;
  int node = 0;
  while (nodes_[node].sphere < 0) {
    const Node& n = nodes_[node];
    const double left = LeftProbability(n, p);
    if (left < 0) return std::nullopt;
    if (remaining < left) {
      remaining /= left;
      probability *= left;
      node = n.left;
    } else {
      remaining = (remaining - left) / (1 - left);
      probability *= 1 - left;
      node = n.right;
    }
    remaining = std::clamp(remaining, 0.0, std::nextafter(1.0, 0.0));
  }
  if (!(probability > 0)) return std::nullopt;
  return Pick{nodes_[node].sphere, probability};
}

TargetSpheres::Pick TargetSpheres::PickByCrossSection(float u) const {
  const DiscreteDistribution::Choice c = by_cross_section_.Sample(u);
  return {c.index, c.pmf};
}

}  // namespace farm
