#include "sampling/target_spheres.h"

#include <algorithm>
#include <cmath>
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
  float d2 = 0;
  for (int a = 0; a < 3; ++a) {
    const float below = b.min[a] - p[a], above = p[a] - b.max[a];
    const float out = below > 0 ? below : above > 0 ? above : 0;
    d2 += out * out;
  }
  return d2;
}

}  // namespace

TargetSpheres::TargetSpheres(std::vector<BoundingSphere> spheres) : spheres_(std::move(spheres)) {
  if (spheres_.empty()) return;
  std::vector<float> cross_sections;
  cross_sections.reserve(spheres_.size());
  for (const BoundingSphere& s : spheres_) cross_sections.push_back(s.radius * s.radius);
  if (std::any_of(cross_sections.begin(), cross_sections.end(), [](float c) { return c > 0; }))
    by_cross_section_ = AliasTable(cross_sections);
  std::vector<int> order(spheres_.size());
  std::iota(order.begin(), order.end(), 0);
  float cross_section = 0;
  root_ = Build(order, 0, static_cast<int>(order.size()), root_box_, cross_section);
}

// Splits [begin, end) of order at the median centre along the widest axis of the centres,
// `levels` times over, into at most 2^levels ranges appended to `ranges`; ties broken by
// index so the tree is the same on every host.
void TargetSpheres::Split(std::vector<int>& order, int begin, int end, int levels,
                          std::vector<std::pair<int, int>>& ranges) const {
  if (levels == 0 || end - begin == 1) {
    ranges.emplace_back(begin, end);
    return;
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
  Split(order, begin, middle, levels - 1, ranges);
  Split(order, middle, end, levels - 1, ranges);
}

// Three median splits make up to eight children a node: balanced, so a descent is
// O(log n) steps, few enough that the nodes it reads (the tree's memory, not its
// arithmetic, is what a descent waits for) stay a handful. Returns the subtree as a child
// reference, with its box and cross-section.
int TargetSpheres::Build(std::vector<int>& order, int begin, int end, Bounds3& box, float& cross_section) {
  if (end - begin == 1) {
    const BoundingSphere& s = spheres_[order[begin]];
    box = Widened(s);
    cross_section = s.radius * s.radius;
    return LeafRef(order[begin]);
  }
  std::vector<std::pair<int, int>> ranges;
  Split(order, begin, end, 3, ranges);
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Node n;
  n.count = static_cast<int>(ranges.size());
  box = Bounds3();
  cross_section = 0;
  for (int c = 0; c < n.count; ++c) {
    n.child[c] = Build(order, ranges[c].first, ranges[c].second, n.box[c], n.cross_section[c]);
    box.Extend(n.box[c]);
    cross_section += n.cross_section[c];
  }
  nodes_[index] = n;
  return index;
}

// A leaf's exact solid angle; for a cluster, its spheres' cross-section over the squared
// distance to the nearest point of its box (what they would subtend there, never much less
// than they do), at most the whole sphere of directions.
double TargetSpheres::Weight(const Node& n, int c, const Vec3& p) const {
  if (IsLeaf(n.child[c])) return SolidAngle(spheres_[SphereOf(n.child[c])], p);
  const float d2 = SquaredDistanceToBox(n.box[c], p);
  return d2 > 0 ? std::min(kFullSphere, kPi * n.cross_section[c] / double(d2)) : kFullSphere;
}

bool TargetSpheres::AnyContains(const Vec3& p) const {
  if (empty() || SquaredDistanceToBox(root_box_, p) > 0) return false;
  int stack[kMaxStack];
  int top = 0;
  stack[top++] = root_;
  while (top > 0) {
    const int ref = stack[--top];
    if (IsLeaf(ref)) {
      const BoundingSphere& s = spheres_[SphereOf(ref)];
      if (LengthSquared(s.center - p) <= s.radius * s.radius) return true;
      continue;
    }
    const Node& n = nodes_[ref];
    for (int c = 0; c < n.count; ++c)
      if (SquaredDistanceToBox(n.box[c], p) == 0) stack[top++] = n.child[c];
  }
  return false;
}

std::optional<TargetSpheres::Pick> TargetSpheres::PickFrom(const Vec3& p, float u) const {
  if (empty()) return std::nullopt;
  double remaining = u, probability = 1;
  int ref = root_;
  while (!IsLeaf(ref)) {
    const Node& n = nodes_[ref];
    double weight[kWidth], sum = 0;
    for (int c = 0; c < n.count; ++c) sum += weight[c] = Weight(n, c, p);
    if (!(sum > 0)) return std::nullopt;
    // The child whose share of [0, 1) holds u, and u rescaled within it.
    int c = 0;
    double below = 0;
    while (c + 1 < n.count && remaining >= below + weight[c] / sum) below += weight[c++] / sum;
    const double share = weight[c] / sum;
    probability *= share;
    remaining = std::clamp((remaining - below) / share, 0.0, std::nextafter(1.0, 0.0));
    ref = n.child[c];
  }
  if (!(probability > 0)) return std::nullopt;
  return Pick{SphereOf(ref), probability};
}

std::optional<AliasTable> TargetSpheres::TableFrom(const Vec3& p) const {
  std::vector<float> weights;
  weights.reserve(spheres_.size());
  bool any = false;
  for (const BoundingSphere& s : spheres_) any |= weights.emplace_back(static_cast<float>(SolidAngle(s, p))) > 0;
  if (!any) return std::nullopt;
  return AliasTable(weights);
}

TargetSpheres::Pick TargetSpheres::PickByCrossSection(float u) const {
  if (by_cross_section_.size() == 0) return {0, 0};
  const AliasTable::Choice c = by_cross_section_.Sample(u);
  return {c.index, c.pmf};
}

}  // namespace farm
