#pragma once

// RGB reflectances and emitters as smooth spectra, by Smits' method ("An RGB-to-Spectrum
// Conversion for Reflectances", JGT 4(4), 1999): a colour is white plus the most of one
// secondary (cyan, magenta or yellow) plus the most of one primary, each a fixed basis
// spectrum. Smits' ten 34 nm bins are resampled to 10 nm bins and each basis spectrum is
// then fitted, once, to the film's own response (colour_matching.h: FilmResponse): the
// spectrum within [0, 1] whose film colour is nearest to the basis colour. The film is
// linear, so a colour comes back from the film as its basis spectra do: greys exactly, and
// saturated colours as nearly as a spectrum within [0, 1] allows (uplift_test.cpp states
// how far). Chosen over Jakob and Hanika's parametric model (2019) because it needs a
// table of 70 numbers rather than a precomputed 3D coefficient grid, maps white to a flat
// spectrum (so the spectral white furnace stays white), and stays within [0, 1] for
// reflectances in [0, 1].

#include <array>

#include "math/rgb.h"

namespace farm {

class SmitsSpectrum {
 public:
  // The spectrum's values in 47 bins of 10 nm over 360-830 nm.
  using Bins = std::array<double, 47>;

  explicit SmitsSpectrum(const Rgb& rgb);

  // The spectrum at a wavelength in nm; outside 360-830 nm its end bins continue.
  double At(double lambda_nm) const;

 private:
  Bins bins_{};
};

}  // namespace farm
