#include "media/dense_grid.h"

#include <algorithm>
#include <cmath>

namespace farm {
namespace {

// The part of [0, t_max] of the ray inside the box (slabs), or nothing.
std::optional<std::pair<float, float>> Clip(const Bounds3& box, const Ray& ray, float t_max) {
  float t0 = 0, t1 = t_max;
  const float o[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
  const float d[3] = {ray.direction.x, ray.direction.y, ray.direction.z};
  const float lo[3] = {box.min.x, box.min.y, box.min.z}, hi[3] = {box.max.x, box.max.y, box.max.z};
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) {
      if (o[a] < lo[a] || o[a] > hi[a]) return std::nullopt;
      continue;
    }
    float near = (lo[a] - o[a]) / d[a], far = (hi[a] - o[a]) / d[a];
    if (near > far) std::swap(near, far);
    t0 = std::max(t0, near);
    t1 = std::min(t1, far);
  }
  if (!(t1 > t0)) return std::nullopt;
  return std::pair{t0, t1};
}

// Tentative collisions against the majorant over the box's part of the ray: calls
// `collide(t, sigma / majorant)` at each, stopping when it returns false. Returns whether
// the flight got past the end.
template <typename Collide>
bool Track(const DenseGrid& grid, float sigma_scale, const Ray& ray, float t_max, const UniformSource& u,
           Collide collide) {
  const float majorant = grid.max_density() * sigma_scale;
  const std::optional<std::pair<float, float>> span = Clip(grid.box(), ray, t_max);
  if (!span || !(majorant > 0)) return true;
  for (float t = span->first;;) {
    t -= std::log1p(-std::min(u(), 0x1.fffffep-1f)) / majorant;
    if (t >= span->second) return true;
    if (!collide(t, grid.Density(ray.At(t)) * sigma_scale / majorant)) return false;
  }
}

}  // namespace

DenseGrid::DenseGrid(int nx, int ny, int nz, std::vector<float> values, const Bounds3& box)
    : nx_(nx), ny_(ny), nz_(nz), values_(std::move(values)), box_(box) {
  if (nx < 1 || ny < 1 || nz < 1 || values_.size() != std::size_t(nx) * ny * nz)
    throw std::invalid_argument("dense grid: " + std::to_string(values_.size()) + " values for " + std::to_string(nx) +
                                " x " + std::to_string(ny) + " x " + std::to_string(nz) + " cells");
  if (box.empty() || !(box.max.x > box.min.x && box.max.y > box.min.y && box.max.z > box.min.z))
    throw std::invalid_argument("dense grid: empty box " + box.ToString());
  for (const float v : values_) {
    if (!(v >= 0) || !std::isfinite(v)) throw std::invalid_argument("dense grid: a density that is not finite and >= 0");
    max_ = std::max(max_, v);
  }
}

float DenseGrid::Density(const Vec3& p) const {
  if (p.x < box_.min.x || p.y < box_.min.y || p.z < box_.min.z || p.x > box_.max.x || p.y > box_.max.y ||
      p.z > box_.max.z)
    return 0;
  // Continuous cell coordinates, cell centres at integers, clamped to the outer centres.
  const auto axis = [](float v, float lo, float hi, int n, int& i, float& f) {
    const float c = std::clamp((v - lo) / (hi - lo) * float(n) - 0.5f, 0.0f, float(n - 1));
    i = std::min(int(c), std::max(n - 2, 0));
    f = n > 1 ? c - float(i) : 0.0f;
  };
  int x, y, z;
  float fx, fy, fz;
  axis(p.x, box_.min.x, box_.max.x, nx_, x, fx);
  axis(p.y, box_.min.y, box_.max.y, ny_, y, fy);
  axis(p.z, box_.min.z, box_.max.z, nz_, z, fz);
  const int x1 = std::min(x + 1, nx_ - 1), y1 = std::min(y + 1, ny_ - 1), z1 = std::min(z + 1, nz_ - 1);
  const auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
  const float c00 = lerp(At(x, y, z), At(x1, y, z), fx), c10 = lerp(At(x, y1, z), At(x1, y1, z), fx);
  const float c01 = lerp(At(x, y, z1), At(x1, y, z1), fx), c11 = lerp(At(x, y1, z1), At(x1, y1, z1), fx);
  return lerp(lerp(c00, c10, fy), lerp(c01, c11, fy), fz);
}

std::optional<float> DeltaTrack(const DenseGrid& grid, float sigma_scale, const Ray& ray, float t_max,
                                const UniformSource& u) {
  float hit = 0;
  const bool passed = Track(grid, sigma_scale, ray, t_max, u, [&](float t, float ratio) {
    if (u() >= ratio) return true;  // a null collision: fly on
    hit = t;
    return false;
  });
  if (passed) return std::nullopt;
  return hit;
}

float RatioTrackTransmittance(const DenseGrid& grid, float sigma_scale, const Ray& ray, float t_max,
                              const UniformSource& u) {
  float transmittance = 1;
  Track(grid, sigma_scale, ray, t_max, u, [&](float, float ratio) {
    transmittance *= 1 - ratio;
    return transmittance > 0;
  });
  return transmittance;
}

}  // namespace farm
