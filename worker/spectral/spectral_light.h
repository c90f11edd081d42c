#pragma once

// Light carried at a few wavelengths: what a camera path's throughput or a photon's power
// is in spectral mode (Sampling.spectral ALWAYS, kWavelengthsPerPath from the path's start)
// and past a dispersive surface (one wavelength: the hero, or one drawn there).
//
// Each wavelength, alone, is drawn with MonochromePath's density, so each one's estimate
// (MonochromePath::ToRgb) is unbiased and their mean is too: stratified wavelengths
// are Wilkie et al.'s hero-wavelength sampling ("Hero Wavelength Spectral Sampling", EGSR
// 2014), rotated in that density's cumulative range rather than in nanometres. Keeping the
// hero alone at a dispersive surface, where each wavelength would leave in a direction of
// its own, stays unbiased for the same reason.

#include <array>

#include "math/rgb.h"
#include "spectral/monochrome.h"
#include "spectral/wavelengths.h"

namespace farm {

class SpectralLight {
 public:
  // rgb's uplift at kWavelengthsPerPath wavelengths drawn from u in [0, 1): the hero from
  // u, its companions from u + k / kWavelengthsPerPath (mod 1).
  static SpectralLight Hero(const Rgb& rgb, double u);

  // rgb's uplift at one wavelength.
  static SpectralLight One(const Rgb& rgb, const MonochromePath& at);

  // The hero wavelength alone, carrying what it carried.
  SpectralLight HeroOnly() const;

  // Each wavelength's value times weight's uplift there, over `over` (Russian roulette's
  // survival probability, or 1).
  SpectralLight Times(const Rgb& weight, double over = 1) const;

  // Each wavelength's value over k.
  SpectralLight Over(double k) const;

  // The film's linear sRGB estimate of this light: the mean of each wavelength's.
  Rgb ToRgb() const;

  double hero_nm() const { return at_[0].lambda_nm; }
  int count() const { return count_; }

 private:
  std::array<MonochromePath, kWavelengthsPerPath> at_{};
  std::array<double, kWavelengthsPerPath> value_{};
  int count_ = 0;
};

}  // namespace farm
