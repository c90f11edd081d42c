#include "spectral/monochrome.h"

#include <algorithm>
#include <array>
#include <vector>

#include "spectral/colour_matching.h"
#include "spectral/uplift.h"
#include "spectral/wavelengths.h"

namespace farm {
namespace {

constexpr double kRange = kLambdaMax - kLambdaMin;
// Intervals of 0.5 nm: fine against the matching functions' smooth lobes.
constexpr int kSteps = 940;
constexpr double kStep = kRange / kSteps;

Rgb ClippedSrgbMatching(double lambda) {
  const Rgb c = XyzToLinearSrgb(ColourMatching(lambda));
  return Rgb(std::max(0.0f, c.r), std::max(0.0f, c.g), std::max(0.0f, c.b));
}

// The clipped matching functions' integrals, and the density wavelengths are drawn with:
// proportional to the sum of the three functions each over its integral, so that every
// channel gets its share of the samples and none is spent where no channel sees light
// (the estimate of white is then 3 w_c(λ) in channel c, w the channels' shares at λ,
// instead of swinging from 0 to several times 1). Piecewise constant over the intervals,
// computed once.
struct Tables {
  std::array<double, 3> integral{};
  std::vector<double> cdf;      // kSteps + 1 entries, 0 to 1
  std::vector<double> density;  // per nm, in each interval
};

const Tables& TablesOnce() {
  static const Tables tables = [] {
    Tables t;
    std::vector<Rgb> at(kSteps + 1);
    for (int i = 0; i <= kSteps; ++i) {
      at[i] = ClippedSrgbMatching(kLambdaMin + kStep * i);
      const double w = (i == 0 || i == kSteps) ? 0.5 : 1.0;
      t.integral[0] += w * at[i].r * kStep;
      t.integral[1] += w * at[i].g * kStep;
      t.integral[2] += w * at[i].b * kStep;
    }
    const auto share = [&](const Rgb& c) { return c.r / t.integral[0] + c.g / t.integral[1] + c.b / t.integral[2]; };
    t.cdf.assign(kSteps + 1, 0);
    t.density.assign(kSteps, 0);
    for (int i = 0; i < kSteps; ++i) {
      t.density[i] = (share(at[i]) + share(at[i + 1])) / 2;
      t.cdf[i + 1] = t.cdf[i] + t.density[i] * kStep;
    }
    const double total = t.cdf[kSteps];
    for (double& c : t.cdf) c /= total;
    for (double& d : t.density) d /= total;
    return t;
  }();
  return tables;
}

}  // namespace

MonochromePath MonochromePath::Sample(double u) {
  const Tables& t = TablesOnce();
  // The interval whose cumulative range holds u (one with no density holds none), then
  // uniformly within it.
  const auto it = std::upper_bound(t.cdf.begin() + 1, t.cdf.end(), u);
  const int i = std::min<int>(static_cast<int>(it - t.cdf.begin()) - 1, kSteps - 1);
  const double within = (u - t.cdf[i]) / (t.cdf[i + 1] - t.cdf[i]);
  return MonochromePath{kLambdaMin + kStep * (i + std::clamp(within, 0.0, 1.0))};
}

double MonochromePath::Pdf() const {
  if (lambda_nm < kLambdaMin || lambda_nm > kLambdaMax) return 0;
  const int i = std::min(kSteps - 1, static_cast<int>((lambda_nm - kLambdaMin) / kStep));
  return TablesOnce().density[i];
}

Rgb MonochromePath::ToRgb(double value) const {
  const double pdf = Pdf();
  if (!(pdf > 0)) return Rgb();
  const Rgb c = ClippedSrgbMatching(lambda_nm);
  const std::array<double, 3>& integral = TablesOnce().integral;
  const double k = value / pdf;
  return Rgb(static_cast<float>(k * c.r / integral[0]), static_cast<float>(k * c.g / integral[1]),
             static_cast<float>(k * c.b / integral[2]));
}

double MonochromePath::ValueOf(const Rgb& rgb) const { return SmitsSpectrum(rgb).At(lambda_nm); }

}  // namespace farm
