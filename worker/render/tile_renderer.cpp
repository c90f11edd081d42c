#include "render/tile_renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <stdexcept>
#include <string>

#include "render/integrator.h"
#include "sampling/pixel_sampler.h"
#include "scene/scene_data.h"

namespace farm {

Image RenderTile(const Scene& scene, const PixelRect& rect, std::stop_token stop) {
  const SceneData& data = scene.data();
  if (!PixelRect{0, 0, data.width, data.height}.Contains(rect) || rect.width < 0 ||
      rect.height < 0)
    throw std::invalid_argument("RenderTile: rect (" + std::to_string(rect.x) + ", " +
                                std::to_string(rect.y) + ", " + std::to_string(rect.width) + "x" +
                                std::to_string(rect.height) + ") is not inside the " +
                                std::to_string(data.width) + "x" + std::to_string(data.height) +
                                " image");
  Image image(rect, RgbaChannels());
  const DirectLightingIntegrator integrator(data);
  const uint32_t spp = data.samples_per_pixel;

  // Rows are the unit of parallel work and of cancellation. A pixel's samples are summed in
  // sample order by one thread, so the result is independent of the partition.
  tbb::parallel_for(tbb::blocked_range<int>(rect.y, rect.y_end()),
                    [&](const tbb::blocked_range<int>& rows) {
                      PixelSampler sampler(spp, data.seed);
                      for (int y = rows.begin(); y < rows.end(); ++y) {
                        if (stop.stop_requested()) return;
                        for (int x = rect.x; x < rect.x_end(); ++x) {
                          const uint64_t pixel_index = uint64_t(y) * uint64_t(data.width) + x;
                          double r = 0, g = 0, b = 0, a = 0;
                          for (uint32_t s = 0; s < spp; ++s) {
                            sampler.StartPixelSample(pixel_index, s);
                            const Vec2 u = sampler.Get2D();  // box filter over the pixel
                            const Ray ray = data.camera.GenerateRay({x + u.x, y + u.y});
                            const SampleResult sample = integrator.Li(ray, sampler);
                            r += sample.radiance.r;
                            g += sample.radiance.g;
                            b += sample.radiance.b;
                            a += sample.alpha;
                          }
                          // Alpha is the covered fraction of the pixel: 1 where every
                          // sample hit, 0 where all missed, fractional on silhouettes.
                          float* out = image.pixel(x, y);
                          out[0] = static_cast<float>(r / spp);
                          out[1] = static_cast<float>(g / spp);
                          out[2] = static_cast<float>(b / spp);
                          out[3] = static_cast<float>(a / spp);
                        }
                      }
                    });
  return image;
}

}  // namespace farm
