#include "media/medium.h"

#include <algorithm>
#include <cmath>
#include <bit>
#include <cstdint>
#include <type_traits>

#include "sampling/hash.h"
#include "util/overloaded.h"

namespace farm {
namespace {

// A stream of uniform numbers in [0, 1) hashed from a key: what the trackers draw.
class HashedUniforms {
 public:
  explicit HashedUniforms(uint64_t key) : key_(key) {}
  float operator()() { return float(Hash(key_, ++count_) >> 40) * 0x1p-24f; }

 private:
  uint64_t key_;
  uint64_t count_ = 0;
};

uint64_t Bits(float x) { return std::bit_cast<uint32_t>(x); }

// The key of a flight along a ray: its origin, direction and stretch, and the sample's own
// number.
uint64_t QueryKey(const Ray& ray, float t0, float t1, uint64_t salt) {
  return Hash(Bits(ray.origin.x), Bits(ray.origin.y), Bits(ray.origin.z), Bits(ray.direction.x),
              Bits(ray.direction.y), Bits(ray.direction.z), Bits(t0), Bits(t1), salt);
}

}  // namespace

Ray GridMedium::ToGrid(const Ray& ray) const {
  return Ray{Vec3(to_grid.Apply(Vec3d(ray.origin))), Vec3(to_grid.ApplyLinear(Vec3d(ray.direction))), ray.t_max};
}

float GridMedium::SigmaT(const Vec3& p) const { return density_scale * grid->Density(Vec3(to_grid.Apply(Vec3d(p)))); }

float Medium::g() const {
  return std::visit(Overloaded{[](const OneOf<HomogeneousMedium, GridMedium> auto& m) { return m.g; }}, kind);
}

bool Medium::Scatters() const {
  return std::visit(Overloaded{[](const HomogeneousMedium& m) { return !m.sigma_s.IsBlack(); },
                               [](const GridMedium& m) { return !m.albedo.IsBlack(); }},
                    kind);
}

std::string Medium::ToString() const {
  return std::visit(Overloaded{[](const HomogeneousMedium& m) { return m.ToString(); },
                               [](const GridMedium& m) {
                                 return "GridMedium{" + std::to_string(m.grid->nx()) + "x" +
                                        std::to_string(m.grid->ny()) + "x" + std::to_string(m.grid->nz()) +
                                        " cells in " + m.grid->box().ToString() + ", density_scale=" +
                                        std::to_string(m.density_scale) + ", albedo=" + farm::ToString(m.albedo) +
                                        ", g=" + std::to_string(m.g) + "}";
                               }},
                    kind);
}

Rgb Transmittance(const Medium& medium, const Ray& ray, float t0, float t1) {
  if (!(t1 > t0)) return Rgb(1);
  return std::visit(Overloaded{[&](const HomogeneousMedium& m) { return m.Transmittance(t1 - t0); },
                               [&](const GridMedium& m) {
                                 return Rgb(float(std::exp(-double(m.density_scale) *
                                                           OpticalDepth(*m.grid, m.ToGrid(ray), t0, t1))));
                               }},
                    medium.kind);
}

Rgb ScatteringAt(const Medium& medium, const Vec3& p) {
  return std::visit(Overloaded{[](const HomogeneousMedium& m) { return m.sigma_s; },
                               [&](const GridMedium& m) { return m.albedo * m.SigmaT(p); }},
                    medium.kind);
}

std::optional<DistanceSample> SampleDistance(const Medium& medium, const Ray& ray, float t0, float t1, float u_channel,
                                             float u) {
  if (!(t1 > t0)) return std::nullopt;
  return std::visit(
      Overloaded{[&](const HomogeneousMedium& m) -> std::optional<DistanceSample> {
                   const std::optional<DistanceSample> s = SampleTruncatedFlight(m, t1 - t0, u_channel, u);
                   if (!s) return std::nullopt;
                   return DistanceSample{t0 + s->t, s->pdf};
                 },
                 [&](const GridMedium& m) {
                   return SampleTruncatedFlight(*m.grid, m.density_scale, m.ToGrid(ray), t0, t1, u);
                 }},
      medium.kind);
}

float DistancePdf(const Medium& medium, const Ray& ray, float t0, float t1, float t) {
  if (!(t1 > t0)) return 0;
  return std::visit(
      Overloaded{[&](const HomogeneousMedium& m) { return TruncatedFlightPdf(m, t1 - t0, t - t0); },
                 [&](const GridMedium& m) {
                   return TruncatedFlightPdf(*m.grid, m.density_scale, m.ToGrid(ray), t0, t1, t);
                 }},
      medium.kind);
}

FreeFlight SampleFlight(const Medium& medium, const Ray& ray, float t0, float t1, float u_channel, float u) {
  return std::visit(
      Overloaded{[&](const HomogeneousMedium& m) {
                   const float length = std::max(0.0f, t1 - t0);
                   if (const std::optional<DistanceSample> s = SampleFreeFlight(m, length, u_channel, u))
                     return FreeFlight{t0 + s->t, m.Transmittance(s->t) * m.sigma_s / s->pdf};
                   return FreeFlight{std::nullopt, m.Transmittance(length) / FreeFlightPassProbability(m, length)};
                 },
                 [&](const GridMedium& m) {
                   HashedUniforms uniforms(QueryKey(ray, t0, t1, Bits(u)));
                   if (const std::optional<float> t =
                           DeltaTrack(*m.grid, m.density_scale, m.ToGrid(ray), t0, t1, std::ref(uniforms)))
                     return FreeFlight{*t, m.albedo};
                   return FreeFlight{std::nullopt, Rgb(1)};
                 }},
      medium.kind);
}

}  // namespace farm
