#pragma once

// A path made monochromatic by a dispersive interface (a prism splitting white light): from
// there on it carries light at one wavelength λ as a number, drawn over the visible range
// where the film's channels see light (Pdf), and says what that is in the film's linear
// sRGB.
//
// The conversion is the film's response (colour_matching.h: FilmResponse, sRGB matching
// functions clipped at zero), the same for photons and camera paths, so that a caustic
// seen directly and through photons is alike.

#include "math/rgb.h"

namespace farm {

struct MonochromePath {
  double lambda_nm = 0;

  // The path at a wavelength drawn from u in [0, 1) with density Pdf: in proportion to
  // the sum of the three matching functions below, each over its integral (every channel
  // gets its share of the samples, and none goes where no channel sees light).
  static MonochromePath Sample(double u);

  // The density, per nm, Sample draws lambda_nm with.
  double Pdf() const;

  // The linear sRGB estimate of light of `value` at lambda_nm: the film's response at λ
  // times value, over the density λ was drawn with. Over many paths
  // carrying the uplift of an RGB colour, its mean is that colour (up to the uplift's
  // round trip and the clipping).
  Rgb ToRgb(double value) const;

  // The uplift of an RGB colour (a photon's power, a surface's reflectance) at lambda_nm.
  double ValueOf(const Rgb& rgb) const;
};

}  // namespace farm
