#include "image/reference_exr.h"
#include "image/round_accumulator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include "image/accumulation_exr.h"
#include "image/image_error.h"
#include "image/sample_map.h"
#include "image/tile_exr.h"

namespace farm {
namespace {

using PixelFn = std::function<float(int x, int y, int c)>;

// 20x12 in 8-pixel tiles: a 3x2 grid with a partial last column and row.
constexpr ImageSize kSize{20, 12};
constexpr int kTile = 8;
const std::vector<std::string> kChannels = {"R", "G", "B", "A", "direct.R", "edge.Y"};

std::vector<EncodedTile> Tiles(const PixelFn& value, ImageSize size = kSize,
                               const std::vector<std::string>& channels = kChannels) {
  std::vector<EncodedTile> tiles;
  for (int y = 0; y < size.height; y += kTile)
    for (int x = 0; x < size.width; x += kTile) {
      const PixelRect r{x, y, std::min(kTile, size.width - x), std::min(kTile, size.height - y)};
      Image tile(r, channels);
      for (int py = r.y; py < r.y_end(); ++py)
        for (int px = r.x; px < r.x_end(); ++px)
          for (int c = 0; c < tile.channel_count(); ++c) tile.pixel(px, py)[c] = value(px, py, c);
      tiles.push_back({r, EncodeTileExr(tile, size)});
    }
  return tiles;
}

Image WholeImage(const PixelFn& value, const std::vector<std::string>& channels,
                 ImageSize size = kSize) {
  Image image({0, 0, size.width, size.height}, channels);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x)
      for (int c = 0; c < image.channel_count(); ++c) image.pixel(x, y)[c] = value(x, y, c);
  return image;
}

// Runs rounds 1..n of the given per-round images; returns the last outputs.
RoundOutputs RunRounds(int n, const std::function<PixelFn(int round)>& round_value,
                       const std::optional<std::string>& reference = std::nullopt,
                       const std::function<void(int, const RoundOutputs&)>& each = {}) {
  RoundOutputs out;
  for (int r = 1; r <= n; ++r) {
    const std::vector<EncodedTile> tiles = Tiles(round_value(r));
    RoundInputs in{kSize, kTile, r, tiles, std::nullopt, reference};
    if (r > 1) in.previous_accumulation = out.accumulation_exr;
    out = AccumulateRound(in);
    if (each) each(r, out);
  }
  return out;
}

Image DecodeImage(const RoundOutputs& out) {
  return DecodeTileExr(out.image_exr, kSize, {0, 0, kSize.width, kSize.height}, kChannels);
}

TEST(RoundAccumulator, SumsAndMeansAreExactOnHandBuiltTiles) {
  // Quarter steps: every sum and square is exact in float.
  const auto round_value = [](int r) -> PixelFn {
    return [r](int x, int y, int c) { return 0.25f * (x + 2 * y + 3 * c) + float(r * r); };
  };
  const RoundOutputs out = RunRounds(3, round_value);
  const Accumulation a = DecodeAccumulationExr(out.accumulation_exr, kSize, kChannels, 3);
  const Image mean = DecodeImage(out);
  for (int y = 0; y < kSize.height; ++y)
    for (int x = 0; x < kSize.width; ++x)
      for (int c = 0; c < int(kChannels.size()); ++c) {
        double sum = 0, squares = 0;
        for (int r = 1; r <= 3; ++r) {
          sum += round_value(r)(x, y, c);
          squares += std::pow(round_value(r)(x, y, c), 2);
        }
        ASSERT_EQ(a.sums.pixel(x, y)[c], float(sum)) << x << ", " << y << " " << kChannels[c];
        if (c < 3) {
          ASSERT_EQ(a.squares.pixel(x, y)[c], float(squares));
        }
        ASSERT_EQ(mean.pixel(x, y)[c], float(sum / 3)) << x << ", " << y << " " << kChannels[c];
      }
}

TEST(RoundAccumulator, RoundOneIsThePlainCompositeWithoutAnErrorEstimate) {
  const PixelFn value = [](int x, int y, int c) { return 0.01f * x + 0.1f * y + 0.3f * c; };
  const std::vector<EncodedTile> tiles = Tiles(value);
  const RoundOutputs out = AccumulateRound({kSize, kTile, 1, tiles, std::nullopt, std::nullopt});
  const CompositeOutput plain = Composite(kSize, kTile, tiles);
  EXPECT_EQ(out.image_exr, plain.exr);
  EXPECT_EQ(out.preview_png, plain.preview_png);
  EXPECT_FALSE(out.error_estimate.has_value());
  EXPECT_FALSE(out.reference_rmse.has_value());
  EXPECT_NO_THROW(DecodeAccumulationExr(out.accumulation_exr, kSize, kChannels, 1));
}

TEST(RoundAccumulator, ErrorEstimateIsTheFormulaOnAHandComputedCase) {
  // Pixel (x, y) channel c in round r: 3 rounds; a, b, c per channel chosen by hand for two
  // pixels, every other pixel constant over rounds (variance 0).
  const auto round_value = [](int r) -> PixelFn {
    return [r](int x, int y, int c) -> float {
      if (y != 0 || x > 1 || c > 2) return 0.5f;
      // pixel 0: R 1,2,3 G 0,0,3 B 2,2,2; pixel 1: R 0,4,8 G 1,1,4 B 5,6,7
      static const float v[2][3][3] = {{{1, 2, 3}, {0, 0, 3}, {2, 2, 2}},
                                       {{0, 4, 8}, {1, 1, 4}, {5, 6, 7}}};
      return v[x][c][r - 1];
    };
  };
  // Unbiased variances: pixel 0: 1, 3, 0; pixel 1: 16, 3, 1. Sum 24, each divided by R = 3.
  const double expected = std::sqrt((24.0 / 3) / (3.0 * kSize.width * kSize.height));
  const RoundOutputs out = RunRounds(3, round_value);
  ASSERT_TRUE(out.error_estimate.has_value());
  EXPECT_NEAR(out.error_estimate->rmse, expected, 1e-12);
}

TEST(RoundAccumulator, EstimateTracksTheNoiseOfIndependentRoundsAndFallsAsTheyAdd) {
  // Each round is truth plus independent Gaussian noise of known sigma: the mean of R
  // rounds has RMSE sigma / sqrt(R), which both the estimate and the reference should find.
  constexpr double kSigma = 0.05;
  const PixelFn truth = [](int x, int y, int c) { return 0.3f + 0.02f * x + 0.03f * y + 0.1f * c; };
  const auto round_value = [&](int r) -> PixelFn {
    auto noise = std::make_shared<std::vector<float>>();
    std::mt19937_64 rng(1000 + r);
    std::normal_distribution<double> gauss(0, kSigma);
    for (int i = 0; i < kSize.width * kSize.height * int(kChannels.size()); ++i)
      noise->push_back(float(gauss(rng)));
    return [=](int x, int y, int c) {
      return truth(x, y, c) + (*noise)[(y * kSize.width + x) * kChannels.size() + c];
    };
  };
  const std::string reference = EncodeTileExr(WholeImage(truth, {"R", "G", "B"}), kSize);
  std::vector<double> estimates;
  RunRounds(16, round_value, reference, [&](int r, const RoundOutputs& out) {
    if (r == 1) return;
    const double expected = kSigma / std::sqrt(double(r));
    ASSERT_TRUE(out.error_estimate && out.reference_rmse);
    EXPECT_NEAR(out.error_estimate->rmse, expected, 0.10 * expected) << "round " << r;
    EXPECT_NEAR(*out.reference_rmse, expected, 0.10 * expected) << "round " << r;
    estimates.push_back(out.error_estimate->rmse);
  });
  // Rounds 2, 4, 8, 16: each doubling cuts the error by about 1/sqrt(2).
  EXPECT_LT(estimates[2], estimates[0]);
  EXPECT_LT(estimates[6], estimates[2]);
  EXPECT_LT(estimates[14], estimates[6]);
}

TEST(RoundAccumulator, ReferenceRmseOfAKnownOffset) {
  const PixelFn value = [](int x, int y, int c) { return 0.1f * c + 0.01f * (x + y); };
  // Reference: R off by 0.25, G exact, B off by 0.5 everywhere; alpha is not beauty.
  const PixelFn reference = [&](int x, int y, int c) {
    return value(x, y, c) + (c == 0 ? 0.25f : c == 2 ? -0.5f : c == 3 ? 9.0f : 0.0f);
  };
  const std::string ref = EncodeTileExr(WholeImage(reference, {"R", "G", "B", "A"}), kSize);
  const RoundOutputs out = RunRounds(1, [&](int) { return value; }, ref);
  ASSERT_TRUE(out.reference_rmse.has_value());
  EXPECT_NEAR(*out.reference_rmse, std::sqrt((0.25 * 0.25 + 0.5 * 0.5) / 3), 1e-6);
}

TEST(RoundAccumulator, LayerReferenceRmseForEachLayerBothImagesHave) {
  const std::vector<std::string> channels = {"R", "G", "B", "A", "direct.R", "direct.G", "direct.B",
                                             "indirect.R", "indirect.G", "indirect.B"};
  const PixelFn value = [](int x, int y, int c) { return 0.05f * c + 0.01f * (x + y); };
  // The reference has no direct layer; its indirect.G is off by 0.5 and the beauty exact.
  const std::vector<std::string> ref_channels = {"R", "G", "B", "indirect.R", "indirect.G", "indirect.B"};
  const PixelFn reference = [&](int x, int y, int c) {
    return c < 3 ? value(x, y, c) : value(x, y, c + 4) + (c == 4 ? 0.5f : 0.0f);
  };
  const std::vector<EncodedTile> tiles = Tiles(value, kSize, channels);
  RoundInputs in{kSize, kTile, 1, tiles, std::nullopt,
                 EncodeTileExr(WholeImage(reference, ref_channels), kSize)};
  in.measured_layers = {"direct", "indirect"};
  const RoundOutputs out = AccumulateRound(in);
  ASSERT_TRUE(out.reference_rmse.has_value());
  EXPECT_NEAR(*out.reference_rmse, 0.0, 1e-7);
  ASSERT_EQ(out.layer_reference_rmse.size(), 1u);
  ASSERT_TRUE(out.layer_reference_rmse.contains("indirect"));
  EXPECT_NEAR(out.layer_reference_rmse.at("indirect"), std::sqrt(0.25 / 3), 1e-6);
  // Only the layers asked for: the reference has no direct layer, and indirect is not one.
  in.measured_layers = {"direct"};
  EXPECT_TRUE(AccumulateRound(in).layer_reference_rmse.empty());
}

TEST(RoundAccumulator, BytesAreDeterministicWhateverTheTileOrder) {
  const auto round_value = [](int r) -> PixelFn {
    return [r](int x, int y, int c) { return std::sin(0.1f * x * r + y + c); };
  };
  const RoundOutputs a = RunRounds(2, round_value);
  RoundOutputs first = RunRounds(1, round_value);
  std::vector<EncodedTile> tiles = Tiles(round_value(2));
  std::reverse(tiles.begin(), tiles.end());
  const RoundOutputs b =
      AccumulateRound({kSize, kTile, 2, tiles, first.accumulation_exr, std::nullopt});
  EXPECT_EQ(a.image_exr, b.image_exr);
  EXPECT_EQ(a.preview_png, b.preview_png);
  EXPECT_EQ(a.accumulation_exr, b.accumulation_exr);
  EXPECT_EQ(a.error_estimate, b.error_estimate);
}

// --- untrusted input -------------------------------------------------------------------

// Expects AccumulateRound to throw an ImageError mentioning needle: a ReferenceImageError
// (the user's input, not the farm's) exactly when the reference is to blame.
void ExpectRefused(const RoundInputs& in, const std::string& needle, bool reference = false) {
  try {
    AccumulateRound(in);
    ADD_FAILURE() << "accepted; expected an ImageError mentioning '" << needle << "'";
  } catch (const ImageError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    EXPECT_EQ(dynamic_cast<const ReferenceImageError*>(&e) != nullptr, reference) << e.what();
  }
}

const PixelFn kFlat = [](int, int, int c) { return 0.5f + c; };

std::string AccumulationOf(int rounds, const std::vector<std::string>& channels = kChannels,
                           ImageSize size = kSize, float poison = 0, int poison_at = -1, double deviations = 0) {
  const PixelRect whole{0, 0, size.width, size.height};
  Accumulation a{rounds, Image(whole, channels), Image(whole, {"R", "G", "B"}), Image(whole, {"W"}), deviations, 0};
  std::fill(a.weights.data().begin(), a.weights.data().end(), float(rounds));
  std::fill(a.sums.data().begin(), a.sums.data().end(), 1.0f);
  std::fill(a.squares.data().begin(), a.squares.data().end(), 1.0f);
  if (poison_at == 0) a.sums.data()[5] = poison;
  if (poison_at == 1) a.squares.data()[7] = poison;
  return EncodeAccumulationExr(a);
}

TEST(RoundAccumulator, RefusesMalformedAccumulationsNamingWhatIsWrong) {
  const std::vector<EncodedTile> tiles = Tiles(kFlat);
  const auto round2 = [&](std::string acc) {
    return RoundInputs{kSize, kTile, 2, tiles, std::move(acc), std::nullopt};
  };
  ExpectRefused(round2(AccumulationOf(2)), "holds 2 rounds, expected 1");
  ExpectRefused(round2(AccumulationOf(1, {"R", "G", "B", "A"})), "accumulation has channels");
  ExpectRefused(round2(AccumulationOf(1, kChannels, {20, 13})), "not the whole 20x12 image");
  ExpectRefused(round2("not an EXR at all"), "accumulation is not a readable OpenEXR");
  ExpectRefused(round2(AccumulationOf(1).substr(0, 300)), "accumulation is not a readable");
  ExpectRefused(round2(AccumulationOf(1, kChannels, kSize, NAN, 0)), "is nan, not finite");
  ExpectRefused(round2(AccumulationOf(1, kChannels, kSize, -1, 1)), "sumsq.");
  ExpectRefused(round2(AccumulationOf(1, kChannels, kSize, 0, -1, -2)), "photonfarm.deviations is -2");
  // A tile EXR is not an accumulation: no round count.
  ExpectRefused(round2(tiles[0].exr), "accumulation");
  ExpectRefused(round2(EncodeTileExr(WholeImage(kFlat, AccumulationChannels(kChannels)), kSize)),
                "no int attribute photonfarm.rounds");
  ExpectRefused({kSize, kTile, 2, tiles, std::nullopt, std::nullopt}, "needs the accumulation");
  ExpectRefused({kSize, kTile, 1, tiles, AccumulationOf(1), std::nullopt}, "round 1 was given");
  ExpectRefused({kSize, kTile, 0, tiles, std::nullopt, std::nullopt}, "not a round");
}

TEST(RoundAccumulator, RefusesMalformedReferencesNamingWhatIsWrong) {
  const std::vector<EncodedTile> tiles = Tiles(kFlat);
  const auto with = [&](std::string ref) {
    return RoundInputs{kSize, kTile, 1, tiles, std::nullopt, std::move(ref)};
  };
  ExpectRefused(with(EncodeTileExr(WholeImage(kFlat, {"R", "G", "B"}, {10, 12}), {10, 12})),
                "not the whole 20x12 image", true);
  ExpectRefused(with(EncodeTileExr(WholeImage(kFlat, {"R", "G"}), kSize)), "no channel B", true);
  ExpectRefused(with("garbage"), "reference image is not a readable OpenEXR", true);
  const PixelFn nan_at_3_4 = [](int x, int y, int c) {
    return x == 3 && y == 4 && c == 1 ? std::numeric_limits<float>::quiet_NaN() : 1.0f;
  };
  ExpectRefused(with(EncodeTileExr(WholeImage(nan_at_3_4, {"R", "G", "B"}), kSize)),
                "channel G at pixel (3, 4) is not finite", true);
}

TEST(RoundAccumulator, RefusesNonFiniteOrMisplacedTiles) {
  const PixelFn inf = [](int x, int, int c) {
    return x == 17 && c == 4 ? std::numeric_limits<float>::infinity() : 1.0f;
  };
  ExpectRefused({kSize, kTile, 1, Tiles(inf), std::nullopt, std::nullopt},
                "tile channel direct.R at pixel (17, 0) is not finite");
  std::vector<EncodedTile> tiles = Tiles(kFlat);
  tiles.pop_back();
  ExpectRefused({kSize, kTile, 1, tiles, std::nullopt, std::nullopt}, "missing");
}

// Progress counts the tiles stitched, then the steps after them (fold and mean, composite
// EXR and preview, accumulation EXR): a composite of n tiles ends at n + 4.
// Adaptive sampling: tiles with a samples layer, pixel (x, y) of round r drawing
// samples(r, x, y) samples.
const std::vector<std::string> kCounted = {"R", "G", "B", "A", "direct.R", "edge.Y", kSamplesChannel};
constexpr int kCountChannel = 6;

TEST(RoundAccumulator, RoundsOfDifferentSampleCountsAreWeighedByTheirSamples) {
  // Two rounds of 2 samples a pixel (weight 1), then a third drawn by a hand-made map of 1
  // to 8 samples (weight n / 2): the mean is (x1 + x2 + (n / 2) x3) / (2 + n / 2), and the
  // samples layer the sum 2 + 2 + n. Quarter steps keep every value exact in float.
  const auto n_of = [](int x, int y) { return std::uint32_t(1 + (x + 3 * y) % 8); };
  SampleMap map{kSize, {}};
  for (int y = 0; y < kSize.height; ++y)
    for (int x = 0; x < kSize.width; ++x) map.counts.push_back(n_of(x, y));
  const auto value = [&](int r) -> PixelFn {
    return [r, n_of](int x, int y, int c) -> float {
      if (c == kCountChannel) return r < 3 ? 2.0f : float(n_of(x, y));
      return 0.25f * float((x + y + c + r * r) % 9);
    };
  };
  RoundOutputs out;
  for (int r = 1; r <= 3; ++r) {
    const std::vector<EncodedTile> tiles = Tiles(value(r), kSize, kCounted);
    RoundInputs in{kSize, kTile, r, tiles, std::nullopt, std::nullopt};
    if (r > 1) in.previous_accumulation = out.accumulation_exr;
    in.samples_per_pixel = 2;
    in.adaptive_max_samples = 8;
    if (r == 3) in.sample_map = EncodeSampleMap(map);
    out = AccumulateRound(in);
    EXPECT_EQ(out.sample_map.has_value(), r >= 2) << r;  // the next round's, from two rounds on
  }
  const Image mean = DecodeTileExr(out.image_exr, kSize, {0, 0, kSize.width, kSize.height}, kCounted);
  for (int y = 0; y < kSize.height; ++y)
    for (int x = 0; x < kSize.width; ++x) {
      const double w3 = n_of(x, y) / 2.0;
      for (int c = 0; c < int(kCounted.size()); ++c) {
        const double want = c == kCountChannel ? 4.0 + n_of(x, y)
                                               : (value(1)(x, y, c) + value(2)(x, y, c) + w3 * value(3)(x, y, c)) / (2 + w3);
        ASSERT_EQ(mean.pixel(x, y)[c], float(want)) << x << ", " << y << " " << kCounted[c];
      }
    }
  ASSERT_TRUE(out.samples.has_value());
  EXPECT_EQ(out.samples->layer, "samples.Y");
  EXPECT_EQ(out.samples->min, 5u);
  EXPECT_EQ(out.samples->max, 12u);
}

// The pipeline end to end on a noisy furnace: every pixel's truth is 0.5, the left half's
// samples four times as noisy (in variance) as the right's; each round draws the samples
// the previous composite allocated, its value the truth plus Gaussian noise of variance
// sigma^2 / n. The allocation moves samples to the noisy half at the same total, and the
// image stays at 0.5 (within 4 standard errors over its pixels), exactly so without noise.
TEST(RoundAccumulator, ANoisyFurnaceStaysAtItsValueUnderAdaptiveSampling) {
  constexpr std::uint32_t kSpp = 4;
  const auto sigma = [](int x) { return x < kSize.width / 2 ? 0.4 : 0.2; };
  for (const bool noisy : {false, true}) {
    RoundOutputs out;
    std::optional<SampleMap> map;
    std::mt19937 rng(7);
    for (int r = 1; r <= 8; ++r) {
      Image round({0, 0, kSize.width, kSize.height}, kCounted);
      for (int y = 0; y < kSize.height; ++y)
        for (int x = 0; x < kSize.width; ++x) {
          const std::uint32_t n = map ? map->at(x, y) : kSpp;
          std::normal_distribution<double> noise(0, sigma(x) / std::sqrt(double(n)));
          for (int c = 0; c < int(kCounted.size()); ++c) round.pixel(x, y)[c] = float(0.5 + (noisy ? noise(rng) : 0.0));
          round.pixel(x, y)[kCountChannel] = float(n);
        }
      std::vector<EncodedTile> tiles;
      for (int y = 0; y < kSize.height; y += kTile)
        for (int x = 0; x < kSize.width; x += kTile) {
          const PixelRect t{x, y, std::min(kTile, kSize.width - x), std::min(kTile, kSize.height - y)};
          Image tile(t, kCounted);
          for (int py = t.y; py < t.y_end(); ++py)
            for (int px = t.x; px < t.x_end(); ++px) std::copy_n(round.pixel(px, py), kCounted.size(), tile.pixel(px, py));
          tiles.push_back({t, EncodeTileExr(tile, kSize)});
        }
      RoundInputs in{kSize, kTile, r, tiles, std::nullopt, std::nullopt};
      if (r > 1) in.previous_accumulation = out.accumulation_exr;
      in.samples_per_pixel = kSpp;
      in.adaptive_max_samples = 64 * kSpp;
      if (map) in.sample_map = EncodeSampleMap(*map);
      out = AccumulateRound(in);
      if (r < 2) continue;
      ASSERT_TRUE(out.sample_map.has_value());
      map = DecodeSampleMap(*out.sample_map, kSize, 64 * kSpp);
      std::uint64_t left = 0, right = 0;
      for (int y = 0; y < kSize.height; ++y)
        for (int x = 0; x < kSize.width; ++x) (x < kSize.width / 2 ? left : right) += map->at(x, y);
      EXPECT_EQ(left + right, std::uint64_t(kSpp) * kSize.width * kSize.height) << "round " << r;
      if (noisy) {
        EXPECT_GT(double(left), 1.4 * double(right)) << "round " << r;
      } else {
        EXPECT_EQ(left, right) << "round " << r;  // no noise: sampled evenly
      }
    }
    const Image mean = DecodeTileExr(out.image_exr, kSize, {0, 0, kSize.width, kSize.height}, kCounted);
    double total = 0;
    for (int y = 0; y < kSize.height; ++y)
      for (int x = 0; x < kSize.width; ++x) {
        if (!noisy) {
          ASSERT_EQ(mean.pixel(x, y)[0], 0.5f) << x << ", " << y;
        }
        total += mean.pixel(x, y)[0];
      }
    const double pixels = kSize.width * kSize.height;
    // Each pixel has at least two rounds of 4 samples at sigma <= 0.4.
    const double standard_error = 0.4 / std::sqrt(8.0 * pixels);
    EXPECT_NEAR(total / pixels, 0.5, 4 * standard_error) << (noisy ? "noisy" : "exact");
  }
}

TEST(RoundAccumulator, RefusesASampleMapWithoutAdaptiveSamplingOrOfTheWrongSize) {
  const std::vector<EncodedTile> tiles = Tiles(kFlat, kSize, kCounted);
  const RoundOutputs one = AccumulateRound({kSize, kTile, 1, tiles, std::nullopt, std::nullopt});
  RoundInputs in{kSize, kTile, 2, tiles, one.accumulation_exr, std::nullopt};
  in.sample_map = EncodeSampleMap({kSize, std::vector<std::uint32_t>(240, 1)});
  ExpectRefused(in, "without adaptive sampling");
  in.adaptive_max_samples = 4;
  in.sample_map = EncodeSampleMap({{20, 13}, std::vector<std::uint32_t>(260, 1)});
  ExpectRefused(in, "not the whole 20x12 image");
  in.sample_map = EncodeSampleMap({kSize, std::vector<std::uint32_t>(240, 5)});
  ExpectRefused(in, "5 samples, not 1 to 4");
}

TEST(RoundAccumulator, ProgressCountsTilesStitchedAndTheStepsAfter) {
  const std::vector<EncodedTile> tiles = Tiles([](int x, int y, int c) { return float(x + y + c); });
  ProgressCounter counter{0};
  RoundInputs in{kSize, kTile, 1, tiles, std::nullopt, std::nullopt};
  AccumulateRound(in, Progress(counter));
  EXPECT_EQ(counter.load(), tiles.size() + 4);
}

}  // namespace
}  // namespace farm
