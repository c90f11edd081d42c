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

void DenseGrid::Pieces(const Ray& ray, const Span& span, const PieceVisit& visit) const {
  // Where the ray crosses a plane of cell centres (c_a integer, c_a = (p_a - lo_a) / cell_a
  // - 0.5) the interpolation's piece changes; between two crossings the density along the
  // ray is a polynomial of degree at most 3 in t, which Simpson's rule integrates exactly.
  // A uniform brick is one piece.
  if (span.minorant == span.majorant) {
    visit(span.t0, span.t1, double(span.majorant) * (span.t1 - span.t0));
    return;
  }
  const float o[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
  const float d[3] = {ray.direction.x, ray.direction.y, ray.direction.z};
  const float lo[3] = {box_.min.x, box_.min.y, box_.min.z}, hi[3] = {box_.max.x, box_.max.y, box_.max.z};
  const int n[3] = {nx_, ny_, nz_};
  float next[3], delta[3];
  for (int a = 0; a < 3; ++a) {
    const float cell = (hi[a] - lo[a]) / float(n[a]);
    if (d[a] == 0) {
      next[a] = delta[a] = kInf;
      continue;
    }
    const float c = (o[a] + span.t0 * d[a] - lo[a]) / cell - 0.5f;  // at the span's start
    const float k = d[a] > 0 ? std::floor(c) + 1 : std::ceil(c) - 1;  // the next centre plane
    next[a] = ((k + 0.5f) * cell + lo[a] - o[a]) / d[a];
    delta[a] = cell / std::abs(d[a]);
    if (!(next[a] > span.t0)) next[a] += delta[a];  // rounding put it behind
  }
  float t = span.t0;
  float at_t = Density(ray.At(t));
  while (t < span.t1) {
    const int a = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
    const float end = std::min(next[a], span.t1);
    if (end > t) {
      const float at_end = Density(ray.At(end));
      const double depth = (double(end) - t) / 6 * (double(at_t) + 4.0 * Density(ray.At(0.5f * (t + end))) + at_end);
      if (!visit(t, end, depth)) return;
      t = end;
      at_t = at_end;
    }
    next[a] += delta[a];
  }
}

double DenseGrid::DepthBetween(const Ray& ray, float a, float b) const {
  return (double(b) - a) / 6 * (double(Density(ray.At(a))) + 4.0 * Density(ray.At(0.5f * (a + b))) + Density(ray.At(b)));
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

double OpticalDepth(const DenseGrid& grid, const Ray& ray, float t_min, float t_max) {
  double depth = 0;
  DenseGrid::Walk walk(grid, ray, t_min, t_max);
  for (DenseGrid::Span span; walk.Next(span);) {
    if (!(span.majorant > 0)) continue;  // an empty brick
    grid.Pieces(ray, span, [&](float, float, double piece) {
      depth += piece;
      return true;
    });
  }
  return depth;
}

std::optional<DistanceSample> SampleTruncatedFlight(const DenseGrid& grid, float sigma_scale, const Ray& ray,
                                                    float t_min, float t_max, float u) {
  const double total = OpticalDepth(grid, ray, t_min, t_max);
  if (!(sigma_scale > 0) || !(total > 0)) return std::nullopt;
  const double mass = -std::expm1(-sigma_scale * total);
  if (!(mass > 0)) return std::nullopt;
  // The depth (in the grid's units) at which the flight lands: the exponential's inverse
  // CDF over [0, total], then the piece that holds it, and the point in the piece by
  // Newton's method on its (exactly integrated) depth, kept inside by bisection.
  const double target = std::min(total, -std::log1p(-double(u) * mass) / sigma_scale);
  double reached = 0;
  float end = t_min;  // of the last piece that holds anything
  std::optional<DistanceSample> landed;
  DenseGrid::Walk walk(grid, ray, t_min, t_max);
  for (DenseGrid::Span span; !landed && walk.Next(span);) {
    if (!(span.majorant > 0)) continue;
    grid.Pieces(ray, span, [&](float a, float b, double piece) {
      if (piece > 0) end = b;
      if (reached + piece < target) {
        reached += piece;
        return true;
      }
      const double need = std::clamp(target - reached, 0.0, piece);
      float lo = a, hi = b, t = piece > 0 ? float(a + (b - a) * (need / piece)) : a;
      for (int i = 0; i < 24 && hi > lo; ++i) {
        const double excess = grid.DepthBetween(ray, a, t) - need;
        if (excess > 0) hi = t;
        else lo = t;
        const float density = grid.Density(ray.At(t));
        const float newton = density > 0 ? float(t - excess / density) : -1;
        t = newton > lo && newton < hi ? newton : 0.5f * (lo + hi);
      }
      const double pdf = sigma_scale * grid.Density(ray.At(t)) * std::exp(-sigma_scale * (reached + need)) / mass;
      if (pdf > 0) landed = DistanceSample{t, float(pdf)};
      return false;
    });
  }
  if (!landed) {
    // Rounding left the target a hair past the pieces' sum: the end of the last one.
    const double pdf = sigma_scale * grid.Density(ray.At(end)) * std::exp(-sigma_scale * total) / mass;
    if (pdf > 0) landed = DistanceSample{end, float(pdf)};
  }
  return landed;
}

float TruncatedFlightPdf(const DenseGrid& grid, float sigma_scale, const Ray& ray, float t_min, float t_max,
                         float t) {
  if (!(sigma_scale > 0) || !(t >= t_min && t <= t_max)) return 0;
  double total = 0, to_t = 0;
  DenseGrid::Walk walk(grid, ray, t_min, t_max);
  for (DenseGrid::Span span; walk.Next(span);) {
    if (!(span.majorant > 0)) continue;
    grid.Pieces(ray, span, [&](float a, float b, double piece) {
      total += piece;
      if (b <= t) to_t += piece;
      else if (a < t) to_t += grid.DepthBetween(ray, a, t);  // the piece that holds t
      return true;
    });
  }
  const double mass = -std::expm1(-sigma_scale * total);
  if (!(mass > 0)) return 0;
  return float(sigma_scale * grid.Density(ray.At(t)) * std::exp(-sigma_scale * to_t) / mass);
}

}  // namespace farm
