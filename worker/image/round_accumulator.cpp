#include "image/round_accumulator.h"

#include <cmath>

#include "image/accumulation_exr.h"
#include "image/image_error.h"
#include "image/reference_exr.h"
#include "image/stitch.h"

// How rounds combine. Round r renders the whole image with fresh, independent samples (and
// photons), so each pixel's round values x_1..x_R are independent estimates; the image is
// their mean. Sums are kept in float (accumulation_exr.h documents the file) and every sum
// is updated in double then rounded once per round, in pixel order: the bytes depend only
// on the rounds' pixels.
//
// The error estimate is the RMSE the mean is expected to have: for each pixel and channel
// R, G, B, the unbiased sample variance s^2 over the rounds estimates one round's variance,
// so s^2 / R estimates the mean's; their average over pixels and channels is the expected
// squared error (if rounds are unbiased; the photon maps' kernel bias is not seen by it),
// and its square root the RMSE.

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

Accumulation Fold(std::optional<Accumulation> previous, const Image& round) {
  const PixelRect& whole = round.rect();
  Accumulation a = previous ? std::move(*previous)
                            : Accumulation{0, Image(whole, round.channels()),
                                           Image(whole, {"R", "G", "B"})};
  ++a.rounds;
  const std::span<const float> x = round.data();
  const std::span<float> sums = a.sums.data();
  for (std::size_t i = 0; i < x.size(); ++i) sums[i] = float(double(sums[i]) + double(x[i]));
  const std::size_t channels = round.channels().size();
  const std::span<float> squares = a.squares.data();
  for (std::size_t p = 0; p < squares.size() / 3; ++p) {
    for (std::size_t c = 0; c < 3; ++c) {  // the beauty is channels 0..2 (CompositeChannels)
      const double v = x[p * channels + c];
      squares[p * 3 + c] = float(double(squares[p * 3 + c]) + v * v);
    }
  }
  return a;
}

Image MeanOf(const Accumulation& a) {
  Image mean(a.sums.rect(), a.sums.channels());
  const std::span<const float> sums = a.sums.data();
  const std::span<float> out = mean.data();
  for (std::size_t i = 0; i < sums.size(); ++i) out[i] = float(double(sums[i]) / a.rounds);
  return mean;
}

double ErrorEstimate(const Accumulation& a) {
  const double r = a.rounds;
  const std::size_t channels = a.sums.channels().size();
  const std::span<const float> sums = a.sums.data();
  const std::span<const float> squares = a.squares.data();
  const std::size_t pixels = squares.size() / 3;
  double total = 0;
  for (std::size_t p = 0; p < pixels; ++p) {
    for (std::size_t c = 0; c < 3; ++c) {
      const double sum = sums[p * channels + c];
      // Rounding in the float sums can make a tiny spread come out negative.
      const double s2 = std::max(0.0, (double(squares[p * 3 + c]) - sum * sum / r) / (r - 1));
      total += s2 / r;
    }
  }
  return std::sqrt(total / (3.0 * double(pixels)));
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
  // Read the reference before any work it could waste.
  std::optional<Image> reference;
  if (inputs.reference_exr) reference = ReadReferenceExr(*inputs.reference_exr, inputs.size);

  // One unit per step after the tiles, each of which takes a while on a big film.
  progress.Advance();  // Inputs read.
  const Accumulation accumulation = Fold(std::move(previous), round);
  const Image mean = MeanOf(accumulation);
  progress.Advance();  // Folded.
  CompositeOutput composite = CompositeImage(mean, inputs.tile_size, inputs.output);
  progress.Advance();  // Final EXR and preview encoded.

  RoundOutputs out;
  out.image_exr = std::move(composite.exr);
  out.preview_png = std::move(composite.preview_png);
  out.accumulation_exr = EncodeAccumulationExr(accumulation);
  progress.Advance();  // Accumulation encoded.
  if (accumulation.rounds > 1) out.error_estimate = ErrorEstimate(accumulation);
  if (reference) {
    out.reference_rmse = LayerRmse(mean, *reference, "");
    for (std::string_view layer : kMeasuredLayers) {
      if (const std::optional<double> rmse = LayerRmse(mean, *reference, layer))
        out.layer_reference_rmse.emplace(layer, *rmse);
    }
  }
  return out;
}

}  // namespace farm
