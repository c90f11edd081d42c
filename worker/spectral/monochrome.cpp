#include "spectral/monochrome.h"

#include <algorithm>
#include <array>
#include <vector>

#include "spectral/colour_matching.h"
#include "spectral/uplift.h"
#include "spectral/wavelengths.h"

namespace farm {
namespace {

constexpr int kSteps = kFilmSteps;
constexpr double kStep = kFilmStep;

// The density wavelengths are drawn with: proportional to the sum of the film's three
// channel responses (each a matching function over its integral), so that every channel
// gets its share of the samples and none is spent where no channel sees light (the
// estimate of white is then 3 w_c(λ) in channel c, w the channels' shares at λ, instead of
// swinging from 0 to several times 1). Piecewise constant over the intervals, computed once.
struct Tables {
  std::vector<double> cdf;      // kSteps + 1 entries, 0 to 1
  std::vector<double> density;  // per nm, in each interval
};

const Tables& TablesOnce() {
  static const Tables tables = [] {
    Tables t;
    const auto share = [](double lambda) {
      const Rgb c = FilmResponse(lambda);
      return double(c.r) + double(c.g) + double(c.b);
    };
    t.cdf.assign(kSteps + 1, 0);
    t.density.assign(kSteps, 0);
    for (int i = 0; i < kSteps; ++i) {
      t.density[i] = (share(kLambdaMin + kStep * i) + share(kLambdaMin + kStep * (i + 1))) / 2;
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
  return FilmResponse(lambda_nm) * static_cast<float>(value / pdf);
}

double MonochromePath::ValueOf(const Rgb& rgb) const { return SmitsSpectrum(rgb).At(lambda_nm); }

}  // namespace farm
