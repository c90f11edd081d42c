#include "scene/disc_coverage.h"

#include <algorithm>
#include <cmath>

#include "math/frame.h"
#include "math/ray.h"
#include "sampling/hash.h"
#include "sampling/sobol.h"
#include "sampling/warps.h"

namespace farm {

namespace {

// As the estimates' normal rule (radiance_estimate.cpp): a surface within 60 degrees of n.
constexpr float kMinNormalCosine = 0.5f;
// How far the probe segments are lifted off the surface, as a share of r: above a concave
// surface's rise over the disc (r / 2R for a sphere of radius R), below any wall's height.
constexpr float kLift = 0.1f;

}  // namespace

float DiscCoverage(const SceneData& scene, const Vec3& p, const Vec3& n, float r, uint32_t seed,
                   const std::function<float(float)>& weight) {
  if (!(r > 0)) return 1;
  const Frame frame = Frame::FromZ(n);
  const Vec3 lifted = p + n * (kLift * r);
  // A point on no surface the scene holds (an estimate over photons placed by hand) has no
  // coverage to measure: the whole disc is taken.
  if (!scene.IntersectFacing(Ray{lifted, -n, 2 * kLift * r})) return 1;
  const uint64_t h = Hash(seed);
  float covered = 0, total = 0;
  for (uint32_t i = 0; i < kDiscCoverageProbes; ++i) {
    const Vec2 d = SampleUniformDiskConcentric(
        {SobolSample(i, 0, uint32_t(h)), SobolSample(i, 1, uint32_t(h >> 32))});
    const float u = std::sqrt(d.x * d.x + d.y * d.y);
    const float w = weight ? weight(u) : 1.0f;
    total += w;
    const Vec3 above = lifted + frame.FromLocal(Vec3(d.x, d.y, 0)) * r;
    if (!scene.SegmentClear(lifted, above)) continue;  // a wall rises between p and the point
    const std::optional<SceneData::FacingHit> below = scene.IntersectFacing(Ray{above, -n, (1 + kLift) * r});
    if (!below || !(AbsDot(below->n, n) >= kMinNormalCosine)) continue;  // past the surface's rim
    covered += w;
  }
  return total > 0 ? std::max(covered / total, 1.0f / kDiscCoverageProbes) : 1.0f;
}

}  // namespace farm
