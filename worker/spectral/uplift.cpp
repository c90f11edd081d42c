#include "spectral/uplift.h"

#include <algorithm>

#include "spectral/colour_matching.h"

namespace farm {
namespace {

using SmitsBins = std::array<double, 10>;
using Bins = SmitsSpectrum::Bins;

// Smits' basis spectra (his table 1), bins of 34 nm from 380 nm; the end bins continue to
// the ends of the visible range.
constexpr SmitsBins kSmitsWhite = {1.0000, 1.0000, 0.9999, 0.9993, 0.9992, 0.9998, 1.0000, 1.0000, 1.0000, 1.0000};
constexpr SmitsBins kSmitsCyan = {0.9710, 0.9426, 1.0007, 1.0007, 1.0007, 1.0007, 0.1564, 0.0000, 0.0000, 0.0000};
constexpr SmitsBins kSmitsMagenta = {1.0000, 1.0000, 0.9685, 0.2229, 0.0000, 0.0458, 0.8369, 1.0000, 1.0000, 0.9959};
constexpr SmitsBins kSmitsYellow = {0.0001, 0.0000, 0.1088, 0.6651, 1.0000, 1.0000, 0.9996, 0.9586, 0.9685, 0.9840};
constexpr SmitsBins kSmitsRed = {0.1012, 0.0515, 0.0000, 0.0000, 0.0000, 0.0000, 0.8325, 1.0149, 1.0149, 1.0149};
constexpr SmitsBins kSmitsGreen = {0.0000, 0.0000, 0.0273, 0.7937, 1.0000, 0.9418, 0.1719, 0.0000, 0.0000, 0.0025};
constexpr SmitsBins kSmitsBlue = {1.0000, 1.0000, 0.8916, 0.3323, 0.0000, 0.0000, 0.0003, 0.0369, 0.0483, 0.0496};

// Smits' bin of a wavelength: 34 nm from 380 nm, the end bins continued.
int SmitsBinOf(double lambda_nm) { return static_cast<int>(std::clamp((lambda_nm - 380) / 34, 0.0, 9.0)); }

// The uplift's own bins: 10 nm over the visible range, fine enough for the film to see a
// colour exactly (Smits' 34 nm bins straddle the film's channel responses).
constexpr double kBinWidth = (kLambdaMax - kLambdaMin) / std::tuple_size_v<Bins>;

int BinOf(double lambda_nm) {
  const double last = std::tuple_size_v<Bins> - 1;
  return static_cast<int>(std::clamp((lambda_nm - kLambdaMin) / kBinWidth, 0.0, last));
}

// A Smits basis spectrum in the uplift's bins (each the Smits bin of its centre).
Bins Resampled(const SmitsBins& smits) {
  Bins out{};
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = smits[SmitsBinOf(kLambdaMin + (double(i) + 0.5) * kBinWidth)];
  return out;
}

// The film's colour of each bin at 1 (FilmResponse over the wavelengths it covers): the
// film's colour of a spectrum is the sum of its bins' values times these.
using BinColours = std::array<Bins, 3>;

BinColours FilmColoursOfBins() {
  BinColours a{};
  for (int i = 0; i <= kFilmSteps; ++i) {
    const double lambda = kLambdaMin + kFilmStep * i;
    const double w = ((i == 0 || i == kFilmSteps) ? 0.5 : 1.0) * kFilmStep;
    const Rgb r = FilmResponse(lambda);
    const int bin = BinOf(lambda);
    a[0][bin] += w * r.r;
    a[1][bin] += w * r.g;
    a[2][bin] += w * r.b;
  }
  return a;
}

// The basis spectrum moved to the spectrum within [0, 1] whose film colour is nearest to
// `colour` (and, among those, nearest to the basis: a small weight on the change keeps
// Smits' smooth shape where the film does not care): min |A x - colour|^2 + mu |x - b|^2
// over 0 <= x <= 1, by projected gradient descent, computed once. Within [0, 1] because a
// reflectance must not reflect more of a wavelength than it receives; the price is that
// the film cannot see some saturated colours exactly (FilmResponse's narrow red: the
// round trip test says how far).
Bins ForTheFilm(const SmitsBins& smits, const std::array<double, 3>& colour, const BinColours& a) {
  const Bins b = Resampled(smits);
  constexpr double kMu = 1e-4;
  constexpr int kIterations = 20000;
  constexpr std::size_t x_size = std::tuple_size_v<Bins>;
  // The gradient's Lipschitz constant: twice the largest eigenvalue of AᵀA + mu, bounded by
  // its trace.
  double trace = 0;
  for (int c = 0; c < 3; ++c)
    for (std::size_t i = 0; i < x_size; ++i) trace += a[c][i] * a[c][i];
  const double step = 1 / (2 * (trace + kMu));
  Bins x = b;
  for (int it = 0; it < kIterations; ++it) {
    std::array<double, 3> miss{};
    for (int c = 0; c < 3; ++c) {
      miss[c] = -colour[c];
      for (std::size_t i = 0; i < x_size; ++i) miss[c] += a[c][i] * x[i];
    }
    for (std::size_t i = 0; i < x_size; ++i) {
      double gradient = 2 * kMu * (x[i] - b[i]);
      for (int c = 0; c < 3; ++c) gradient += 2 * a[c][i] * miss[c];
      x[i] = std::clamp(x[i] - step * gradient, 0.0, 1.0);
    }
  }
  return x;
}

// Smits' seven basis spectra, each moved so that the film sees its colour as nearly as a
// spectrum within [0, 1] can. The uplift is a sum of basis spectra weighted by differences
// of the colour's channels, and the film is linear, so every colour comes back from the
// film as its basis spectra do.
struct Basis {
  Bins white, cyan, magenta, yellow, red, green, blue;
};

const Basis& BasisOnce() {
  static const Basis basis = [] {
    const BinColours a = FilmColoursOfBins();
    return Basis{ForTheFilm(kSmitsWhite, {1, 1, 1}, a),   ForTheFilm(kSmitsCyan, {0, 1, 1}, a),
                 ForTheFilm(kSmitsMagenta, {1, 0, 1}, a), ForTheFilm(kSmitsYellow, {1, 1, 0}, a),
                 ForTheFilm(kSmitsRed, {1, 0, 0}, a),     ForTheFilm(kSmitsGreen, {0, 1, 0}, a),
                 ForTheFilm(kSmitsBlue, {0, 0, 1}, a)};
  }();
  return basis;
}

void Add(Bins& to, const Bins& basis, double weight) {
  for (size_t i = 0; i < to.size(); ++i) to[i] += weight * basis[i];
}

}  // namespace

SmitsSpectrum::SmitsSpectrum(const Rgb& c) {
  const double r = c.r, g = c.g, b = c.b;
  // The smallest channel is white; the middle one less it is the secondary made of the two
  // largest channels; the rest of the largest is that channel's primary.
  const double lo = std::min({r, g, b});
  const Basis& k = BasisOnce();
  Add(bins_, k.white, lo);
  if (r == lo) {
    const double mid = std::min(g, b);
    Add(bins_, k.cyan, mid - lo);
    Add(bins_, g > b ? k.green : k.blue, std::max(g, b) - mid);
  } else if (g == lo) {
    const double mid = std::min(r, b);
    Add(bins_, k.magenta, mid - lo);
    Add(bins_, r > b ? k.red : k.blue, std::max(r, b) - mid);
  } else {
    const double mid = std::min(r, g);
    Add(bins_, k.yellow, mid - lo);
    Add(bins_, r > g ? k.red : k.green, std::max(r, g) - mid);
  }
}

double SmitsSpectrum::At(double lambda_nm) const { return bins_[static_cast<size_t>(BinOf(lambda_nm))]; }

}  // namespace farm
