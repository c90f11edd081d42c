#include "image/error_estimate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "image/image_error.h"

namespace farm {
namespace {

// A round of synthetic pixels: the beauty's R, G, B and the bias layer's, row-major.
struct SyntheticRound {
  std::vector<double> beauty, bias;
};

// Rounds folded as the round accumulator folds them (weight 1 each), in double then
// rounded to float like the accumulation file.
class SyntheticAccumulation {
 public:
  SyntheticAccumulation(int width, int height, bool bias_layer)
      : width_(width), height_(height), bias_layer_(bias_layer),
        sums_(std::size_t(width * height) * 6), squares_(std::size_t(width * height) * 6) {}

  void Add(const SyntheticRound& r) {
    if (rounds_ > 0) {  // D_r of Accumulation::deviations, every weight 1
      double d = 0;
      for (std::size_t i = 0; i < r.beauty.size(); ++i) {
        const double off = r.beauty[i] - sums_[(i / 3) * 6 + i % 3] / rounds_;
        d += off * off * rounds_ / (rounds_ + 1);
      }
      deviations_ += d;
      deviation_squares_ += d * d;
    }
    ++rounds_;
    for (std::size_t i = 0; i < r.beauty.size(); ++i) {
      const std::size_t p = i / 3, c = i % 3;
      sums_[p * 6 + c] += r.beauty[i];
      squares_[p * 6 + c] += r.beauty[i] * r.beauty[i];
      if (!bias_layer_) continue;
      sums_[p * 6 + 3 + c] += r.bias[i];
      squares_[p * 6 + 3 + c] += r.bias[i] * r.bias[i];
    }
  }

  Accumulation Get() const {
    const PixelRect whole{0, 0, width_, height_};
    std::vector<std::string> channels = {"R", "G", "B"};
    if (bias_layer_) channels.insert(channels.end(), {"bias.R", "bias.G", "bias.B"});
    Accumulation a{rounds_, Image(whole, channels), Image(whole, SquaredChannels(channels)), Image(whole, {"W"}),
                   deviations_, deviation_squares_};
    const std::size_t n = channels.size(), squared = a.squares.channels().size();
    for (std::size_t p = 0; p < std::size_t(width_ * height_); ++p) {
      for (std::size_t c = 0; c < n; ++c) a.sums.data()[p * n + c] = float(sums_[p * 6 + c]);
      for (std::size_t c = 0; c < 3; ++c) a.squares.data()[p * squared + c] = float(squares_[p * 6 + c]);
      if (bias_layer_)  // the bias layer's squares, summed over R, G, B
        a.squares.data()[p * squared + 3] = float(squares_[p * 6 + 3] + squares_[p * 6 + 4] + squares_[p * 6 + 5]);
      a.weights.data()[p] = float(rounds_);
    }
    return a;
  }

 private:
  int width_, height_;
  bool bias_layer_;
  int rounds_ = 0;
  std::vector<double> sums_, squares_;
  double deviations_ = 0, deviation_squares_ = 0;
};

// Progressive photon mapping's kernel area in round r (RoundSettings: the radius scale
// squared at alpha 0.7), which a kernel's leading bias follows.
double KernelArea(int round) {
  double area = 1;
  for (int i = 1; i < round; ++i) area *= (i + 0.7) / (i + 1);
  return area;
}

constexpr int kWidth = 64, kHeight = 48;

// Pixel p's truth, its rounds' noise sigma and its bias in round 1, channel c.
double Truth(std::size_t i) { return 0.2 + 0.001 * double(i % 997); }
double Sigma(std::size_t i) { return 0.04 * (1.0 + double((i / 3) % kWidth) / kWidth); }
double Bias(std::size_t i) {
  const double x = double((i / 3) % kWidth), y = double((i / 3) / kWidth);
  return 0.03 * std::sin(x / 5) * std::cos(y / 7) * (1 + 0.2 * double(i % 3));
}

// Rounds with independent Gaussian noise of Sigma and the kernel bias Bias * KernelArea; the
// bias layer holds that bias plus noise of noise_d * Sigma (the companion's own).
SyntheticRound Round(int r, double noise_d, std::mt19937_64& rng) {
  std::normal_distribution<double> gauss(0, 1);
  SyntheticRound round;
  for (std::size_t i = 0; i < std::size_t(kWidth * kHeight * 3); ++i) {
    const double b = Bias(i) * KernelArea(r);
    round.beauty.push_back(Truth(i) + b + Sigma(i) * gauss(rng));
    round.bias.push_back(b + noise_d * Sigma(i) * gauss(rng));
  }
  return round;
}

TEST(ErrorEstimate, FindsBothTheNoiseAndTheBiasOfSyntheticRounds) {
  std::mt19937_64 rng(7);
  SyntheticAccumulation acc(kWidth, kHeight, true);
  std::vector<double> mean(std::size_t(kWidth * kHeight * 3));
  double bias_sum = 0;  // sum over rounds of KernelArea: the mean bias is Bias * bias_sum / R
  for (int r = 1; r <= 16; ++r) {
    const SyntheticRound round = Round(r, 0.3, rng);
    acc.Add(round);
    bias_sum += KernelArea(r);
    for (std::size_t i = 0; i < mean.size(); ++i) mean[i] += (round.beauty[i] - mean[i]) / r;
    if (r == 1) continue;
    double variance = 0, bias2 = 0, actual = 0;
    for (std::size_t i = 0; i < mean.size(); ++i) {
      variance += Sigma(i) * Sigma(i) / r;
      bias2 += std::pow(Bias(i) * bias_sum / r, 2);
      actual += std::pow(mean[i] - Truth(i), 2);
    }
    const double n = double(mean.size());
    const ErrorEstimate e = EstimateError(acc.Get());
    EXPECT_NEAR(e.noise, std::sqrt(variance / n), 0.05 * std::sqrt(variance / n)) << "round " << r;
    EXPECT_NEAR(e.bias, std::sqrt(bias2 / n), 0.10 * std::sqrt(bias2 / n)) << "round " << r;
    EXPECT_NEAR(e.rmse, std::sqrt((variance + bias2) / n), 0.05 * std::sqrt((variance + bias2) / n)) << "round " << r;
    EXPECT_DOUBLE_EQ(e.rmse, std::hypot(e.noise, e.bias));
    EXPECT_LE(e.low, std::sqrt(actual / n)) << "round " << r;
    EXPECT_GE(e.high, std::sqrt(actual / n)) << "round " << r;
  }
}

TEST(ErrorEstimate, TheNoiseOfTheBiasLayerIsNotTakenForBias) {
  // No bias at all, a very noisy bias layer: B^2 alone would claim a bias of about
  // 3 sigma / sqrt(R); less its own variance it is near 0.
  std::mt19937_64 rng(11);
  SyntheticAccumulation acc(kWidth, kHeight, true);
  for (int r = 1; r <= 8; ++r) {
    SyntheticRound round = Round(r, 3.0, rng);
    for (std::size_t i = 0; i < round.beauty.size(); ++i) {
      const double b = Bias(i) * KernelArea(r);
      round.beauty[i] -= b;
      round.bias[i] -= b;
    }
    acc.Add(round);
  }
  const ErrorEstimate e = EstimateError(acc.Get());
  EXPECT_LT(e.bias, 0.2 * e.noise);
}

TEST(ErrorEstimate, WithoutABiasLayerOnlyTheSpreadCounts) {
  std::mt19937_64 rng(3);
  SyntheticAccumulation with(kWidth, kHeight, true), without(kWidth, kHeight, false);
  for (int r = 1; r <= 4; ++r) {
    const SyntheticRound round = Round(r, 0.3, rng);
    with.Add(round);
    without.Add(round);
  }
  const ErrorEstimate a = EstimateError(with.Get()), b = EstimateError(without.Get());
  EXPECT_EQ(b.bias, 0.0);
  EXPECT_EQ(b.noise, a.noise);
  EXPECT_EQ(b.rmse, b.noise);
  EXPECT_GT(a.bias, 0.0);
}

// How often the interval holds the actual RMSE of the mean of `rounds` synthetic rounds of
// noise only, over `trials` renders; heavy puts most of the error in 1% of the pixels (a
// light's rim), each of them noisier by a factor of 30.
double Coverage(int rounds, bool heavy, int trials, double* widest = nullptr) {
  constexpr int kSide = 32;
  std::mt19937_64 rng(rounds * 100 + heavy);
  std::normal_distribution<double> gauss(0, 1);
  int covered = 0;
  for (int t = 0; t < trials; ++t) {
    SyntheticAccumulation acc(kSide, kSide, false);
    std::vector<double> sums(kSide * kSide * 3);
    for (int r = 1; r <= rounds; ++r) {
      SyntheticRound round;
      for (std::size_t i = 0; i < sums.size(); ++i) {
        const double sigma = heavy && (i / 3) % 97 == 0 ? 1.5 : 0.05;
        round.beauty.push_back(sigma * gauss(rng));
        sums[i] += round.beauty.back();
      }
      acc.Add(round);
    }
    double actual = 0;
    for (double s : sums) actual += (s / rounds) * (s / rounds);
    actual = std::sqrt(actual / double(sums.size()));
    const ErrorEstimate e = EstimateError(acc.Get());
    covered += e.low <= actual && actual <= e.high;
    if (widest) *widest = std::max(*widest, e.high / e.low);
  }
  return double(covered) / trials;
}

TEST(ErrorEstimate, TheIntervalHoldsTheActualErrorAtLeastAtItsLevel) {
  // Pixels of a 2x2 block are taken as fully correlated, so for independent pixels the
  // interval is cautious: it should hold at least 95% of the time, heavy tails or not.
  for (const int rounds : {2, 3, 8}) {
    EXPECT_GE(Coverage(rounds, false, 200), 0.95) << rounds << " rounds";
    EXPECT_GE(Coverage(rounds, true, 200), 0.95) << rounds << " rounds, heavy";
  }
  // And it is not uselessly wide where every pixel is alike: 256 blocks of 32x32 pixels
  // give it about +-10%.
  double widest = 0;
  Coverage(8, false, 20, &widest);
  EXPECT_LT(widest, 1.25);
}

TEST(ErrorEstimate, NeedsTwoRounds) {
  SyntheticAccumulation acc(4, 4, true);
  acc.Add({std::vector<double>(48, 0.5), std::vector<double>(48, 0.0)});
  EXPECT_THROW(EstimateError(acc.Get()), ImageError);
}

}  // namespace
}  // namespace farm
