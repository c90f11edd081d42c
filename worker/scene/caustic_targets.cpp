#include "scene/caustic_targets.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "math/math.h"
#include "util/overloaded.h"

namespace farm {
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
  nodes_.reserve(2 * spheres_.size() / kLeafSpheres + 2);
  Build(0, size());

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

// Median split of [begin, end) along the widest axis of the centres; returns the node.
int CausticTargets::Build(int begin, int end) {
  Bounds3 box, centres;
  for (int k = begin; k < end; ++k) {
    const BoundingSphere& s = spheres_[k];
    const Vec3 r(s.radius, s.radius, s.radius);
    box.Extend(s.center - r);
    box.Extend(s.center + r);
    centres.Extend(s.center);
  }
  const int index = static_cast<int>(nodes_.size());
  const Vec3 grow = Vec3(1, 1, 1) * (kRelativeMargin * (box.Diagonal() + MaxComponent(Max(Abs(box.min), Abs(box.max)))));
  Node node;
  node.box = {box.min - grow, box.max + grow};
  node.radius = node.box.Diagonal() / 2;
  nodes_.push_back(node);
  if (end - begin <= kLeafSpheres) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return index;
  }
  const Vec3 extent = centres.max - centres.min;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const auto key = [axis](const BoundingSphere& s) { return axis == 0 ? s.center.x : axis == 1 ? s.center.y : s.center.z; };
  const int middle = begin + (end - begin) / 2;
  std::nth_element(spheres_.begin() + begin, spheres_.begin() + middle, spheres_.begin() + end,
                   [&](const BoundingSphere& a, const BoundingSphere& b) { return key(a) < key(b); });
  Build(begin, middle);  // the first child: the next node
  const int second = Build(middle, end);
  nodes_[index].first = second;
  return index;
}

CausticTargets::RayQuery CausticTargets::Query(const Vec3& o, const Vec3& w, float t_min, float slack) const {
  RayQuery q;
  q.o = o;
  q.w = w;
  q.t_min = t_min;
  const float d[3] = {w.x, w.y, w.z};
  for (int a = 0; a < 3; ++a) {
    // A zero component would make 0 * infinity: a tiny one keeps the test conservative (the
    // slab's times become huge, of the right signs).
    q.inv[a] = 1 / (std::abs(d[a]) < 1e-20f ? 1e-20f : d[a]);
    q.near_is_max[a] = q.inv[a] < 0;
  }
  const Bounds3& root = nodes_.empty() ? Bounds3{} : nodes_[0].box;
  const Vec3 far = Max(Abs(root.min - o), Abs(root.max - o));
  q.grow = slack * (far.x + far.y + far.z);
  return q;
}

bool CausticTargets::AnyContains(const Vec3& p) const {
  bool found = false;
  const auto inside = [&](const Bounds3& b) {
    return p.x >= b.min.x && p.y >= b.min.y && p.z >= b.min.z && p.x <= b.max.x && p.y <= b.max.y && p.z <= b.max.z;
  };
  Traverse([&](const Node& n) { return !found && inside(n.box); },
           [&](int k) { found = found || LengthSquared(spheres_[k].center - p) <= spheres_[k].radius * spheres_[k].radius; });
  return found;
}

}  // namespace farm
