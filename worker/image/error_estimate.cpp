#include "image/error_estimate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "image/image_error.h"

namespace farm {
namespace {

// The two-sided 95% point of the standard normal.
constexpr double kInterval95 = 1.959963984540054;

// digamma and trigamma for x > 0: the recurrences up to x >= 8, then their asymptotic
// series (the terms left out are below 1e-10 there).
double Digamma(double x) {
  double shift = 0;
  for (; x < 8; x += 1) shift -= 1 / x;
  const double i2 = 1 / (x * x);
  return shift + std::log(x) - 0.5 / x - i2 * (1.0 / 12 - i2 * (1.0 / 120 - i2 * (1.0 / 252)));
}

double Trigamma(double x) {
  double shift = 0;
  for (; x < 8; x += 1) shift += 1 / (x * x);
  const double i = 1 / x, i2 = i * i;
  return shift + i + 0.5 * i2 + i * i2 * (1.0 / 6 - i2 * (1.0 / 30 - i2 * (1.0 / 42)));
}

// E[log(X / nu)] and Var[log X] for X a chi-square of nu degrees of freedom.
double LogChiSquareMean(double nu) { return Digamma(nu / 2) + std::log(2 / nu); }
double LogChiSquareVariance(double nu) { return Trigamma(nu / 2); }

// Where the bias layer's channels are among the sums', or empty without one.
std::vector<std::size_t> BiasSums(const Accumulation& a) {
  if (a.squares.channels().size() != 4) return {};
  std::vector<std::size_t> at;
  const std::vector<std::string>& names = a.sums.channels();
  for (const std::string& name : BiasChannels())
    at.push_back(std::size_t(std::find(names.begin(), names.end(), name) - names.begin()));
  return at;
}

// The degrees of freedom of a whole round's squared error as its rounds show them: 2 mean^2
// / variance of the D_r (Accumulation::deviations), at least 1; infinite before there are
// three rounds (two D_r), or when they do not vary.
double DeviationDegrees(const Accumulation& a) {
  const double n = a.rounds - 1;
  if (n < 2) return std::numeric_limits<double>::infinity();
  const double mean = a.deviations / n;
  const double variance = (a.deviation_squares - a.deviations * mean) / (n - 1);
  if (!(variance > 0)) return std::numeric_limits<double>::infinity();
  return std::max(1.0, 2 * mean * mean / variance);
}

}  // namespace

double RoundSpread(double sum, double squares, double weight, int rounds) {
  return std::max(0.0, (squares - sum * sum / weight) / double(rounds - 1));
}

ErrorEstimate EstimateError(const Accumulation& a) {
  if (a.rounds < 2) throw ImageError("an error estimate needs two rounds, the accumulation holds " +
                                     std::to_string(a.rounds));
  const PixelRect& whole = a.weights.rect();
  const std::size_t channels = a.sums.channels().size(), squared = a.squares.channels().size();
  const std::vector<std::size_t> bias_at = BiasSums(a);
  const std::span<const float> sums = a.sums.data(), squares = a.squares.data(), weights = a.weights.data();
  const int blocks_wide = (whole.width + 1) / 2;
  std::vector<double> blocks(std::size_t(blocks_wide) * std::size_t((whole.height + 1) / 2));
  double noise = 0, bias = 0;
  for (int y = 0; y < whole.height; ++y) {
    for (int x = 0; x < whole.width; ++x) {
      const std::size_t p = std::size_t(y) * std::size_t(whole.width) + std::size_t(x);
      const double w = weights[p];
      double pixel_noise = 0, pixel_bias = 0;
      for (std::size_t c = 0; c < 3; ++c)  // the beauty is channels 0..2 of sums and squares
        pixel_noise += RoundSpread(sums[p * channels + c], squares[p * squared + c], w, a.rounds) / w;
      if (!bias_at.empty()) {
        // B^2 less B's variance, summed over R, G, B: the squares are summed over them too.
        double d2 = 0;
        for (std::size_t c : bias_at) d2 += double(sums[p * channels + c]) * sums[p * channels + c];
        pixel_bias = d2 / (w * w) - std::max(0.0, (squares[p * squared + 3] - d2 / w) / (a.rounds - 1)) / w;
      }
      noise += pixel_noise;
      bias += pixel_bias;
      blocks[std::size_t(y / 2) * std::size_t(blocks_wide) + std::size_t(x / 2)] += pixel_noise + pixel_bias;
    }
  }
  const double values = 3.0 * double(weights.size());
  ErrorEstimate e;
  e.noise = std::sqrt(noise / values);
  e.bias = std::sqrt(std::max(0.0, bias / values));
  const double mse = e.noise * e.noise + e.bias * e.bias;
  e.rmse = std::sqrt(mse);
  double total = 0, total_squared = 0;
  for (double t : blocks) {
    t = std::max(0.0, t);
    total += t;
    total_squared += t * t;
  }
  if (!(total > 0) || !(mse > 0)) {
    e.low = e.high = e.rmse;
    return e;
  }
  const double actual_nu = std::min(total * total / total_squared, DeviationDegrees(a));
  const double estimate_nu = actual_nu * double(a.rounds - 1);
  const double mean = LogChiSquareMean(actual_nu) - LogChiSquareMean(estimate_nu);
  const double spread = kInterval95 * std::sqrt(LogChiSquareVariance(actual_nu) + LogChiSquareVariance(estimate_nu));
  e.low = std::sqrt(mse * std::exp(mean - spread));
  e.high = std::sqrt(mse * std::exp(mean + spread));
  return e;
}

}  // namespace farm
