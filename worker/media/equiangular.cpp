#include "media/equiangular.h"

#include <algorithm>
#include <cmath>

#include "math/math.h"

namespace farm {
namespace {

// The equiangular density over a segment, in s = t - delta (delta where the point of the
// line nearest p lies), in double: the angles of a long ray far from the light differ by
// little. Off the line it is uniform in the angle from a to b; on it (h vanishing against
// the distances involved) the limit, proportional to 1 / s^2 with mass inv0 - inv1.
struct EquiangularSegment {
  double delta = 0, h = 0, s0 = 0, s1 = 0;
  bool on_line = false;
  double a = 0, b = 0;        // off the line: the angles of the segment's ends
  double inv0 = 0, mass = 0;  // on the line: 1 / s0 and the mass of 1 / s^2

  static std::optional<EquiangularSegment> Of(const Vec3& origin, const Vec3& direction, float t_min, float t_max,
                                              const Vec3& p) {
    if (!(t_max > t_min)) return std::nullopt;
    EquiangularSegment e;
    const Vec3 to_p = p - origin;
    e.delta = Dot(to_p, direction);
    e.h = Length(to_p - direction * float(e.delta));
    e.s0 = double(t_min) - e.delta;
    e.s1 = double(t_max) - e.delta;
    const double scale = std::max(std::abs(e.s0), std::isfinite(e.s1) ? std::abs(e.s1) : 0.0);
    e.on_line = !(e.h > 1e-6 * scale);
    if (!e.on_line) {
      e.a = std::atan2(e.s0, e.h);
      e.b = std::atan2(e.s1, e.h);
      if (!(e.b > e.a)) return std::nullopt;
      return e;
    }
    // s keeps one sign over the segment unless it crosses the light, where the integrand
    // is infinite.
    if (e.s0 <= 0 && e.s1 >= 0) return std::nullopt;
    e.inv0 = 1 / e.s0;
    e.mass = e.inv0 - (std::isfinite(e.s1) ? 1 / e.s1 : 0.0);
    if (!(e.mass > 0)) return std::nullopt;
    return e;
  }

  double Density(double s) const { return on_line ? 1 / (s * s * mass) : h / ((b - a) * (h * h + s * s)); }
};

}  // namespace

std::optional<DistanceSample> SampleEquiangular(const Vec3& origin, const Vec3& direction, float t_min, float t_max,
                                                const Vec3& p, float u) {
  const std::optional<EquiangularSegment> e = EquiangularSegment::Of(origin, direction, t_min, t_max, p);
  if (!e) return std::nullopt;
  const double s = e->on_line ? 1 / (e->inv0 - double(u) * e->mass) : e->h * std::tan(e->a + double(u) * (e->b - e->a));
  const double pdf = e->Density(s);
  const float t = float(std::clamp(e->delta + s, double(t_min), double(t_max)));
  if (!std::isfinite(t) || !(pdf > 0) || !std::isfinite(pdf)) return std::nullopt;
  return DistanceSample{t, float(pdf)};
}

float EquiangularPdf(const Vec3& origin, const Vec3& direction, float t_min, float t_max, const Vec3& p, float t) {
  if (!(t >= t_min && t <= t_max)) return 0;
  const std::optional<EquiangularSegment> e = EquiangularSegment::Of(origin, direction, t_min, t_max, p);
  if (!e) return 0;
  const double pdf = e->Density(double(t) - e->delta);
  return std::isfinite(pdf) ? float(pdf) : 0.0f;
}

}  // namespace farm
