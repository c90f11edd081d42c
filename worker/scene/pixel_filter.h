#pragma once

// The pixel reconstruction filter of a scene's film (renderfarm.v1.PixelFilter,
// docs/pixel-filters.md), with its defaults applied: a separable weight
// f(dx) f(dy) over the offset of a camera sample from a pixel's centre. Each profile f is
// normalised to integrate to 1 over [-radius, radius] and is 0 outside, so a filter's
// weights over a uniform density of samples sum to 1 wherever its support lies inside the
// image.

#include <string>

namespace renderfarm::v1 {
class PixelFilter;
}

namespace farm {

enum class PixelFilterKind {
  kBox,       // constant
  kTent,      // linear to 0 at the radius
  kGaussian,  // exp(-x^2 / (2 sigma^2)) less its value at the radius
  kMitchell,  // Mitchell and Netravali's cubic, B = C = 1/3, stretched over the radius
};

class PixelFilter {
 public:
  // The box of radius 1/2: a pixel is the mean of its own samples.
  PixelFilter() = default;
  PixelFilter(PixelFilterKind kind, double radius, double sigma = 0);

  // Reads `filter`, which has passed contract::CheckRules; unset is the box of radius 1/2,
  // a field that is 0 takes its default.
  static PixelFilter FromProto(const renderfarm::v1::PixelFilter& filter);

  PixelFilterKind kind() const { return kind_; }
  double radius() const { return radius_; }

  // The normalised profile at x (|x| < radius, else 0; the box is half-open, [-r, r), so
  // that the box of radius 1/2 holds exactly the samples of its own pixel).
  double Profile(double x) const;
  // The weight of a sample at offset (dx, dy) from a pixel's centre.
  double Weight(double dx, double dy) const { return Profile(dx) * Profile(dy); }
  // The integral of Profile over [a, b] clipped to the support: exact for the box, the
  // tent and Mitchell's piecewise cubic, Simpson's rule (64 steps between knots) for the
  // Gaussian.
  double Integral(double a, double b) const;

  // Pixels about a pixel whose samples it weighs, on each side: a sample lies in
  // [q, q + 1) of its pixel q and counts for p when it is within the radius of p + 1/2.
  int margin() const;
  // Whether a pixel is exactly the mean of its own samples (the box of radius 1/2), so that
  // the tile renderer can take them without weights, as it did before filters.
  bool is_pixel_box() const { return kind_ == PixelFilterKind::kBox && radius_ == 0.5; }

  std::string ToString() const;

 private:
  PixelFilterKind kind_ = PixelFilterKind::kBox;
  double radius_ = 0.5;
  double sigma_ = 0;         // the Gaussian's
  double normaliser_ = 1.0;  // divides the unnormalised profile
};

}  // namespace farm
