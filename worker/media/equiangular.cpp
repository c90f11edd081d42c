#include "media/equiangular.h"

#include <algorithm>
#include <cmath>

#include "math/math.h"

namespace farm {

std::optional<DistanceSample> SampleEquiangular(const Vec3& origin, const Vec3& direction, float t_min, float t_max,
                                                const Vec3& p, float u) {
  if (!(t_max > t_min)) return std::nullopt;
  // In double: the angles of a long ray far from the light differ by little.
  const Vec3 to_p = p - origin;
  const double delta = Dot(to_p, direction);
  const double h = Length(to_p - direction * float(delta));
  const double s0 = double(t_min) - delta, s1 = double(t_max) - delta;  // s = t - delta
  const double scale = std::max(std::abs(s0), std::isfinite(s1) ? std::abs(s1) : 0.0);
  double s, pdf;
  if (h > 1e-6 * scale) {
    const double a = std::atan2(s0, h), b = std::atan2(s1, h);
    if (!(b > a)) return std::nullopt;
    s = h * std::tan(a + double(u) * (b - a));
    pdf = h / ((b - a) * (h * h + s * s));
  } else {
    // The light on the line: s keeps one sign over the segment unless it crosses the
    // light, where the integrand is infinite.
    if (s0 <= 0 && s1 >= 0) return std::nullopt;
    const double inv0 = 1 / s0, inv1 = std::isfinite(s1) ? 1 / s1 : 0.0;
    const double mass = inv0 - inv1;  // of 1 / s^2 over the segment
    if (!(mass > 0)) return std::nullopt;
    s = 1 / (inv0 - double(u) * mass);
    pdf = 1 / (s * s * mass);
  }
  const float t = float(std::clamp(delta + s, double(t_min), double(t_max)));
  if (!std::isfinite(t) || !(pdf > 0) || !std::isfinite(pdf)) return std::nullopt;
  return DistanceSample{t, float(pdf)};
}

}  // namespace farm
