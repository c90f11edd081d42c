#include "image/sample_allocation.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace farm {
namespace {

// An error estimate of exactly 0 (two rounds that happened to agree, a black background) is
// raised to this share of the mean, so that no pixel counts as exact and lambda is bounded.
constexpr double kSigmaFloor = 1e-3;

}  // namespace

std::vector<std::uint32_t> AllocateSamples(std::span<const double> sigma, std::span<const double> taken,
                                           const AllocationBudget& budget) {
  if (sigma.size() != taken.size()) throw std::invalid_argument("AllocateSamples: sigma and taken differ in length");
  if (budget.min < 1 || budget.max < budget.min) throw std::invalid_argument("AllocateSamples: need 1 <= min <= max");
  const std::size_t pixels = sigma.size();
  if (pixels == 0) return {};
  const double lo_total = double(budget.min) * double(pixels), hi_total = double(budget.max) * double(pixels);
  const double total = std::clamp(double(budget.total), lo_total, hi_total);

  double mean = 0;
  for (double s : sigma) mean += s;
  mean /= double(pixels);
  const double floor = mean > 0 ? kSigmaFloor * mean : 1.0;
  std::vector<double> s(pixels);
  double lambda_hi = 0;
  for (std::size_t p = 0; p < pixels; ++p) {
    s[p] = std::max(sigma[p], floor);
    lambda_hi = std::max(lambda_hi, (double(budget.max) + taken[p]) / s[p]);
  }
  const auto counts_at = [&](double lambda, std::vector<double>* out) {
    double sum = 0;
    for (std::size_t p = 0; p < pixels; ++p) {
      const double n = std::clamp(lambda * s[p] - taken[p], double(budget.min), double(budget.max));
      if (out) (*out)[p] = n;
      sum += n;
    }
    return sum;
  };
  // The counts grow with lambda: bisect for the largest lambda whose counts fit the total.
  double lo = 0, hi = lambda_hi;
  for (int i = 0; i < 100 && hi - lo > 0; ++i) {
    const double mid = 0.5 * (lo + hi);
    (counts_at(mid, nullptr) <= total ? lo : hi) = mid;
  }
  std::vector<double> real(pixels);
  counts_at(lo, &real);

  std::vector<std::uint32_t> out(pixels);
  double assigned = 0;
  for (std::size_t p = 0; p < pixels; ++p) {
    out[p] = std::uint32_t(std::floor(real[p]));
    assigned += out[p];
  }
  // What the floors left of the total goes one sample each to the largest remainders.
  std::vector<std::size_t> order(pixels);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return real[a] - std::floor(real[a]) > real[b] - std::floor(real[b]);
  });
  auto left = std::uint64_t(std::llround(total - assigned));
  for (std::size_t i = 0; left > 0 && i < pixels; ++i) {
    std::uint32_t& n = out[order[i]];
    if (n < budget.max) {
      ++n;
      --left;
    }
  }
  return out;
}

}  // namespace farm
