#include "spectral/uplift.h"

#include <algorithm>

namespace farm {
namespace {

using Bins = std::array<double, 10>;

// Smits' basis spectra (his table 1), bins of 34 nm from 380 nm.
constexpr Bins kWhite = {1.0000, 1.0000, 0.9999, 0.9993, 0.9992, 0.9998, 1.0000, 1.0000, 1.0000, 1.0000};
constexpr Bins kCyan = {0.9710, 0.9426, 1.0007, 1.0007, 1.0007, 1.0007, 0.1564, 0.0000, 0.0000, 0.0000};
constexpr Bins kMagenta = {1.0000, 1.0000, 0.9685, 0.2229, 0.0000, 0.0458, 0.8369, 1.0000, 1.0000, 0.9959};
constexpr Bins kYellow = {0.0001, 0.0000, 0.1088, 0.6651, 1.0000, 1.0000, 0.9996, 0.9586, 0.9685, 0.9840};
constexpr Bins kRed = {0.1012, 0.0515, 0.0000, 0.0000, 0.0000, 0.0000, 0.8325, 1.0149, 1.0149, 1.0149};
constexpr Bins kGreen = {0.0000, 0.0000, 0.0273, 0.7937, 1.0000, 0.9418, 0.1719, 0.0000, 0.0000, 0.0025};
constexpr Bins kBlue = {1.0000, 1.0000, 0.8916, 0.3323, 0.0000, 0.0000, 0.0003, 0.0369, 0.0483, 0.0496};

constexpr double kFirst = 380, kLast = 720;

void Add(Bins& to, const Bins& basis, double weight) {
  for (size_t i = 0; i < to.size(); ++i) to[i] += weight * basis[i];
}

}  // namespace

SmitsSpectrum::SmitsSpectrum(const Rgb& c) {
  const double r = c.r, g = c.g, b = c.b;
  // The smallest channel is white; the middle one less it is the secondary made of the two
  // largest channels; the rest of the largest is that channel's primary.
  const double lo = std::min({r, g, b});
  Add(bins_, kWhite, lo);
  if (r == lo) {
    const double mid = std::min(g, b);
    Add(bins_, kCyan, mid - lo);
    Add(bins_, g > b ? kGreen : kBlue, std::max(g, b) - mid);
  } else if (g == lo) {
    const double mid = std::min(r, b);
    Add(bins_, kMagenta, mid - lo);
    Add(bins_, r > b ? kRed : kBlue, std::max(r, b) - mid);
  } else {
    const double mid = std::min(r, g);
    Add(bins_, kYellow, mid - lo);
    Add(bins_, r > g ? kRed : kGreen, std::max(r, g) - mid);
  }
}

double SmitsSpectrum::At(double lambda_nm) const {
  const double t = (lambda_nm - kFirst) / (kLast - kFirst) * bins_.size();
  const auto i = static_cast<long>(std::clamp(t, 0.0, static_cast<double>(bins_.size() - 1)));
  return bins_[static_cast<size_t>(i)];
}

}  // namespace farm
