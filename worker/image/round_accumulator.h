#pragma once

#include <map>
#include <optional>
#include <span>
#include <string>

#include "image/composite.h"
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
  // The final EXR's metadata and the preview's tone mapping.
  OutputSettings output = {};
};

struct RoundOutputs {
  // The mean of all rounds so far, every channel, as the final tiled EXR.
  std::string image_exr;
  std::string preview_png;
  // What the next round needs to extend the mean and the error estimate.
  std::string accumulation_exr;
  // RMSE of the mean's beauty (R, G, B) estimated from the spread between rounds; absent in
  // round 1.
  std::optional<double> error_estimate;
  // RMSE of the mean's beauty against reference_exr, when one was given.
  std::optional<double> reference_rmse;
  // RMSE of each kMeasuredLayers layer (by name) that both the mean and reference_exr have.
  std::map<std::string, double> layer_reference_rmse;
};

// Stitches the round's tiles, folds them into the running per-pixel sums of earlier rounds,
// and measures the error of the mean. Deterministic bytes. Throws ImageError naming what is
// wrong with a tile, the accumulation or the reference. progress advances by one per tile
// stitched, then once per later step (inputs read, fold, final EXR, accumulation EXR):
// tiles + 4 in all.
RoundOutputs AccumulateRound(const RoundInputs& inputs, Progress progress = {});

}  // namespace farm
