#pragma once

// For the tests: a spectrum's colour, the linear sRGB of its XYZ, and colours compared.

#include <gtest/gtest.h>

#include <functional>

#include "spectral/colour_matching.h"

namespace farm {

// The linear sRGB of a spectrum: its XYZ by the midpoint rule over n intervals of the
// visible range, with Y = 1 for the spectrum that is 1 everywhere.
inline Rgb SrgbOf(const std::function<double(double)>& spectrum, int n = 4096) {
  const double step = (kLambdaMax - kLambdaMin) / n;
  const double scale = step / YIntegral();
  Xyz sum;
  for (int k = 0; k < n; ++k) {
    const double lambda = kLambdaMin + (k + 0.5) * step;
    const Xyz m = ColourMatching(lambda);
    const double v = spectrum(lambda);
    sum.x += v * m.x * scale;
    sum.y += v * m.y * scale;
    sum.z += v * m.z * scale;
  }
  return XyzToLinearSrgb(sum);
}

// The mean and variance of each channel over the colours added.
class ChannelSpread {
 public:
  void Add(const Rgb& c) {
    const double v[3] = {c.r, c.g, c.b};
    for (int k = 0; k < 3; ++k) sum_[k] += v[k], sum2_[k] += v[k] * v[k];
    ++n_;
  }
  double Mean(int channel) const { return sum_[channel] / n_; }
  double Variance(int channel) const { return sum2_[channel] / n_ - Mean(channel) * Mean(channel); }

 private:
  double sum_[3] = {0, 0, 0}, sum2_[3] = {0, 0, 0};
  int n_ = 0;
};

// Each channel of got within `within` of want's.
inline void ExpectColourNear(const Rgb& got, const Rgb& want, float within) {
  EXPECT_NEAR(got.r, want.r, within) << ToString(got) << " against " << ToString(want);
  EXPECT_NEAR(got.g, want.g, within) << ToString(got) << " against " << ToString(want);
  EXPECT_NEAR(got.b, want.b, within) << ToString(got) << " against " << ToString(want);
}

}  // namespace farm
