#pragma once

// CIE 1931 2° colour matching, and the film's conversion of CIE XYZ to linear sRGB.
//
// The matching functions are Wyman, Sloan and Shirley's multi-lobe fit ("Simple Analytic
// Approximations to the CIE XYZ Color Matching Functions", JCGT 2(2), 2013): a few
// piecewise Gaussians, within a few percent of the tabulated functions, evaluated anywhere
// without a table.

#include "math/rgb.h"
#include "spectral/wavelengths.h"

namespace farm {

struct Xyz {
  double x = 0, y = 0, z = 0;
};

// x̄(λ), ȳ(λ), z̄(λ) at a wavelength in nm.
Xyz ColourMatching(double lambda_nm);

// ∫ȳ over [kLambdaMin, kLambdaMax]: an estimate of ∫ f(λ) x̄(λ) dλ divided by it is the XYZ
// of f with Y = 1 for the spectrum that is 1 everywhere.
double YIntegral();

// XYZ to linear sRGB (Rec. 709 primaries), with the equal-energy spectrum (1 everywhere)
// as white: reflectances and emitters uplift white to that spectrum (uplift.h), so the
// film adapts its white to sRGB's D65 by scaling XYZ (the simplest of the von Kries
// adaptations, exact for the white point itself) before the sRGB matrix.
Rgb XyzToLinearSrgb(const Xyz& xyz);

// The film's response to light at a wavelength in nm: the linear sRGB of the matching
// functions at λ with their negative parts (the spectral colours outside sRGB's gamut) set
// to 0, each channel over its integral over the visible range, so that the spectrum that is
// 1 everywhere is white (1, 1, 1). The film's colour of a spectrum S is ∫ S(λ) R(λ) dλ.
// Clipped because photons must stay non-negative (the snapshot stores their power as
// shared-exponent RGB); the price is spectral colours a little less saturated.
Rgb FilmResponse(double lambda_nm);

// FilmResponse's integration: the visible range in kFilmSteps intervals of kFilmStep nm
// (fine against the matching functions' smooth lobes), by the trapezoid rule.
inline constexpr int kFilmSteps = 940;
inline constexpr double kFilmStep = (kLambdaMax - kLambdaMin) / kFilmSteps;

}  // namespace farm
