#pragma once

// For the in-process benchmarks: a scene file loaded and built without a blob store,
// pixels rendered as the tile renderer draws them, and the error between two images
// (photon maps traced into memory: photon/test_photons.h).

#include <google/protobuf/util/json_util.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "photon/test_photons.h"
#include "render/integrator.h"
#include "renderfarm/v1/scene.pb.h"
#include "scene/scene.h"

namespace farm::bench {

namespace pb = renderfarm::v1;

inline pb::Scene LoadScene(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::stringstream text;
  text << in.rdbuf();
  pb::Scene s;
  const auto status = google::protobuf::util::JsonStringToMessage(text.str(), &s);
  if (!status.ok()) throw std::runtime_error(path + ": " + status.ToString());
  return s;
}

inline Scene BuildScene(const pb::Scene& s) {
  return Scene::Build(s, [](const std::string& d) -> std::string {
    throw std::runtime_error("no blob store in the benchmark: " + d);
  });
}

// The pixels (y * width + x) whose centre and four corners all see, first, a surface for
// which keep(hit) holds (hit empty where a ray sees nothing): a pixel wholly of what it
// measures, without a silhouette's edge.
template <typename Keep>
std::vector<int> PixelsWhere(const SceneData& data, const Keep& keep) {
  std::vector<int> pixels;
  for (int y = 0; y < data.height; ++y)
    for (int x = 0; x < data.width; ++x) {
      bool all = true;
      for (const Vec2 o : {Vec2{0.5f, 0.5f}, {0, 0}, {1, 0}, {0, 1}, {1, 1}})
        all = all && keep(data.Intersect(data.camera.GenerateRay({x + o.x, y + o.y})));
      if (all) pixels.push_back(y * data.width + x);
    }
  return pixels;
}

// The mean beauty of samples [0, count) of each pixel (indices y * width + x), drawn as the
// tile renderer draws them (a box filter over the pixel), with sampler seed `seed`;
// seconds receives the wall time.
inline std::vector<Rgb> RenderPixels(const SceneData& data, const PhotonMappingIntegrator& integrator,
                                     const std::vector<int>& pixels, uint32_t count, uint64_t seed,
                                     double& seconds) {
  std::vector<Rgb> out(pixels.size());
  const auto start = std::chrono::steady_clock::now();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pixels.size(), 16), [&](const auto& range) {
    PixelSampler sampler(count, seed);
    std::vector<PhotonNeighbour> scratch;
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const int x = pixels[i] % data.width, y = pixels[i] / data.width;
      Rgb sum;
      for (uint32_t s = 0; s < count; ++s) {
        sampler.StartPixelSample(uint64_t(pixels[i]), s);
        const Vec2 u = sampler.Get2D();
        sum += integrator.Li(data.camera.GenerateRay({x + u.x, y + u.y}), sampler, scratch).radiance;
      }
      out[i] = sum / float(count);
    }
  });
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

// The mean over pixels and channels of (a - b)^2.
inline double SquaredError(const std::vector<Rgb>& a, const std::vector<Rgb>& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (const auto channel : {&Rgb::r, &Rgb::g, &Rgb::b}) {
      const double d = double(a[i].*channel) - double(b[i].*channel);
      sum += d * d;
    }
  }
  return sum / (3.0 * double(a.size()));
}

}  // namespace farm::bench
