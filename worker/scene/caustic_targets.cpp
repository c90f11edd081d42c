#include "scene/caustic_targets.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "math/math.h"
#include "util/overloaded.h"

namespace farm {

struct CausticTargets::BinaryNode {
  Bounds3 box;    // of the spheres below, grown by a margin against rounding
  int first = 0;  // a leaf: its first sphere; an inner node: its second child
  int count = 0;  // spheres of a leaf; 0 for an inner node (first child: the next node)
};

namespace {

constexpr int kLeafSpheres = 4;
constexpr float kRelativeMargin = CausticTargets::kRelativeMargin;

// Where a light with an origin emits from: a sphere about it (radius 0 for point and spot
// lights); none for light from infinitely far away.
std::optional<BoundingSphere> EmitterSphere(const Light& light) {
  return std::visit(
      Overloaded{
          [](const SphereLight& l) -> std::optional<BoundingSphere> { return BoundingSphere{l.sphere.center, l.sphere.radius}; },
          [](const QuadLight& l) -> std::optional<BoundingSphere> {
            Bounds3 b;
            for (const Vec3& p : {l.quad.origin, l.quad.origin + l.quad.edge_u, l.quad.origin + l.quad.edge_v,
                                  l.quad.origin + l.quad.edge_u + l.quad.edge_v})
              b.Extend(p);
            return BoundingSphere::Of(b);
          },
          [](const TriangleMeshLight& l) -> std::optional<BoundingSphere> {
            Bounds3 b;
            for (int i = 0; i < l.mesh->triangle_count(); ++i) {
              Vec3 p0, p1, p2;
              l.Corners(i, p0, p1, p2);
              b.Extend(p0);
              b.Extend(p1);
              b.Extend(p2);
            }
            return BoundingSphere::Of(b);
          },
          [](const PointLight& l) -> std::optional<BoundingSphere> { return BoundingSphere{l.position, 0}; },
          [](const SpotLight& l) -> std::optional<BoundingSphere> { return BoundingSphere{l.position, 0}; },
          [](const OneOf<SunLight, EnvironmentLight> auto&) -> std::optional<BoundingSphere> { return std::nullopt; },
      },
      light);
}

// The largest solid angle `target` subtends from a point of `emitter`: 2 pi once they overlap.
float LargestSolidAngle(const BoundingSphere& target, const BoundingSphere& emitter) {
  const float gap = Length(target.center - emitter.center) - emitter.radius;
  if (gap <= target.radius) return 2 * kPi;
  const float sin2 = Sqr(target.radius / gap);
  return 2 * kPi * sin2 / (1 + std::sqrt(1 - sin2));  // 1 - cos, without cancellation
}

bool Overlap(const BoundingSphere& a, const BoundingSphere& b) {
  return LengthSquared(a.center - b.center) <= Sqr(a.radius + b.radius) * (1 + kRelativeMargin);
}

}  // namespace

CausticTargets::CausticTargets(std::span<const BoundingSphere> spheres, std::span<const Light> lights)
    : spheres_(spheres.begin(), spheres.end()) {
  if (spheres_.empty()) return;
  std::vector<BinaryNode> tree;
  tree.reserve(2 * spheres_.size() / kLeafSpheres + 2);
  BuildBinary(spheres_, 0, size(), tree);
  root_box_ = tree[0].box;
  nodes_.reserve(tree.size() / 2 + 1);
  Collapse(tree, 0);

  std::vector<float> weights;
  for (const BoundingSphere& s : spheres_) weights.push_back(s.radius * s.radius);
  tables_.emplace_back(weights);
  std::vector<std::optional<BoundingSphere>> emitters;
  for (const Light& light : lights) emitters.push_back(EmitterSphere(light));
  const auto origins = std::count_if(emitters.begin(), emitters.end(), [](const auto& e) { return e.has_value(); });
  const bool per_light = static_cast<std::size_t>(origins) * spheres_.size() <= kMaxTableEntries;
  for (const std::optional<BoundingSphere>& emitter : emitters) {
    may_contain_.push_back(emitter && std::any_of(spheres_.begin(), spheres_.end(),
                                                  [&](const BoundingSphere& s) { return Overlap(s, *emitter); }));
    if (!emitter || !per_light) {
      table_of_light_.push_back(0);
      continue;
    }
    for (std::size_t k = 0; k < spheres_.size(); ++k) weights[k] = LargestSolidAngle(spheres_[k], *emitter);
    table_of_light_.push_back(static_cast<int>(tables_.size()));
    tables_.emplace_back(weights);
  }
}

// Median split of spheres[begin, end) along the widest axis of the centres, appending the
// nodes to tree; returns the node.
int CausticTargets::BuildBinary(std::vector<BoundingSphere>& spheres, int begin, int end,
                                std::vector<BinaryNode>& tree) {
  Bounds3 box, centres;
  for (int k = begin; k < end; ++k) {
    const BoundingSphere& s = spheres[k];
    const Vec3 r(s.radius, s.radius, s.radius);
    box.Extend(s.center - r);
    box.Extend(s.center + r);
    centres.Extend(s.center);
  }
  const int index = static_cast<int>(tree.size());
  const Vec3 grow = Vec3(1, 1, 1) * (kRelativeMargin * (box.Diagonal() + MaxComponent(Max(Abs(box.min), Abs(box.max)))));
  tree.push_back({Bounds3{box.min - grow, box.max + grow}, begin, end - begin});
  if (end - begin <= kLeafSpheres) return index;
  const Vec3 extent = centres.max - centres.min;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const auto key = [axis](const BoundingSphere& s) { return axis == 0 ? s.center.x : axis == 1 ? s.center.y : s.center.z; };
  const int middle = begin + (end - begin) / 2;
  std::nth_element(spheres.begin() + begin, spheres.begin() + middle, spheres.begin() + end,
                   [&](const BoundingSphere& a, const BoundingSphere& b) { return key(a) < key(b); });
  BuildBinary(spheres, begin, middle, tree);  // the first child: the next node
  const int second = BuildBinary(spheres, middle, end, tree);
  tree[index].first = second;
  tree[index].count = 0;
  return index;
}

// A wide node for binary node `index`: its children, the inner ones among them replaced
// by theirs while there is room.
int CausticTargets::Collapse(const std::vector<BinaryNode>& tree, int index) {
  std::vector<int> slots;
  if (tree[index].count > 0) {
    slots = {index};
  } else {
    slots = {index + 1, tree[index].first};
  }
  for (std::size_t i = 0; i < slots.size() && slots.size() < 4;) {
    const BinaryNode& n = tree[slots[i]];
    if (n.count > 0) {
      ++i;
      continue;
    }
    const int left = slots[i] + 1, right = n.first;
    slots[i] = left;
    slots.insert(slots.begin() + static_cast<std::ptrdiff_t>(i) + 1, right);
  }
  const int wide = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  for (int c = 0; c < 4; ++c) {
    WideNode& w = nodes_[wide];
    if (c >= static_cast<int>(slots.size())) {
      const float inf = std::numeric_limits<float>::infinity();
      for (int a = 0; a < 3; ++a) {
        w.lo[a][c] = inf;
        w.hi[a][c] = -inf;
      }
      w.first[c] = 0;
      w.count[c] = -1;
      continue;
    }
    const BinaryNode& n = tree[slots[c]];
    const float lo[3] = {n.box.min.x, n.box.min.y, n.box.min.z}, hi[3] = {n.box.max.x, n.box.max.y, n.box.max.z};
    for (int a = 0; a < 3; ++a) {
      w.lo[a][c] = lo[a];
      w.hi[a][c] = hi[a];
    }
    w.count[c] = n.count;
    w.first[c] = n.count > 0 ? n.first : 0;
    if (n.count == 0) {
      const int child = Collapse(tree, slots[c]);  // may move nodes_
      nodes_[wide].first[c] = child;
    }
  }
  return wide;
}

CausticTargets::RayQuery CausticTargets::Query(const Vec3& o, const Vec3& w, float t_min, float slack) const {
  RayQuery q;
  q.o = o;
  q.w = w;
  q.origin[0] = o.x;
  q.origin[1] = o.y;
  q.origin[2] = o.z;
  q.t_min = t_min;
  const float d[3] = {w.x, w.y, w.z};
  for (int a = 0; a < 3; ++a) {
    // A zero component would make 0 * infinity: a tiny one keeps the test conservative (the
    // slab's times become huge, of the right signs).
    q.inv[a] = 1 / (std::abs(d[a]) < 1e-20f ? 1e-20f : d[a]);
    q.near_is_max[a] = q.inv[a] < 0;
  }
  const Vec3 far = Max(Abs(root_box_.min - o), Abs(root_box_.max - o));
  q.grow = slack * Length(far);  // the farthest corner
  return q;
}

bool CausticTargets::AnyContains(const Vec3& p) const {
  bool found = false;
  const float q[3] = {p.x, p.y, p.z};
  Traverse(
      [&](const WideNode& n) {
        int mask = 0;
        for (int c = 0; c < 4 && !found; ++c) {
          bool inside = true;
          for (int a = 0; a < 3; ++a) inside = inside && q[a] >= n.lo[a][c] && q[a] <= n.hi[a][c];
          mask |= inside << c;
        }
        return mask;
      },
      [&](int k) { found = found || LengthSquared(spheres_[k].center - p) <= spheres_[k].radius * spheres_[k].radius; });
  return found;
}

}  // namespace farm
