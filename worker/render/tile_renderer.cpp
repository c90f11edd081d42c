#include "render/tile_renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "render/edge_detect.h"
#include "render/filter_splats.h"
#include "render/integrator.h"
#include "sampling/film_sampler.h"
#include "sampling/hash.h"
#include "sampling/pixel_sampler.h"
#include "scene/scene_data.h"

// How a tile's pixels are sampled.
//
// Every pixel first gets samples_per_pixel camera samples (the base pass). With edge
// anti-aliasing, the base pass also covers a one-pixel apron around the tile; the base
// pass's surface ids, normals, depths and irradiance from the lights (render/edge_detect.h)
// mark edge pixels, and those continue to max(samples_per_pixel, edge_samples) samples in
// all, times the bright-edge factor where a light borders the edge (EdgeSampleFactor).
// FULL mode gives every pixel max(samples_per_pixel, edge_samples); NONE gives none more.
//
// Sample j of a pixel in a round is a pure function of (seed, round key, pixel, j). Its
// film position is the film sampler's sample j of the pixel (sampling/film_sampler.h: one
// sequence over the image, so that neighbouring pixels' samples are stratified together),
// its other dimensions the pixel sampler's, whose permutation domain is the samples an edge
// pixel takes in the round (a scene constant, never a per-pixel choice). An edge pixel's
// first samples are therefore exactly its base samples, and the extra ones continue that
// stratified set; a bright edge's samples past it are a set of their own, keyed apart,
// whose domain is how many more the pixel takes (a pure function of its neighbours and
// pilot, so sample j still depends only on the seed, the round, the pixel and j). A round
// is keyed by RoundSettings::first_sample: round 1 (first_sample 0) uses the scene seed,
// later rounds a seed hashed from (seed, first_sample), so any value distinct per round
// draws a fresh, independent set (the image's rounds then have independent errors, which
// the round accumulator's error estimate relies on).
//
// Under adaptive sampling (RoundSettings::samples), each pixel draws the samples the map
// gives it, samples 0.. of a set whose domain is the round's max_samples, and no edge
// detection runs: the allocation by error already gives an edge's noisy pixels more.
//
// A pixel's first samples_per_pixel samples take the scene's light samples and gather rays
// in full; the samples it draws beyond them (an edge's, or adaptive sampling's) share
// samples_per_pixel samples' worth between them (SamplePlan::Effort), drawn as one
// stratified set over the pixel's extra samples (a run of it each), so that a few rays a
// sample stratify as well as a full sample's. Those samples are there to resolve what the
// pixel covers, a silhouette or a highlight seen in glass, which wants camera rays; the
// light at each point is no noisier than a smooth pixel's, and an edge pixel costs a few
// samples instead of edge_samples.
//
// Apron pixels are computed exactly as in their own tile and the edge decision reads only
// the eight base-pass neighbours, mirrored at the image border, and the pixel's pilot rays
// (drawn from their own set, EdgePilotSeed: a pure function of the round and the pixel),
// so tiles stitch into the same bytes as one whole-image render.
//
// With a pixel filter wider than the box of radius 1/2 (scene/pixel_filter.h), the pixels
// within the filter's margin of the tile are sampled too, each as in its own tile (edge
// pixels among them supersampled, their edge decision on an apron about the margin), and
// every sample is splatted onto the tile pixels it reaches (render/filter_splats.h); the
// light channels are the filtered ones. Normal and depth stay the mean over the pixel's own
// samples that hit: a weighted mean of depths across a silhouette is no depth, and a
// negative lobe could turn a normal around.

namespace farm {
namespace {

// Channel offsets in RenderChannels() order.
enum Channel : int {
  kBeauty = 0,  // R G B, then A at 3
  kAlpha = 3,
  kDirect = 4,
  kIndirect = 7,
  kCaustic = 10,
  kVolume = 13,
  kBias = 16,
  kAlbedo = 19,
  kNormal = 22,
  kDepth = 25,
  kEdge = 26,
  kSamples = 27,
  kSummed = 26,  // channels summed over samples: all but the edge mask and the count
  kChannelCount = 28,
  kHits = kSummed,  // in Sums after the channels: samples that hit geometry
};

using Sums = std::array<double, kSummed + 1>;

PhotonMaps MapsOf(const SceneData& data, const PhotonSnapshot* photons) {
  PhotonMaps maps;
  if (photons) {
    maps.global = photons->map(PhotonMapKind::kGlobal);
    maps.caustic = photons->map(PhotonMapKind::kCaustic);
    maps.volume = photons->map(PhotonMapKind::kVolume);
    maps.irradiance = photons->irradiance_sites();
  }
  maps.global_estimate = ToRadianceEstimate(data.photons.global_estimate);
  maps.caustic_estimate = ToRadianceEstimate(data.photons.caustic_estimate);
  maps.volume_estimate = ToRadianceEstimate(data.photons.volume_estimate);
  return maps;
}

void Add(double* sum, int at, const Rgb& c) {
  sum[at] += c.r;
  sum[at + 1] += c.g;
  sum[at + 2] += c.b;
}

// Adds a sample's light channels, [kBeauty, kNormal), the ones a pixel filter weighs.
void AddLight(const SampleResult& r, double* sum) {
  Add(sum, kBeauty, r.radiance);
  sum[kAlpha] += r.alpha;
  Add(sum, kDirect, r.direct);
  Add(sum, kIndirect, r.indirect);
  Add(sum, kCaustic, r.caustic);
  Add(sum, kVolume, r.volume);
  Add(sum, kBias, r.bias);
  Add(sum, kAlbedo, r.albedo);
}
static_assert(kNormal == FilterSplats::kChannels, "the filtered channels are the light channels");

// Adds a sample's surface cues to a pixel's (edge_detect.h): the first sample's surface
// id, mixed when a later one's differs, the surface normal of each that hit, and the
// brightest emitted light one saw.
void AddSurfaceCues(const SampleResult& r, bool first, SurfaceCues& cues) {
  if (first) cues.surface = r.surface;
  else if (r.surface != cues.surface) cues.mixed = true;
  if (r.hit) cues.normal += r.surface_normal;
  cues.emitted = std::max(cues.emitted, r.emitted.Luminance());
}

// The per-round sampling plan, the same for every pixel of the scene.
struct SamplePlan {
  uint32_t base = 1;          // samples of an ordinary pixel
  uint32_t supersampled = 1;  // samples of an edge pixel (every pixel in FULL mode)
  bool detect_edges = false;  // EDGES mode with something to add
  bool supersample_all = false;
  uint64_t seed = 0;  // of this round's sample set
  uint64_t pilot_seed = 0;  // of its edge pilots: another set
  uint64_t bright_seed = 0;  // of a bright edge's samples past supersampled: another set
  std::span<const uint32_t> allocated;  // adaptive sampling's per-pixel samples, or empty
  int width = 0;

  // The effort (PhotonMappingIntegrator::Li) of sample s of pixel `pixel` (its index in the
  // image), which draws n samples in the round: a pure function of the three and the
  // round, as a sample must be.
  SampleEffort Effort(uint32_t s, uint32_t n, uint64_t pixel) const {
    if (s < base || n <= base) return {};
    constexpr uint64_t kStrataKey = 0x737472617461;  // "strata"
    return {float(base) / float(n), uint32_t(Hash(seed, pixel, kStrataKey)), s - base, n - base};
  }

  // The samples pixel (x, y) draws in the base pass.
  uint32_t first(int x, int y) const {
    if (!allocated.empty()) return allocated[std::size_t(y) * std::size_t(width) + std::size_t(x)];
    return supersample_all ? supersampled : base;
  }

  static SamplePlan Of(const SceneData& data, const RoundSettings& round) {
    SamplePlan p;
    p.base = data.samples_per_pixel;
    p.seed = round.first_sample == 0 ? data.seed : Hash(data.seed, round.first_sample);
    p.pilot_seed = EdgePilotSeed(p.seed);
    constexpr uint64_t kBrightKey = 0x627269676874;  // "bright"
    p.bright_seed = Hash(p.seed, kBrightKey);
    p.width = data.width;
    if (!round.samples.empty()) {
      p.allocated = round.samples;
      p.supersampled = round.max_samples;
      return p;
    }
    const AntialiasingSettings& aa = data.antialiasing;
    p.supersampled = aa.mode == AntialiasingMode::kNone ? p.base
                                                        : std::max(p.base, aa.edge_samples);
    p.detect_edges = aa.mode == AntialiasingMode::kEdges && p.supersampled > p.base;
    p.supersample_all = aa.mode == AntialiasingMode::kFull;
    return p;
  }
};

// The tile's SampleCounts, added to by every thread.
struct SampleTally {
  std::atomic<uint64_t> samples{0}, nonfinite{0}, zero{0};

  SampleCounts Counts() const { return {samples.load(), nonfinite.load(), zero.load()}; }
};

// Draws camera samples of single pixels; one per thread. Counts its samples' outcomes,
// adding them to the tile's tally when it ends.
class PixelRenderer {
 public:
  PixelRenderer(const SceneData& data, const PhotonMappingIntegrator& integrator,
                const SamplePlan& plan, SampleTally& tally)
      : data_(data),
        integrator_(integrator),
        plan_(plan),
        film_(data.width, data.height),
        sampler_(plan.supersampled, plan.seed),
        pilot_sampler_(kEdgePilots, plan.pilot_seed),
        tally_(tally) {}
  ~PixelRenderer() {
    tally_.samples += counts_.samples;
    tally_.nonfinite += counts_.nonfinite;
    tally_.zero += counts_.zero;
  }
  PixelRenderer(const PixelRenderer&) = delete;
  PixelRenderer& operator=(const PixelRenderer&) = delete;

  // Pixel (x, y)'s edge pilot (render/edge_detect.h): samples 0 to kEdgePilots - 1 of the
  // round's pilot set, traced for their cues only, as one pixel's cues.
  SurfaceCues Pilot(int x, int y) {
    SurfaceCues cues;
    int hits = 0;
    double depth = 0;
    for (uint32_t j = 0; j < kEdgePilots; ++j) {
      pilot_sampler_.StartPixelSample(uint64_t(y) * uint64_t(data_.width) + uint64_t(x), j);
      const SampleResult r = integrator_.Cues(Camera(x, y, j, plan_.pilot_seed, pilot_sampler_).ray, pilot_sampler_);
      AddSurfaceCues(r, j == 0, cues);
      if (r.hit) {
        depth += r.depth;
        ++hits;
      }
    }
    cues.inverse_depth = hits > 0 && depth > 0 ? hits / depth : 0.0;
    return cues;
  }

  // Adds samples [from, to) of pixel (x, y), which draws `total` samples in the round, to
  // sum, in sample order, and splats them if splats is not null. If cues is not null, sets
  // its surface and mixed from the samples, adds the surface normals of those that hit to
  // its normal, and adds their irradiance from the lights to irradiance.
  void AddSamples(int x, int y, uint32_t from, uint32_t to, uint32_t total, Sums& sum, FilterSplats* splats,
                  SurfaceCues* cues = nullptr, Rgb* irradiance = nullptr) {
    const uint64_t pixel_index = uint64_t(y) * uint64_t(data_.width) + uint64_t(x);
    // A bright edge's samples past supersampled (render/edge_detect.h) are a stratified set
    // of their own: the first samples of a larger set's shuffle are not stratified, and
    // the base and edge samples must stay so.
    PixelSampler bright(total > plan_.supersampled ? total - plan_.supersampled : 1, plan_.bright_seed);
    for (uint32_t s = from; s < to; ++s) {
      const bool past = s >= plan_.supersampled;
      PixelSampler& sampler = past ? bright : sampler_;
      sampler.StartPixelSample(pixel_index, past ? s - plan_.supersampled : s);
      const auto [film, ray] = Camera(x, y, s, plan_.seed, sampler);
      const SampleEffort effort = plan_.Effort(s, total, pixel_index);
      const SampleResult r = integrator_.Li(ray, sampler, scratch_, effort);
      Count(r, effort.share);
      if (cues) {
        AddSurfaceCues(r, s == from, *cues);
        *irradiance += r.light_irradiance;
      }
      AddLight(r, sum.data());
      if (splats) {
        std::array<double, FilterSplats::kChannels> light{};
        AddLight(r, light.data());
        splats->Add(x, y, film.x, film.y, light.data());
      }
      if (r.hit) {
        sum[kHits] += 1;
        sum[kNormal] += r.normal.x;
        sum[kNormal + 1] += r.normal.y;
        sum[kNormal + 2] += r.normal.z;
        sum[kDepth] += r.depth;
      }
    }
  }

 private:
  // share: the sample's SampleEffort::share.
  void Count(const SampleResult& r, float share) {
    ++counts_.samples;
    if (r.nonfinite) ++counts_.nonfinite;
    // At a lower share one shadow ray and one gather ray may both find nothing.
    if (r.shaded && r.radiance.IsBlack() && share == 1) ++counts_.zero;
  }

  // Sample s of pixel (x, y) in the set keyed by seed: its film position and camera ray,
  // which draws its lens sample from sampler (started for it).
  struct CameraSample {
    Vec2 film;
    Ray ray;
  };
  CameraSample Camera(int x, int y, uint32_t s, uint64_t seed, PixelSampler& sampler) const {
    const Vec2 u = film_.Sample(x, y, s, seed);  // uniform over the pixel; a filter weighs it
    // A pinhole draws no lens sample, so that its images keep their dimensions.
    const Vec2 lens = data_.camera.has_lens() ? sampler.Get2D() : Vec2{};
    const Vec2 film{x + u.x, y + u.y};
    return {film, data_.camera.GenerateRay(film, lens)};
  }

  const SceneData& data_;
  const PhotonMappingIntegrator& integrator_;
  const SamplePlan& plan_;
  FilmSampler film_;
  PixelSampler sampler_;
  PixelSampler pilot_sampler_;
  std::vector<PhotonNeighbour> scratch_;
  SampleTally& tally_;
  SampleCounts counts_;
};

// Runs pixel(renderer, x, y) on every pixel of area. Rows are the unit of parallel work
// and of cancellation; each thread draws with its own PixelRenderer, and a pixel's samples
// are summed in sample order by one thread, so the result is independent of the partition.
template <typename Pixel>
void ForEachPixel(const PixelRect& area, const SceneData& data, const PhotonMappingIntegrator& integrator,
                  const SamplePlan& plan, SampleTally& tally, const std::stop_token& stop, Pixel pixel) {
  tbb::parallel_for(tbb::blocked_range<int>(area.y, area.y_end()), [&](const tbb::blocked_range<int>& rows) {
    PixelRenderer renderer(data, integrator, plan, tally);
    for (int y = rows.begin(); y < rows.end(); ++y) {
      if (stop.stop_requested()) return;
      for (int x = area.x; x < area.x_end(); ++x) pixel(renderer, x, y);
    }
  });
}

// Light and albedo average over all samples (alpha is the covered fraction); normal and
// depth over the samples that hit something, so an edge pixel's depth is a real distance,
// not one diluted by the background.
void WritePixel(const Sums& sum, uint32_t samples, bool supersampled, float* out) {
  const double hits = sum[kHits];
  for (int c = 0; c < kSummed; ++c) {
    const double n = c >= kNormal ? hits : double(samples);
    out[c] = n > 0 ? static_cast<float>(sum[c] / n) : 0.0f;
  }
  out[kEdge] = supersampled ? 1.0f : 0.0f;
  out[kSamples] = static_cast<float>(samples);  // exact: at most 65536
}

void CheckArguments(const SceneData& data, const PixelRect& rect, const RoundSettings& round) {
  if (rect.width < 0 || rect.height < 0 || !PixelRect{0, 0, data.width, data.height}.Contains(rect))
    throw std::invalid_argument("RenderTile: rect (" + std::to_string(rect.x) + ", " +
                                std::to_string(rect.y) + ", " + std::to_string(rect.width) + "x" +
                                std::to_string(rect.height) + ") is not inside the " +
                                std::to_string(data.width) + "x" + std::to_string(data.height) +
                                " image");
  if (!std::isfinite(round.radius_scale) || !(round.radius_scale > 0))
    throw std::invalid_argument("RenderTile: radius_scale must be finite and > 0, got " +
                                std::to_string(round.radius_scale));
  if (round.samples.empty()) return;
  if (round.samples.size() != std::size_t(data.width) * std::size_t(data.height))
    throw std::invalid_argument("RenderTile: the sample map has " + std::to_string(round.samples.size()) +
                                " pixels, the image " + std::to_string(data.width) + "x" + std::to_string(data.height));
  if (!data.filter.is_pixel_box())
    throw std::invalid_argument("RenderTile: adaptive sampling needs the one-pixel box filter");
  for (std::uint32_t n : round.samples)
    if (n < 1 || n > round.max_samples)
      throw std::invalid_argument("RenderTile: the sample map gives a pixel " + std::to_string(n) +
                                  " samples, not 1 to " + std::to_string(round.max_samples));
}

}  // namespace

std::vector<std::string> RenderChannels() {
  return {"R",          "G",          "B",          "A",          "direct.R",  "direct.G",
          "direct.B",   "indirect.R", "indirect.G", "indirect.B", "caustic.R", "caustic.G",
          "caustic.B",  "volume.R",   "volume.G",   "volume.B",   "bias.R",    "bias.G",
          "bias.B",     "albedo.R",   "albedo.G",   "albedo.B",   "normal.X",  "normal.Y",
          "normal.Z",   "depth.Z",    "edge.Y",     kSamplesChannel};
}

int RenderChannelIndex(std::string_view name) {
  const std::vector<std::string> channels = RenderChannels();
  const auto at = std::find(channels.begin(), channels.end(), name);
  if (at == channels.end()) throw std::out_of_range("RenderTile renders no channel " + std::string(name));
  return int(at - channels.begin());
}

std::uint64_t EdgePilotSeed(std::uint64_t round_seed) {
  constexpr std::uint64_t kPilotKey = 0x70696c6f74;  // "pilot"
  return Hash(round_seed, kPilotKey);
}

std::uint32_t AdaptiveMaxSamples(std::uint32_t samples_per_pixel, std::uint32_t edge_samples) {
  return std::min<std::uint32_t>(65536, std::max(64 * samples_per_pixel, edge_samples * kMaxEdgeSampleFactor));
}

Image RenderTile(const Scene& scene, const PhotonSnapshot* photons, const PixelRect& rect,
                 const RoundSettings& round, std::stop_token stop, Progress progress, SampleCounts* counts) {
  const SceneData& data = scene.data();
  CheckArguments(data, rect, round);
  Image image(rect, RenderChannels());
  if (rect.width == 0 || rect.height == 0) return image;
  const PhotonMappingIntegrator integrator(data, MapsOf(data, photons), round.radius_scale, round.bias_layer);
  const SamplePlan plan = SamplePlan::Of(data, round);
  const ImageSize size{data.width, data.height};
  SampleTally tally;
  // Whichever way the render ends, the counts are of the samples it drew.
  const auto report = [&] {
    if (counts) *counts = tally.Counts();
  };

  // The pixels whose samples count: the tile, and with a filter wider than a pixel its
  // margin.
  std::optional<FilterSplats> splats;
  if (!data.filter.is_pixel_box()) splats.emplace(data.filter, rect, size);
  FilterSplats* const splat = splats ? &*splats : nullptr;
  const PixelRect source = splats ? splats->source() : rect;

  // Base pass: every pixel of source, and with edge detection the apron it is judged on.
  const PixelRect area = plan.detect_edges ? ApronArea(source, size) : source;
  std::vector<Sums> sums(static_cast<std::size_t>(area.width) * area.height);
  const auto sum_at = [&](int x, int y) -> Sums& {
    return sums[static_cast<std::size_t>(y - area.y) * area.width + (x - area.x)];
  };
  std::optional<LogLuminanceGrid> light;
  std::optional<SurfaceCueGrid> surfaces, pilots;
  if (plan.detect_edges) {
    light.emplace(area);
    surfaces.emplace(area);
    pilots.emplace(source);
  }
  ForEachPixel(area, data, integrator, plan, tally, stop, [&](PixelRenderer& renderer, int x, int y) {
    Sums& sum = sum_at(x, y);
    const uint32_t first = plan.first(x, y);
    SurfaceCues cues;
    Rgb irradiance;
    renderer.AddSamples(x, y, 0, first, first, sum, splat, surfaces ? &cues : nullptr, &irradiance);
    if (surfaces) {
      const Rgb e = irradiance / float(first);
      light->set(x, y, EdgeLogLuminance(e.r, e.g, e.b));
      // 1 / the mean depth of the samples that hit.
      cues.inverse_depth = sum[kHits] > 0 && sum[kDepth] > 0 ? sum[kHits] / sum[kDepth] : 0.0;
      cues.luminance = Rgb(float(sum[kBeauty]), float(sum[kBeauty + 1]), float(sum[kBeauty + 2])).Luminance() /
                       float(first);
      surfaces->set(x, y, cues);
      if (source.Contains({x, y, 1, 1})) pilots->set(x, y, renderer.Pilot(x, y));
    }
    // Per pixel, not per row: a row of a heavy scene can take long, and one relaxed add
    // per pixel costs nothing beside it.
    progress.Advance(first);
  });
  if (stop.stop_requested()) {
    report();
    return image;
  }

  // Samples each pixel of source took.
  std::vector<std::uint32_t> samples(static_cast<std::size_t>(source.width) * source.height);
  const auto samples_at = [&](int x, int y) -> std::uint32_t& {
    return samples[static_cast<std::size_t>(y - source.y) * source.width + (x - source.x)];
  };
  for (int y = source.y; y < source.y_end(); ++y)
    for (int x = source.x; x < source.x_end(); ++x) samples_at(x, y) = plan.first(x, y);
  if (plan.detect_edges) {
    const std::vector<std::uint8_t> edges =
        DetectEdges(*surfaces, *light, source, data.antialiasing.edge_threshold, &*pilots);
    // Edge pixels continue where their base samples ended, to edge_samples times their
    // bright-edge factor. They cluster along a few rows, so the work is split by edge
    // pixel, not by row, to keep both threads busy.
    std::vector<std::pair<int, int>> edge_pixels;
    for (int y = source.y; y < source.y_end(); ++y)
      for (int x = source.x; x < source.x_end(); ++x)
        if (edges[static_cast<std::size_t>(y - source.y) * source.width + (x - source.x)] != 0) {
          edge_pixels.emplace_back(x, y);
          samples_at(x, y) = plan.supersampled * EdgeSampleFactor(*surfaces, x, y, pilots->at(x, y));
        }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, edge_pixels.size()),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        PixelRenderer renderer(data, integrator, plan, tally);
                        for (std::size_t i = range.begin(); i < range.end(); ++i) {
                          if (stop.stop_requested()) return;
                          const auto [x, y] = edge_pixels[i];
                          const uint32_t n = samples_at(x, y);
                          renderer.AddSamples(x, y, plan.base, n, n, sum_at(x, y), splat);
                          progress.Advance(n - plan.base);
                        }
                      });
    if (stop.stop_requested()) {
      report();
      return image;
    }
  }

  for (int y = rect.y; y < rect.y_end(); ++y)
    for (int x = rect.x; x < rect.x_end(); ++x) {
      const std::uint32_t n = samples_at(x, y);
      WritePixel(sum_at(x, y), n, plan.allocated.empty() && n > plan.base, image.pixel(x, y));
      if (!splats) continue;
      // Under edge anti-aliasing the pixels it left with the base samples are smooth.
      splats->Resolve(x, y, [&](int qx, int qy) {
        const std::uint32_t m = samples_at(qx, qy);
        return FilterSplats::Source{m, !plan.detect_edges || m > plan.base, sum_at(qx, qy).data()};
      }, image.pixel(x, y));
    }
  report();
  return image;
}

}  // namespace farm
