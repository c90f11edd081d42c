#include "media/homogeneous_medium.h"

#include <algorithm>
#include <cmath>

namespace farm {
namespace {

std::array<float, 3> Channels(const Rgb& c) { return {c.r, c.g, c.b}; }

// The channels whose sigma_t is positive: those a distance can be sampled from.
struct ActiveChannels {
  std::array<float, 3> sigma{};
  int count = 0;

  explicit ActiveChannels(const Rgb& sigma_t) {
    for (const float s : Channels(sigma_t))
      if (s > 0) sigma[count++] = s;
  }
  // u in [0, 1) picks one.
  float Pick(float u) const { return sigma[std::min(count - 1, int(u * float(count)))]; }
};

// -log(1 - u) / s without losing u near 0 (log1p) and finite for u < 1.
float ExponentialSample(float s, float u) { return -std::log1p(-std::min(u, 0x1.fffffep-1f)) / s; }

}  // namespace

HomogeneousMedium HomogeneousMedium::FromCoefficients(const Rgb& sigma_a, const Rgb& sigma_s, float g) {
  return {sigma_a, sigma_s, sigma_a + sigma_s, g};
}

HomogeneousMedium HomogeneousMedium::FromAlbedo(const Rgb& albedo, float density, float g) {
  const Rgb sigma_s = albedo * density;
  // (1 - albedo) * density per channel, exactly 0 where the albedo is 1.
  const Rgb sigma_a{(1 - albedo.r) * density, (1 - albedo.g) * density, (1 - albedo.b) * density};
  return {sigma_a, sigma_s, sigma_a + sigma_s, g};
}

Rgb HomogeneousMedium::Transmittance(float d) const {
  // 0 * infinity is NaN: a channel without extinction keeps everything however far.
  const auto t = [d](float s) { return s > 0 ? std::exp(-s * d) : 1.0f; };
  return {t(sigma_t.r), t(sigma_t.g), t(sigma_t.b)};
}

std::string HomogeneousMedium::ToString() const {
  return "HomogeneousMedium{sigma_a=" + farm::ToString(sigma_a) + ", sigma_s=" + farm::ToString(sigma_s) +
         ", g=" + std::to_string(g) + "}";
}

std::optional<DistanceSample> SampleFreeFlight(const HomogeneousMedium& medium, float t_max, float u_channel, float u) {
  const ActiveChannels active(medium.sigma_t);
  if (active.count == 0) return std::nullopt;
  const float t = ExponentialSample(active.Pick(u_channel), u);
  if (!(t < t_max)) return std::nullopt;
  return DistanceSample{t, FreeFlightPdf(medium, t)};
}

float FreeFlightPdf(const HomogeneousMedium& medium, float t) {
  const ActiveChannels active(medium.sigma_t);
  if (active.count == 0) return 0;
  float sum = 0;
  for (int c = 0; c < active.count; ++c) sum += active.sigma[c] * std::exp(-active.sigma[c] * t);
  return sum / float(active.count);
}

float FreeFlightPassProbability(const HomogeneousMedium& medium, float t_max) {
  const ActiveChannels active(medium.sigma_t);
  if (active.count == 0) return 1;
  float sum = 0;
  for (int c = 0; c < active.count; ++c) sum += std::exp(-active.sigma[c] * t_max);
  return sum / float(active.count);
}

std::optional<DistanceSample> SampleTruncatedFlight(const HomogeneousMedium& medium, float t_max, float u_channel,
                                                    float u) {
  const ActiveChannels active(medium.sigma_t);
  if (active.count == 0 || !(t_max > 0)) return std::nullopt;
  const float s = active.Pick(u_channel);
  // The exponential's inverse CDF over [0, t_max]: u scaled by the mass 1 - exp(-s t_max).
  const float mass = -std::expm1(-s * t_max);
  const float t = std::min(ExponentialSample(s, u * mass), t_max);
  const float pdf = TruncatedFlightPdf(medium, t_max, t);
  if (!(pdf > 0) || !std::isfinite(pdf)) return std::nullopt;
  return DistanceSample{t, pdf};
}

float TruncatedFlightPdf(const HomogeneousMedium& medium, float t_max, float t) {
  const ActiveChannels active(medium.sigma_t);
  if (active.count == 0 || !(t >= 0 && t <= t_max)) return 0;
  float sum = 0;
  for (int c = 0; c < active.count; ++c) {
    const float s = active.sigma[c];
    sum += s * std::exp(-s * t) / -std::expm1(-s * t_max);
  }
  return sum / float(active.count);
}

}  // namespace farm
