#pragma once

#include <cstdint>
#include <span>
#include <stop_token>
#include <string>
#include <string_view>
#include <vector>

#include "image/image.h"
#include "photonmap/photon_snapshot.h"
#include "scene/scene.h"
#include "util/progress.h"

namespace farm {

// The channels RenderTile produces: the beauty (R, G, B, A), then the AOV layers
// direct.{R,G,B}, indirect.{R,G,B}, caustic.{R,G,B}, volume.{R,G,B} (light scattered by
// media towards the camera; 0 without media), bias.{R,G,B} (the bias layer: the kernel
// bias of the photon estimates, estimated by their companions, image/error_estimate.h;
// 0 unless RoundSettings::bias_layer),
// albedo.{R,G,B}, normal.{X,Y,Z},
// depth.Z, edge.Y (1 on pixels edge anti-aliasing supersampled) and samples.Y (the camera
// samples the pixel drew), so that passes can be recombined after the render.
std::vector<std::string> RenderChannels();

// The index of channel `name` ("normal.X") in RenderChannels(); throws std::out_of_range
// for a name it does not have.
int RenderChannelIndex(std::string_view name);

// What changes from one progressive round to the next.
struct RoundSettings {
  // Multiplies the scene's photon search radii (progressive photon mapping shrinks them).
  double radius_scale = 1.0;
  // Index of the round's first pixel sample, so that each round draws fresh samples. It keys
  // the round's sample set: any value distinct per round (0 in round 1) gives independent
  // samples, however many an edge pixel takes (see tile_renderer.cpp).
  std::uint32_t first_sample = 0;
  // Under adaptive sampling, from round 3: each pixel's samples this round, the whole image
  // row-major (image/sample_map.h), in place of samples_per_pixel and edge anti-aliasing;
  // empty otherwise. Needs the one-pixel box filter.
  std::span<const std::uint32_t> samples = {};
  // With samples: the most a pixel may draw in a round (AdaptiveMaxSamples), the domain of
  // the round's sample set, so that a pixel's samples never depend on its neighbours'.
  std::uint32_t max_samples = 0;
  // Whether the bias layer is rendered (a job of more than one round, whose error is
  // estimated: image/error_estimate.h); else it stays 0, at no cost.
  bool bias_layer = false;
};

// The seed of a round's edge pilots (render/edge_detect.h), from its samples' seed: a set
// of its own, so that a pixel's pilot is independent of the samples it is estimated from.
std::uint64_t EdgePilotSeed(std::uint64_t round_seed);

// Camera rays in a pixel's pilot, stratified over the pixel (a (0,2)-net of 4 points): a
// feature covering a quarter of a pixel in one piece is seen by one of them, where one ray
// would see it one time in four. Each is a ray per specular bounce, no light.
inline constexpr std::uint32_t kEdgePilots = 4;

// The most camera samples a pixel may draw in a round under adaptive sampling: 64 times
// samples_per_pixel, and at least a bright edge's (edge_samples times
// kMaxEdgeSampleFactor, render/edge_detect.h: adaptive rounds give a light's image no fewer
// than the rounds before them could), at most 65536.
std::uint32_t AdaptiveMaxSamples(std::uint32_t samples_per_pixel, std::uint32_t edge_samples);

// How a tile's camera samples came out, which the worker reports (TileSamples in
// worker.proto) and the coordinator counts: a healthy render has no non-finite sample and
// no zero one where light reaches.
struct SampleCounts {
  std::uint64_t samples = 0;
  // With a light term that came out NaN or infinite (dropped: SampleResult::nonfinite).
  std::uint64_t nonfinite = 0;
  // Exactly black although the path reached a non-specular surface and shaded it
  // (SampleResult::shaded), of the samples taken at full effort (a pixel's first
  // samples_per_pixel; the extra ones take a share of the light samples and gather rays,
  // and one shadow ray and one gather ray may both find nothing).
  std::uint64_t zero = 0;
};

// Renders one rectangle of the scene's image into RenderChannels(): linear radiance, alpha
// the fraction of camera rays that hit geometry (or see an environment visible to the
// camera). photons holds the job's photon maps, or is
// null for a job without any. Uses all threads TBB allows. A pixel's value depends only on
// the scene (its seed included), the photon maps and the pixel, never on the rectangle it
// was rendered in, so tiles rendered anywhere stitch into a bit-identical image. If stop is
// requested the render ends early and the returned image must be discarded. progress
// advances by the camera samples each pixel took as it is finished (with edge
// anti-aliasing: every base-pass pixel of the tile and its apron, then an edge pixel's extra
// samples), so a tile rendered in one pass adds width x height x samples in all. With a
// pixel filter wider than a pixel (scene.data().filter), the pixels of its margin about
// the tile are rendered too and count alike (docs/pixel-filters.md). counts, if not null,
// receives how every sample drawn came out (the apron's and the margin's included).
Image RenderTile(const Scene& scene, const PhotonSnapshot* photons, const PixelRect& rect,
                 const RoundSettings& round = {}, std::stop_token stop = {},
                 Progress progress = {}, SampleCounts* counts = nullptr);

}  // namespace farm
