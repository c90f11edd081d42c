#pragma once

// RGB reflectances and emitters as smooth spectra, by Smits' method ("An RGB-to-Spectrum
// Conversion for Reflectances", JGT 4(4), 1999): a colour is white plus the most of one
// secondary (cyan, magenta or yellow) plus the most of one primary, each a fixed smooth
// spectrum of ten bins over 380-720 nm. Chosen over Jakob and Hanika's parametric model
// (2019) because it needs a table of 70 numbers rather than a precomputed 3D coefficient
// grid, maps white to a flat spectrum (so the spectral white furnace stays white), and
// stays within [0, 1] for reflectances in [0, 1]; its price is a less exact round trip
// for saturated colours (uplift_test.cpp states how far).

#include <array>

#include "math/rgb.h"

namespace farm {

class SmitsSpectrum {
 public:
  explicit SmitsSpectrum(const Rgb& rgb);

  // The spectrum at a wavelength in nm; outside 380-720 nm its end bins continue.
  double At(double lambda_nm) const;

 private:
  std::array<double, 10> bins_{};
};

}  // namespace farm
