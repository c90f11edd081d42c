#include "image/round_accumulator.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "image/accumulation_exr.h"
#include "image/error_estimate.h"
#include "image/image_error.h"
#include "image/reference_exr.h"
#include "image/sample_allocation.h"
#include "image/sample_map.h"
#include "image/stitch.h"

// How rounds combine. Round r renders the whole image with fresh, independent samples (and
// photons), so each pixel's round values x_1..x_R are independent estimates; the image is
// their mean. Sums are kept in float (accumulation_exr.h documents the file) and every sum
// is updated in double then rounded once per round, in pixel order: the bytes depend only
// on the rounds' pixels.
//
// Under adaptive sampling a pixel's rounds hold different numbers of samples, so each
// round's value x is weighed by w, its samples over samples_per_pixel (1 without adaptive
// sampling), and the image is sum(w x) / sum(w): every round's x is an unbiased estimate
// of the pixel (its samples are fresh, whatever their number), and the weighted mean is
// the one of least variance when a round's variance is that of its camera samples. The
// samples layer is summed, not averaged: samples per pixel over all rounds.
//
// The error estimate (image/error_estimate.h) is the RMSE the mean is expected to have:
// the spread between rounds for its noise and the bias layer for its bias; the weighted
// spread (sum(w x^2) - sum(w x)^2 / W) / (R - 1) estimates the variance of a round of
// weight 1 (W = sum(w); the unbiased s^2 when every w is 1), and that over W the mean's.

namespace farm {
namespace {

void CheckRoundValues(const Image& round) {
  const PixelRect& r = round.rect();
  for (int y = r.y; y < r.y_end(); ++y) {
    for (int x = r.x; x < r.x_end(); ++x) {
      const float* p = round.pixel(x, y);
      for (int c = 0; c < round.channel_count(); ++c) {
        if (std::isfinite(p[c])) continue;
        throw ImageError("tile channel " + round.channels()[c] + " at pixel (" +
                         std::to_string(x) + ", " + std::to_string(y) + ") is not finite");
      }
    }
  }
}

// Where channel kSamplesChannel is among channels, or -1.
int SamplesChannel(const std::vector<std::string>& channels) {
  const auto it = std::find(channels.begin(), channels.end(), kSamplesChannel);
  return it == channels.end() ? -1 : int(it - channels.begin());
}

// Each pixel's weight in the round: its allocated samples over samples_per_pixel, or none
// (every pixel 1) without a sample map.
std::vector<double> RoundWeights(const std::optional<SampleMap>& map, std::uint32_t samples_per_pixel) {
  std::vector<double> w;
  if (!map) return w;
  w.reserve(map->counts.size());
  for (std::uint32_t n : map->counts) w.push_back(double(n) / double(samples_per_pixel));
  return w;
}

Accumulation Fold(std::optional<Accumulation> previous, const Image& round, std::span<const double> weights) {
  const PixelRect& whole = round.rect();
  const std::vector<std::string> squared = SquaredChannels(round.channels());
  Accumulation a = previous ? std::move(*previous)
                            : Accumulation{0, Image(whole, round.channels()), Image(whole, squared),
                                           Image(whole, {"W"}), 0, 0};
  ++a.rounds;
  const int samples = SamplesChannel(round.channels());
  std::vector<std::size_t> bias_at;  // where the bias layer is in the round's channels
  if (squared.size() > 3)
    for (const std::string& name : BiasChannels())
      bias_at.push_back(std::size_t(std::find(round.channels().begin(), round.channels().end(), name) -
                                    round.channels().begin()));
  const std::span<const float> x = round.data();
  const std::span<float> sums = a.sums.data();
  const std::span<float> squares = a.squares.data();
  const std::span<float> total = a.weights.data();
  const std::size_t channels = round.channels().size(), nsquared = squared.size();
  double deviation = 0;  // D_r (Accumulation::deviations), from the sums before this round's
  for (std::size_t p = 0; p < total.size(); ++p) {
    const double w = weights.empty() ? 1.0 : weights[p];
    if (a.rounds > 1) {
      const double before = total[p];
      for (std::size_t c = 0; c < 3; ++c) {
        const double d = x[p * channels + c] - double(sums[p * channels + c]) / before;
        deviation += d * d * w * before / (before + w);
      }
    }
    for (std::size_t c = 0; c < channels; ++c) {
      const double v = x[p * channels + c];
      float& sum = sums[p * channels + c];
      sum = float(double(sum) + (int(c) == samples ? v : w * v));
    }
    for (std::size_t c = 0; c < 3; ++c) {  // the beauty is channels 0..2 (CompositeChannels)
      const double v = x[p * channels + c];
      float& square = squares[p * nsquared + c];
      square = float(double(square) + w * v * v);
    }
    if (!bias_at.empty()) {
      double d2 = 0;
      for (std::size_t c : bias_at) d2 += double(x[p * channels + c]) * x[p * channels + c];
      float& square = squares[p * nsquared + 3];
      square = float(double(square) + w * d2);
    }
    total[p] = float(double(total[p]) + w);
  }
  a.deviations += deviation;
  a.deviation_squares += deviation * deviation;
  return a;
}

Image MeanOf(const Accumulation& a) {
  Image mean(a.sums.rect(), a.sums.channels());
  const int samples = SamplesChannel(a.sums.channels());
  const std::size_t channels = a.sums.channels().size();
  const std::span<const float> sums = a.sums.data();
  const std::span<const float> weights = a.weights.data();
  const std::span<float> out = mean.data();
  for (std::size_t i = 0; i < sums.size(); ++i) {
    const bool summed = int(i % channels) == samples;
    out[i] = summed ? sums[i] : float(double(sums[i]) / double(weights[i / channels]));
  }
  return mean;
}

// The spread between rounds of pixel p's beauty channel c: the variance of a round of
// weight 1 (samples_per_pixel samples). Needs two rounds.
double RoundVariance(const Accumulation& a, std::size_t p, std::size_t c) {
  return RoundSpread(a.sums.data()[p * a.sums.channels().size() + c],
                     a.squares.data()[p * a.squares.channels().size() + c], a.weights.data()[p], a.rounds);
}

// The squared error from noise each pixel's mean is expected to have: its rounds' variance
// over its weight, averaged over R, G, B (what more samples reduce, and so what adaptive
// sampling ranks pixels by).
std::vector<double> SquaredErrors(const Accumulation& a) {
  std::vector<double> e(a.weights.data().size());
  for (std::size_t p = 0; p < e.size(); ++p) {
    double v = 0;
    for (std::size_t c = 0; c < 3; ++c) v += RoundVariance(a, p, c);
    e[p] = v / 3.0 / double(a.weights.data()[p]);
  }
  return e;
}

// The next round's samples (image/sample_allocation.h): the variance of one sample of
// each pixel, from its rounds' spread smoothed over its 3x3 neighbourhood (two rounds give
// a single pixel a very rough estimate; its neighbours mostly see the same light), the
// samples it has been weighed as so far, and as many samples in all as this round drew.
SampleMap NextSamples(const Accumulation& a, const Image& round, std::uint32_t samples_per_pixel,
                      std::uint32_t max_samples) {
  const PixelRect& whole = a.weights.rect();
  const std::size_t pixels = a.weights.data().size();
  std::vector<double> variance(pixels);
  for (std::size_t p = 0; p < pixels; ++p) {
    for (std::size_t c = 0; c < 3; ++c) variance[p] += RoundVariance(a, p, c) / 3.0;
  }
  std::vector<double> sigma(pixels), taken(pixels);
  for (int y = 0; y < whole.height; ++y) {
    for (int x = 0; x < whole.width; ++x) {
      double sum = 0;
      int n = 0;
      for (int qy = std::max(0, y - 1); qy <= std::min(whole.height - 1, y + 1); ++qy) {
        for (int qx = std::max(0, x - 1); qx <= std::min(whole.width - 1, x + 1); ++qx, ++n) {
          sum += variance[std::size_t(qy) * std::size_t(whole.width) + std::size_t(qx)];
        }
      }
      const std::size_t p = std::size_t(y) * std::size_t(whole.width) + std::size_t(x);
      sigma[p] = std::sqrt(sum / n * samples_per_pixel);  // a round of weight 1 is spp samples
      taken[p] = double(a.weights.data()[p]) * samples_per_pixel;
    }
  }
  const int samples = SamplesChannel(round.channels());
  double drawn = 0;
  for (std::size_t p = 0; p < pixels; ++p) drawn += round.data()[p * round.channels().size() + std::size_t(samples)];
  const AllocationBudget budget{std::uint64_t(std::llround(drawn)), 1, max_samples};
  return SampleMap{{whole.width, whole.height}, AllocateSamples(sigma, taken, budget)};
}

// Where the samples so far went: their range over pixels and, from round 2, the share of
// them in the tenth of the pixels with the largest expected error (ties to the lower
// index).
SampleSpread SpreadOf(const Accumulation& a, const std::vector<double>& squared_errors) {
  const int samples = SamplesChannel(a.sums.channels());
  const std::size_t channels = a.sums.channels().size(), pixels = a.weights.data().size();
  std::vector<double> n(pixels);
  for (std::size_t p = 0; p < pixels; ++p) n[p] = a.sums.data()[p * channels + std::size_t(samples)];
  SampleSpread s{kSamplesChannel, std::uint64_t(*std::min_element(n.begin(), n.end())),
                 std::uint64_t(*std::max_element(n.begin(), n.end())), 0, std::nullopt};
  double total = 0;
  for (double v : n) total += v;
  s.mean = total / double(pixels);
  if (squared_errors.empty() || total <= 0) return s;
  std::vector<std::size_t> order(pixels);
  std::iota(order.begin(), order.end(), std::size_t{0});
  const std::size_t decile = std::max<std::size_t>(1, pixels / 10);
  std::partial_sort(order.begin(), order.begin() + std::ptrdiff_t(decile), order.end(), [&](std::size_t i, std::size_t j) {
    return squared_errors[i] != squared_errors[j] ? squared_errors[i] > squared_errors[j] : i < j;
  });
  double top = 0;
  for (std::size_t i = 0; i < decile; ++i) top += n[order[i]];
  s.top_error_decile_share = top / total;
  return s;
}

}  // namespace

RoundOutputs AccumulateRound(const RoundInputs& inputs, Progress progress) {
  if (inputs.round < 1) {
    throw ImageError("round " + std::to_string(inputs.round) + " is not a round (they count from 1)");
  }
  if (inputs.round == 1 && inputs.previous_accumulation) {
    throw ImageError("round 1 was given a previous accumulation");
  }
  if (inputs.round > 1 && !inputs.previous_accumulation) {
    throw ImageError("round " + std::to_string(inputs.round) + " needs the accumulation of round " +
                     std::to_string(inputs.round - 1));
  }
  const Image round = StitchTiles(inputs.size, inputs.tile_size, inputs.tiles, progress);
  CheckRoundValues(round);
  std::optional<Accumulation> previous;
  if (inputs.previous_accumulation) {
    previous = DecodeAccumulationExr(*inputs.previous_accumulation, inputs.size,
                                     round.channels(), inputs.round - 1);
  }
  std::optional<SampleMap> map;
  if (inputs.sample_map) {
    if (!inputs.adaptive_max_samples) throw ImageError("a sample map was given for a render without adaptive sampling");
    map = DecodeSampleMap(*inputs.sample_map, inputs.size, *inputs.adaptive_max_samples);
  }
  const bool counted = SamplesChannel(round.channels()) >= 0;
  if (inputs.adaptive_max_samples && !counted) throw ImageError("adaptive sampling needs tiles with a samples.Y channel");
  // Read the reference before any work it could waste.
  std::optional<Image> reference;
  if (inputs.reference_exr) reference = ReadReferenceExr(*inputs.reference_exr, inputs.size, inputs.measured_layers);

  // One unit per step after the tiles, each of which takes a while on a big film.
  progress.Advance();  // Inputs read.
  const Accumulation accumulation = Fold(std::move(previous), round, RoundWeights(map, inputs.samples_per_pixel));
  const Image mean = MeanOf(accumulation);
  progress.Advance();  // Folded.
  CompositeOutput composite = CompositeImage(mean, inputs.tile_size, inputs.output);
  progress.Advance();  // Final EXR and preview encoded.

  RoundOutputs out;
  out.image_exr = std::move(composite.exr);
  out.preview_png = std::move(composite.preview_png);
  out.accumulation_exr = EncodeAccumulationExr(accumulation);
  progress.Advance();  // Accumulation encoded.
  std::vector<double> squared_errors;
  if (accumulation.rounds > 1) {
    out.error_estimate = EstimateError(accumulation);
    if (counted) squared_errors = SquaredErrors(accumulation);
    if (inputs.adaptive_max_samples) {
      out.sample_map = EncodeSampleMap(
          NextSamples(accumulation, round, inputs.samples_per_pixel, *inputs.adaptive_max_samples));
    }
  }
  if (counted) out.samples = SpreadOf(accumulation, squared_errors);
  if (reference) {
    out.reference_rmse = LayerRmse(mean, *reference, "");
    for (const std::string& layer : inputs.measured_layers) {
      if (const std::optional<double> rmse = LayerRmse(mean, *reference, layer))
        out.layer_reference_rmse.emplace(layer, *rmse);
    }
  }
  return out;
}

}  // namespace farm
