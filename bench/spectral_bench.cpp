// Issue 18, acceptance 2 and 5: spectral mode (Sampling.spectral ALWAYS: every photon and
// camera path at eight wavelengths, colours uplifted to spectra) against RGB mode (AUTO, on
// a scene without dispersion: RGB throughout), in process, on the same scene.
//
// A round here is what a farm round does for its tiles: trace the round's own global and
// caustic photons into in-memory maps, precompute irradiance at the global photons, render
// every pixel at `samples` camera samples with its own sampler seed; its time is all of
// that. Radii stay fixed, so the rounds' mean converges to each mode's own photon-mapped
// image and the error below is the estimate's noise.
//
// Prints:
// - the relative MSE between the two modes' converged images (the mean of
//   reference_rounds rounds each): mean over pixels and channels of (spectral - rgb)^2 /
//   (rgb^2 + 0.01), with target at most 0.005 (acceptance 2), and the part of it the two
//   references' own noise explains (from each reference's two halves), and each channel's
//   mean ratio spectral / RGB;
// - each mode's RMSE against its own converged image after `rounds` independent rounds,
//   less the reference's noise (the rounds' error is their variance plus the reference's,
//   rounds / reference_rounds of it), and the time those rounds took; then the cost of
//   spectral mode at equal error: the ratio of times to reach the same RMSE,
//   (t_spectral e_spectral^2) / (t_rgb e_rgb^2), as error falls as 1 / sqrt(time)
//   (acceptance 5). A figure, not a test: nothing here fails on a busy machine.
//
//   farm_bench_spectral [scene.json [size [samples [reference_rounds [rounds]]]]]
//   (default scenes/cornell-box.json 64 4 16 4)

#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "in_process.h"
#include "photon/irradiance_precompute.h"
#include "sampling/hash.h"

namespace {

namespace pb = renderfarm::v1;
using farm::Rgb;

struct Rounds {
  std::vector<Rgb> mean;
  double seconds = 0;
};

// Rounds [first, first + count) of `scene`, each with its own photons and sampler seed, and
// the mean of their images.
Rounds Render(const farm::Scene& scene, const std::vector<int>& pixels, uint32_t samples, uint64_t first,
              uint64_t count) {
  const farm::SceneData& data = scene.data();
  const uint64_t global_paths = data.photons.global_photons, caustic_paths = data.photons.caustic_photons;
  Rounds out;
  out.mean.assign(pixels.size(), Rgb());
  for (uint64_t r = first; r < first + count; ++r) {
    const auto start = std::chrono::steady_clock::now();
    auto global = farm::testing::TraceIntoMemory(scene, farm::PhotonMapKind::kGlobal, global_paths, r * global_paths);
    auto caustic = farm::testing::TraceIntoMemory(scene, farm::PhotonMapKind::kCaustic, caustic_paths, r * caustic_paths);
    if (global) global->set_irradiance(farm::ComputeIrradiance(data, *global, caustic.get(), 0, global->size(), 1.0));
    farm::PhotonMaps maps;
    maps.global = maps.irradiance = global.get();
    maps.caustic = caustic.get();
    maps.global_estimate = farm::ToRadianceEstimate(data.photons.global_estimate);
    maps.caustic_estimate = farm::ToRadianceEstimate(data.photons.caustic_estimate);
    const farm::PhotonMappingIntegrator integrator(data, maps);
    double render_seconds = 0;
    const std::vector<Rgb> image =
        farm::bench::RenderPixels(data, integrator, pixels, samples, farm::Hash(data.seed, r), render_seconds);
    out.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (std::size_t i = 0; i < image.size(); ++i) out.mean[i] += image[i] / float(count);
  }
  return out;
}

// The pixels (y * width + x) whose centre and four corners see no emitter first: a light
// seen directly (and its edges, where a pixel's few samples decide how much of it is
// seen) would swamp every figure. Its light is in every other pixel.
std::vector<int> PixelsSeeingNoEmitter(const farm::SceneData& data) {
  return farm::bench::PixelsWhere(data, [&data](const auto& hit) { return !(hit && data.capabilities_of(*hit).emits); });
}

double RelativeMse(const std::vector<Rgb>& a, const std::vector<Rgb>& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (const auto channel : {&Rgb::r, &Rgb::g, &Rgb::b}) {
      const double d = double(a[i].*channel) - double(b[i].*channel), v = b[i].*channel;
      sum += d * d / (v * v + 0.01);
    }
  return sum / (3.0 * double(a.size()));
}

std::vector<Rgb> MeanOf(const std::vector<Rgb>& a, const std::vector<Rgb>& b) {
  std::vector<Rgb> out(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) out[i] = (a[i] + b[i]) * 0.5f;
  return out;
}

Rgb ChannelMeans(const std::vector<Rgb>& a) {
  Rgb sum;
  for (const Rgb& c : a) sum += c;
  return sum / float(a.size());
}

struct Mode {
  const char* name;
  pb::SpectralSampling spectral;
  std::vector<Rgb> reference;
  double noise = 0;  // relMSE of the reference against the truth it converges to
  double rmse = 0, seconds = 0;
};

}  // namespace

int main(int argc, char** argv) try {
  const std::string path = argc > 1 ? argv[1] : PHOTONFARM_DEFAULT_SCENE;
  const int size = argc > 2 ? std::stoi(argv[2]) : 64;
  const uint32_t samples = argc > 3 ? uint32_t(std::stoul(argv[3])) : 4;
  const uint64_t reference_rounds = argc > 4 ? std::stoull(argv[4]) : 16;
  const uint64_t rounds = argc > 5 ? std::stoull(argv[5]) : 4;
  if (reference_rounds < 2 || rounds < 1) throw std::invalid_argument("reference_rounds >= 2 and rounds >= 1");
  pb::Scene description = farm::bench::LoadScene(path);
  description.mutable_film()->set_width(size);
  description.mutable_film()->set_height(size);
  const farm::Scene plain = farm::bench::BuildScene(description);
  const farm::PhotonSettings& photons = plain.data().photons;
  const std::vector<int> pixels = PixelsSeeingNoEmitter(plain.data());
  std::printf("scene %s at %dx%d, %u samples a pixel a round, %llu global and %llu caustic paths a round; "
              "figures over the %zu pixels that see no emitter\n",
              path.c_str(), size, size, samples, (unsigned long long)photons.global_photons,
              (unsigned long long)photons.caustic_photons, pixels.size());

  Mode modes[] = {{"RGB (AUTO)", pb::SPECTRAL_SAMPLING_AUTO, {}}, {"spectral (ALWAYS)", pb::SPECTRAL_SAMPLING_ALWAYS, {}}};
  for (Mode& mode : modes) {
    description.mutable_sampling()->set_spectral(mode.spectral);
    const farm::Scene scene = farm::bench::BuildScene(description);
    // The converged image from rounds far from the measured ones, in two halves.
    const uint64_t half = reference_rounds / 2, far = 1'000'000;
    const Rounds a = Render(scene, pixels, samples, far, half);
    const Rounds b = Render(scene, pixels, samples, far + half, half);
    mode.reference = MeanOf(a.mean, b.mean);
    mode.noise = RelativeMse(a.mean, b.mean) / 4;  // each half's variance is twice the mean's
    const Rounds measured = Render(scene, pixels, samples, 1, rounds);
    const double raw = farm::bench::SquaredError(measured.mean, mode.reference);
    mode.rmse = std::sqrt(raw / (1 + double(rounds) / double(2 * half)));
    mode.seconds = measured.seconds;
    std::printf("%-18s converged image: %llu rounds in %.1f s; %llu rounds: RMSE %.5f against it (%.5f before "
                "taking out its noise) in %.2f s (%.3f s a round)\n",
                mode.name, (unsigned long long)(2 * half), a.seconds + b.seconds, (unsigned long long)rounds,
                mode.rmse, std::sqrt(raw), mode.seconds, mode.seconds / double(rounds));
  }
  const Mode& rgb = modes[0];
  const Mode& spectral = modes[1];
  const double rel = RelativeMse(spectral.reference, rgb.reference);
  const Rgb ms = ChannelMeans(spectral.reference), mr = ChannelMeans(rgb.reference);
  std::printf("converged spectral against RGB: relMSE %.5f (target <= 0.005: %s), of which the references' own "
              "noise %.5f; channel means spectral / RGB %.4f %.4f %.4f\n",
              rel, rel <= 0.005 ? "PASS" : "MISSED", spectral.noise + rgb.noise, ms.r / mr.r, ms.g / mr.g,
              ms.b / mr.b);
  const double cost = (spectral.seconds * spectral.rmse * spectral.rmse) / (rgb.seconds * rgb.rmse * rgb.rmse);
  std::printf("cost of spectral mode at equal error (time to the same RMSE, spectral / RGB): %.2f (time a round "
              "%.2f, variance %.2f)\n",
              cost, spectral.seconds / rgb.seconds, (spectral.rmse * spectral.rmse) / (rgb.rmse * rgb.rmse));
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "farm_bench_spectral: %s\n", e.what());
  return 2;
}
