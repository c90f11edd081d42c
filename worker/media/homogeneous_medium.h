#pragma once

// A homogeneous participating medium: constant absorption sigma_a and scattering sigma_s
// per channel (sigma_t = sigma_a + sigma_s), scattering by a Henyey-Greenstein phase
// function (henyey_greenstein.h). Everything here is closed-form: light that travels a
// distance d keeps T(d) = exp(-sigma_t d) of itself (Beer-Lambert), and free-flight
// distances are sampled exactly from the density sigma_t exp(-sigma_t t), one channel
// picked at random and the channels' densities averaged (single-sample MIS over the
// channels, so no channel's colour makes another's weights blow up).

#include <array>
#include <optional>
#include <string>

#include "math/rgb.h"

namespace farm {

struct HomogeneousMedium {
  Rgb sigma_a, sigma_s, sigma_t;
  float g = 0;  // Henyey-Greenstein asymmetry, in (-1, 1)

  static HomogeneousMedium FromCoefficients(const Rgb& sigma_a, const Rgb& sigma_s, float g);
  // sigma_s = albedo * density, sigma_a = (1 - albedo) * density.
  static HomogeneousMedium FromAlbedo(const Rgb& albedo, float density, float g);

  // exp(-sigma_t d) per channel; d may be infinite (1 in a channel where sigma_t is 0).
  Rgb Transmittance(float d) const;
  // Whether nothing happens in it: sigma_t is 0 in every channel.
  bool IsVacuum() const { return sigma_t.IsBlack(); }

  std::string ToString() const;
};

// A distance sampled along a ray in a medium, within [0, t_max].
struct DistanceSample {
  float t = 0;
  // The density of t among the distances the sampler returns (per unit length).
  float pdf = 0;
};

// Free flight: t from the channel-averaged density p(t) = mean_c sigma_t,c exp(-sigma_t,c t)
// over the channels where sigma_t > 0 (u_channel picks one, u the distance). Nothing if t
// lands past t_max (the flight reaches the ray's end: that happens with probability
// FreeFlightPassProbability) or the medium is vacuum.
std::optional<DistanceSample> SampleFreeFlight(const HomogeneousMedium& medium, float t_max, float u_channel, float u);
float FreeFlightPdf(const HomogeneousMedium& medium, float t);
float FreeFlightPassProbability(const HomogeneousMedium& medium, float t_max);

// Free flight truncated to [0, t_max] (t_max may be infinite): every sample lands on the
// segment, with the channel-averaged truncated density mean_c sigma_t,c exp(-sigma_t,c t)
// / (1 - exp(-sigma_t,c t_max)), over the channels where sigma_t > 0; for single scattering
// from lights that are not points. Nothing for vacuum or an empty segment.
std::optional<DistanceSample> SampleTruncatedFlight(const HomogeneousMedium& medium, float t_max, float u_channel,
                                                    float u);
float TruncatedFlightPdf(const HomogeneousMedium& medium, float t_max, float t);

}  // namespace farm
