#pragma once

// Helpers for the integrator's tests (not linked into the worker): the photon maps a tile
// sees, and the mean of camera samples over the centre of the image.

#include <cstdint>
#include <vector>

#include "render/integrator.h"
#include "sampling/pixel_sampler.h"

namespace farm::testing {

// The maps of a tile that has `global` (may be null) and no caustic map, estimated as the
// scene says; final gathering reads global's own irradiance, if it has some, at every photon.
inline PhotonMaps MapsOf(const SceneData& data, const PhotonMap* global) {
  PhotonMaps maps;
  maps.global = global;
  if (global && global->has_irradiance()) maps.irradiance = global;
  maps.global_estimate = ToRadianceEstimate(data.photons.global_estimate);
  maps.caustic_estimate = ToRadianceEstimate(data.photons.caustic_estimate);
  return maps;
}

// The mean of `samples` camera samples of each pixel of a pixels x pixels block at the image
// centre (radiance, emitted, direct, indirect, caustic, volume, bias and alpha).
inline SampleResult MeanOverCentre(const SceneData& data, const PhotonMappingIntegrator& integrator, int pixels,
                                   uint32_t samples) {
  PixelSampler sampler(samples, data.seed);
  std::vector<PhotonNeighbour> scratch;
  SampleResult mean;
  int n = 0;
  for (int y = data.height / 2 - pixels / 2; y < data.height / 2 + pixels / 2; ++y)
    for (int x = data.width / 2 - pixels / 2; x < data.width / 2 + pixels / 2; ++x)
      for (uint32_t s = 0; s < samples; ++s) {
        sampler.StartPixelSample(uint64_t(y) * data.width + x, s);
        const Vec2 u = sampler.Get2D();
        const SampleResult r = integrator.Li(data.camera.GenerateRay({x + u.x, y + u.y}), sampler, scratch);
        mean.radiance += r.radiance;
        mean.emitted += r.emitted;
        mean.direct += r.direct;
        mean.indirect += r.indirect;
        mean.caustic += r.caustic;
        mean.volume += r.volume;
        mean.bias += r.bias;
        mean.alpha += r.alpha;
        ++n;
      }
  for (Rgb* term : {&mean.radiance, &mean.emitted, &mean.direct, &mean.indirect, &mean.caustic, &mean.volume,
                    &mean.bias})
    *term = *term / float(n);
  mean.alpha /= float(n);
  return mean;
}

}  // namespace farm::testing
