#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "image/composite.h"
#include "image/error_estimate.h"
#include "image/image.h"
#include "util/progress.h"

namespace farm {

// One progressive round's composite: the round's tiles, and what earlier rounds left.
struct RoundInputs {
  ImageSize size;
  int tile_size = 32;
  // From 1.
  int round = 1;
  std::span<const EncodedTile> tiles;
  // The previous round's RoundOutputs::accumulation_exr; absent in round 1.
  std::optional<std::string> previous_accumulation;
  // A converged image of the same size to measure the error against (untrusted bytes).
  std::optional<std::string> reference_exr;
  // The sample map (image/sample_map.h) the round's tiles were drawn with, if they were
  // allocated by error; absent, every pixel drew samples_per_pixel (edge pixels more).
  std::optional<std::string> sample_map = {};
  // The scene's samples_per_pixel: a round's pixel weighs its allocated samples over this.
  std::uint32_t samples_per_pixel = 1;
  // With adaptive sampling: the most samples a pixel may draw in a round. From round 2 on
  // the composite then allocates the next round's samples (RoundOutputs::sample_map).
  std::optional<std::uint32_t> adaptive_max_samples = {};
  // The final EXR's metadata and the preview's tone mapping.
  OutputSettings output = {};
  // The light layers ("indirect": indirect.R, G, B) whose error against reference_exr is
  // measured apart from the beauty's where both images have them, in the order reports
  // show them: the contract's keys of RoundMetrics.layer_reference_rmse (the executor
  // reads them; the coordinator accepts no other).
  std::vector<std::string> measured_layers = {};
};

// How the camera samples so far spread over pixels (RoundMetrics.samples in worker.proto).
struct SampleSpread {
  std::string layer;  // the final EXR's channel of samples per pixel over all rounds
  std::uint64_t min = 0, max = 0;
  double mean = 0;
  // The share of all samples in the tenth of pixels with the largest estimated error
  // (from round 2).
  std::optional<double> top_error_decile_share;
};

struct RoundOutputs {
  // The mean of all rounds so far, every channel, as the final tiled EXR.
  std::string image_exr;
  std::string preview_png;
  // What the next round needs to extend the mean and the error estimate.
  std::string accumulation_exr;
  // The estimated RMSE of the mean's beauty (R, G, B), its noise and bias parts and an
  // interval (image/error_estimate.h); absent in round 1.
  std::optional<ErrorEstimate> error_estimate;
  // RMSE of the mean's beauty against reference_exr, when one was given.
  std::optional<double> reference_rmse;
  // RMSE of each of measured_layers (by name) that both the mean and reference_exr have.
  std::map<std::string, double> layer_reference_rmse;
  // The next round's samples per pixel (RoundInputs::adaptive_max_samples).
  std::optional<std::string> sample_map;
  // Where the samples went, if the tiles have a samples layer.
  std::optional<SampleSpread> samples;
};

// Stitches the round's tiles, folds them into the running per-pixel sums of earlier rounds,
// and measures the error of the mean. Deterministic bytes. Throws ImageError naming what is
// wrong with a tile, the accumulation or the reference. progress advances by one per tile
// stitched, then once per later step (inputs read, fold, final EXR, accumulation EXR):
// tiles + 4 in all.
RoundOutputs AccumulateRound(const RoundInputs& inputs, Progress progress = {});

}  // namespace farm
