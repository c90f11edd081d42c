#include "render/tile_renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <stdexcept>
#include <string>

#include "render/integrator.h"
#include "sampling/pixel_sampler.h"
#include "scene/scene_data.h"

namespace farm {
namespace {

// Channel offsets in RenderChannels() order.
enum Channel : int {
  kBeauty = 0,    // R G B, then A at 3
  kAlpha = 3,
  kDirect = 4,
  kIndirect = 7,
  kCaustic = 10,
  kAlbedo = 13,
  kNormal = 16,
  kDepth = 19,
  kChannelCount = 20,
};

PhotonMaps MapsOf(const SceneData& data, const PhotonSnapshot* photons) {
  PhotonMaps maps;
  if (photons) {
    maps.global = photons->map(PhotonMapKind::kGlobal);
    maps.caustic = photons->map(PhotonMapKind::kCaustic);
  }
  maps.global_estimate = ToRadianceEstimate(data.photons.global_estimate);
  maps.caustic_estimate = ToRadianceEstimate(data.photons.caustic_estimate);
  return maps;
}

void Add(std::array<double, kChannelCount>& sum, int at, const Rgb& c) {
  sum[at] += c.r;
  sum[at + 1] += c.g;
  sum[at + 2] += c.b;
}

}  // namespace

std::vector<std::string> RenderChannels() {
  return {"R",          "G",          "B",          "A",         "direct.R",  "direct.G",
          "direct.B",   "indirect.R", "indirect.G", "indirect.B", "caustic.R", "caustic.G",
          "caustic.B",  "albedo.R",   "albedo.G",   "albedo.B",  "normal.X",  "normal.Y",
          "normal.Z",   "depth.Z"};
}

Image RenderTile(const Scene& scene, const PhotonSnapshot* photons, const PixelRect& rect,
                 std::stop_token stop) {
  const SceneData& data = scene.data();
  if (!PixelRect{0, 0, data.width, data.height}.Contains(rect) || rect.width < 0 ||
      rect.height < 0)
    throw std::invalid_argument("RenderTile: rect (" + std::to_string(rect.x) + ", " +
                                std::to_string(rect.y) + ", " + std::to_string(rect.width) + "x" +
                                std::to_string(rect.height) + ") is not inside the " +
                                std::to_string(data.width) + "x" + std::to_string(data.height) +
                                " image");
  Image image(rect, RenderChannels());
  const PhotonMappingIntegrator integrator(data, MapsOf(data, photons));
  const uint32_t spp = data.samples_per_pixel;

  // Rows are the unit of parallel work and of cancellation. A pixel's samples are summed in
  // sample order by one thread, so the result is independent of the partition.
  tbb::parallel_for(
      tbb::blocked_range<int>(rect.y, rect.y_end()), [&](const tbb::blocked_range<int>& rows) {
        PixelSampler sampler(spp, data.seed);
        std::vector<PhotonNeighbour> scratch;
        for (int y = rows.begin(); y < rows.end(); ++y) {
          if (stop.stop_requested()) return;
          for (int x = rect.x; x < rect.x_end(); ++x) {
            const uint64_t pixel_index = uint64_t(y) * uint64_t(data.width) + x;
            std::array<double, kChannelCount> sum{};
            for (uint32_t s = 0; s < spp; ++s) {
              sampler.StartPixelSample(pixel_index, s);
              const Vec2 u = sampler.Get2D();  // box filter over the pixel
              const Ray ray = data.camera.GenerateRay({x + u.x, y + u.y});
              const SampleResult r = integrator.Li(ray, sampler, scratch);
              Add(sum, kBeauty, r.radiance);
              sum[kAlpha] += r.alpha;
              Add(sum, kDirect, r.direct);
              Add(sum, kIndirect, r.indirect);
              Add(sum, kCaustic, r.caustic);
              Add(sum, kAlbedo, r.albedo);
              if (r.alpha > 0) {
                sum[kNormal] += r.normal.x;
                sum[kNormal + 1] += r.normal.y;
                sum[kNormal + 2] += r.normal.z;
                sum[kDepth] += r.depth;
              }
            }
            // Light and albedo average over all samples (alpha is the covered fraction);
            // normal and depth over the samples that hit something, so an edge pixel's depth
            // is a real distance, not one diluted by the background.
            float* out = image.pixel(x, y);
            const double hits = sum[kAlpha];
            for (int c = 0; c < kChannelCount; ++c) {
              const bool geometric = c >= kNormal;
              const double n = geometric ? hits : double(spp);
              out[c] = n > 0 ? static_cast<float>(sum[c] / n) : 0.0f;
            }
          }
        }
      });
  return image;
}

}  // namespace farm
