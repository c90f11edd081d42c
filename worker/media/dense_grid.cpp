#include "media/dense_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace farm {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

}  // namespace

std::optional<std::pair<float, float>> ClipToBox(const Bounds3& box, const Ray& ray, float t_min, float t_max) {
  float t0 = t_min, t1 = t_max;
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

namespace {

// -log(1 - u) without losing u near 0 (log1p) and finite for u < 1.
float Exponential(float u) { return -std::log1p(-std::min(u, 0x1.fffffep-1f)); }

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
  // Each brick's bounds: the largest and smallest value its interpolation reads (the cells
  // from one before its first to one past its last: Density's neighbours; a trilinear
  // value lies between them), widened by one more cell each way so that a point rounded
  // across a brick's face stays within them.
  const int n[3] = {nx, ny, nz};
  for (int a = 0; a < 3; ++a) bricks_[a] = (n[a] + kBrick - 1) / kBrick;
  brick_max_.assign(std::size_t(bricks_[0]) * bricks_[1] * bricks_[2], 0.0f);
  brick_min_.assign(brick_max_.size(), 0.0f);
  const auto range = [&](int a, int b, int& lo, int& hi) {
    lo = std::max(0, b * kBrick - 2);
    hi = std::min(n[a] - 1, b * kBrick + kBrick + 1);
  };
  for (int bz = 0; bz < bricks_[2]; ++bz)
    for (int by = 0; by < bricks_[1]; ++by)
      for (int bx = 0; bx < bricks_[0]; ++bx) {
        int x0, x1, y0, y1, z0, z1;
        range(0, bx, x0, x1);
        range(1, by, y0, y1);
        range(2, bz, z0, z1);
        float lo = At(x0, y0, z0), hi = lo;
        for (int z = z0; z <= z1; ++z)
          for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
              lo = std::min(lo, At(x, y, z));
              hi = std::max(hi, At(x, y, z));
            }
        brick_min_[Brick(bx, by, bz)] = lo;
        brick_max_[Brick(bx, by, bz)] = hi;
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

DenseGrid::Walk::Walk(const DenseGrid& grid, const Ray& ray, float t_min, float t_max) : grid_(grid) {
  const std::optional<std::pair<float, float>> span = ClipToBox(grid.box_, ray, t_min, t_max);
  if (!span) return;
  t_ = span->first;
  t_end_ = span->second;
  done_ = false;
  const Vec3 entry = ray.At(t_);
  const float o[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
  const float d[3] = {ray.direction.x, ray.direction.y, ray.direction.z};
  const float p[3] = {entry.x, entry.y, entry.z};
  const float lo[3] = {grid.box_.min.x, grid.box_.min.y, grid.box_.min.z};
  const float hi[3] = {grid.box_.max.x, grid.box_.max.y, grid.box_.max.z};
  const int n[3] = {grid.nx_, grid.ny_, grid.nz_};
  for (int a = 0; a < 3; ++a) {
    const float extent = (hi[a] - lo[a]) * float(kBrick) / float(n[a]);  // of a brick
    index_[a] = std::clamp(int(std::floor((p[a] - lo[a]) / extent)), 0, grid.bricks_[a] - 1);
    if (d[a] > 0) {
      step_[a] = 1;
      next_[a] = (lo[a] + float(index_[a] + 1) * extent - o[a]) / d[a];
      delta_[a] = extent / d[a];
    } else if (d[a] < 0) {
      step_[a] = -1;
      next_[a] = (lo[a] + float(index_[a]) * extent - o[a]) / d[a];
      delta_[a] = -extent / d[a];
    } else {
      next_[a] = kInf;
    }
  }
}

bool DenseGrid::Walk::Next(Span& span) {
  if (done_) return false;
  const int a = next_[0] < next_[1] ? (next_[0] < next_[2] ? 0 : 2) : (next_[1] < next_[2] ? 1 : 2);
  const float exit = std::max(t_, std::min(next_[a], t_end_));
  const std::size_t brick = grid_.Brick(index_[0], index_[1], index_[2]);
  span = {t_, exit, grid_.brick_min_[brick], grid_.brick_max_[brick]};
  t_ = exit;
  index_[a] += step_[a];
  next_[a] += delta_[a];
  done_ = !(exit < t_end_) || index_[a] < 0 || index_[a] >= grid_.bricks_[a];
  return true;
}

std::optional<float> DeltaTrack(const DenseGrid& grid, float sigma_scale, const Ray& ray, float t_min, float t_max,
                                const UniformSource& u) {
  if (!(sigma_scale > 0)) return std::nullopt;
  DenseGrid::Walk walk(grid, ray, t_min, t_max);
  for (DenseGrid::Span span; walk.Next(span);) {
    const float majorant = span.majorant * sigma_scale;
    if (!(majorant > 0)) continue;  // an empty brick: nothing to meet
    // Exponential steps are memoryless: each brick starts afresh at its entry.
    for (float t = span.t0;;) {
      t += Exponential(u()) / majorant;
      if (!(t < span.t1)) break;
      // A real collision with probability sigma / majorant, else a null one: fly on.
      if (u() < grid.Density(ray.At(t)) * sigma_scale / majorant) return t;
    }
  }
  return std::nullopt;
}

float RatioTrackTransmittance(const DenseGrid& grid, float sigma_scale, const Ray& ray, float t_min, float t_max,
                              const UniformSource& u) {
  if (!(sigma_scale > 0)) return 1;
  double transmittance = 1;
  DenseGrid::Walk walk(grid, ray, t_min, t_max);
  for (DenseGrid::Span span; walk.Next(span);) {
    const float minorant = span.minorant * sigma_scale;
    transmittance *= std::exp(-double(minorant) * (span.t1 - span.t0));
    const float residual = span.majorant * sigma_scale - minorant;
    if (!(residual > 0)) continue;  // a uniform brick: its closed form is all
    for (float t = span.t0;;) {
      t += Exponential(u()) / residual;
      if (!(t < span.t1)) break;
      const float ratio = std::clamp((grid.Density(ray.At(t)) * sigma_scale - minorant) / residual, 0.0f, 1.0f);
      transmittance *= 1 - ratio;
      if (transmittance == 0) return 0;
    }
  }
  return float(transmittance);
}

std::optional<DistanceSample> SampleMajorantDistance(const DenseGrid& grid, float sigma_scale, const Ray& ray,
                                                     float t_min, float t_max, float u) {
  if (!(sigma_scale > 0)) return std::nullopt;
  double depth = 0;  // the majorants' optical depth over the stretch
  DenseGrid::Walk all(grid, ray, t_min, t_max);
  for (DenseGrid::Span span; all.Next(span);) depth += double(span.majorant) * sigma_scale * (span.t1 - span.t0);
  if (!(depth > 0)) return std::nullopt;
  const double mass = -std::expm1(-depth);
  const double target = -std::log1p(-double(u) * mass);  // the optical depth to land at
  double reached = 0;
  DenseGrid::Walk walk(grid, ray, t_min, t_max);
  DenseGrid::Span last;
  for (DenseGrid::Span span; walk.Next(span);) {
    const double m = double(span.majorant) * sigma_scale;
    const double here = m * (span.t1 - span.t0);
    if (m > 0) last = span;
    if (m > 0 && reached + here >= target) {
      const float t = std::min(span.t1, float(span.t0 + (target - reached) / m));
      return DistanceSample{t, float(m * std::exp(-target) / mass)};
    }
    reached += here;
  }
  // Rounding left the target a hair past the sum: the end of the last brick that holds
  // anything.
  const double m = double(last.majorant) * sigma_scale;
  return DistanceSample{last.t1, float(m * std::exp(-depth) / mass)};
}

}  // namespace farm
