// Pixel filters against closed forms: the image of a straight emitter edge, filtered, is
// the edge's step convolved with the filter's profile (the filter is separable, and the
// step varies along x only); and at equal samples the Gaussian's error is lower.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "render/tile_renderer.h"
#include "scene/scene_data.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

constexpr int kWidth = 32, kHeight = 8;
constexpr double kEdgeX = 13.3;  // in pixels from the image's left
constexpr float kRadiance = 2;

// An emitter facing the camera fills the image right of x = edge_x (image coordinates)
// and black space the rest; sampled `spp` times a pixel without edge anti-aliasing.
pb::Scene EdgeScene(uint32_t spp, double edge_x = kEdgeX, int height = kHeight) {
  const double distance = 10, fov = 40;
  pb::Scene s = MakeScene(kWidth, height, {0, 0, -distance}, {0, 0, 0}, {0, 1, 0}, fov, spp, 3);
  s.mutable_antialiasing()->set_mode(pb::ANTIALIASING_MODE_NONE);
  AddEmissive(s, "lamp", Rgb(kRadiance));
  // The image's right is cross(forward, up) = -x; film x maps to that axis linearly on the
  // plane z = 0 (camera.cpp): right = (2 x / width - 1) tan(fov / 2) aspect distance.
  const double tan_half = std::tan(fov / 2 * std::numbers::pi / 180);
  const double edge_right = (2 * edge_x / kWidth - 1) * tan_half * kWidth / height * distance;
  const double far = 100, tall = 100;
  // Faces -z (cross(u, v)), spanning right >= edge_right, that is x <= -edge_right.
  AddQuad(s, "lamp", {-edge_right - far, -tall, 0}, {0, 2 * tall, 0}, {far, 0, 0});
  return s;
}

Image RenderEdge(uint32_t spp, void (*set)(pb::PixelFilter*)) {
  pb::Scene s = EdgeScene(spp);
  set(s.mutable_film()->mutable_filter());
  return RenderTile(Scene::Build(s, NoBlobs()), nullptr, {0, 0, kWidth, kHeight});
}

// Over the middle row's pixels: the largest |value - expected(centre x)| of beauty and
// alpha, expected the fraction of the filter's weight on the lit side.
template <typename Expected>
double WorstError(const Image& image, Expected lit_share) {
  double worst = 0;
  const int y = kHeight / 2;
  for (int x = 0; x < kWidth; ++x) {
    const double share = lit_share(x + 0.5);
    worst = std::max(worst, std::abs(image.pixel(x, y)[0] - kRadiance * share));
    worst = std::max(worst, std::abs(image.pixel(x, y)[3] - share) * kRadiance);
  }
  return worst;
}

TEST(PixelFilterEdge, TheBoxOfHalfAPixelGivesEachPixelItsCoveredFraction) {
  const Image image = RenderEdge(256, [](pb::PixelFilter*) {});
  const double worst = WorstError(image, [](double centre) { return std::clamp(centre + 0.5 - kEdgeX, 0.0, 1.0); });
  std::printf("box: largest error %.5f of radiance %.1f\n", worst, kRadiance);
  EXPECT_LT(worst, 0.005 * kRadiance);
  EXPECT_EQ(image.pixel(12, 4)[0], 0.0f);  // wholly dark
  EXPECT_EQ(image.pixel(14, 4)[0], kRadiance);
}

// The Gaussian of radius r and sigma s: the share of its weight at offsets above a is
// (s sqrt(pi / 2) (erf(r / (s sqrt 2)) - erf(a / (s sqrt 2))) - (r - a) exp(-r^2 / 2 s^2))
// over the same for a = -r.
double GaussianUpperShare(double a, double r, double s) {
  a = std::clamp(a, -r, r);
  const auto upper = [&](double from) {
    return s * std::sqrt(std::numbers::pi / 2) * (std::erf(r / (s * std::numbers::sqrt2)) - std::erf(from / (s * std::numbers::sqrt2))) -
           (r - from) * std::exp(-r * r / (2 * s * s));
  };
  return upper(a) / upper(-r);
}

TEST(PixelFilterEdge, AGaussianFilteredEdgeIsTheStepConvolvedWithTheGaussian) {
  for (const auto& [radius, sigma] : {std::pair{1.5, 0.5}, {2.0, 0.5}, {2.0, 0.8}}) {
    pb::Scene s = EdgeScene(256);
    s.mutable_film()->mutable_filter()->mutable_gaussian()->set_radius(radius);
    s.mutable_film()->mutable_filter()->mutable_gaussian()->set_sigma(sigma);
    const Image image = RenderTile(Scene::Build(s, NoBlobs()), nullptr, {0, 0, kWidth, kHeight});
    const double worst = WorstError(image, [&](double centre) { return GaussianUpperShare(kEdgeX - centre, radius, sigma); });
    std::printf("gaussian radius %.1f sigma %.1f: largest error %.5f of radiance %.1f\n", radius, sigma, worst, kRadiance);
    EXPECT_LT(worst, 0.005 * kRadiance) << radius << " " << sigma;
  }
}

// Mitchell's negative lobes overshoot on both sides of the edge: the pixels 1 to 2 pixels
// into the dark side come out slightly negative, and are kept so (docs/pixel-filters.md).
TEST(PixelFilterEdge, AMitchellFilteredEdgeRingsAsItsProfileSays) {
  const PixelFilter mitchell(PixelFilterKind::kMitchell, 2);
  const Image image = RenderEdge(256, [](pb::PixelFilter* f) { f->mutable_mitchell(); });
  const double worst = WorstError(image, [&](double centre) { return mitchell.Integral(kEdgeX - centre, 10); });
  std::printf("mitchell: largest error %.5f of radiance %.1f\n", worst, kRadiance);
  EXPECT_LT(worst, 0.005 * kRadiance);
  // Centre 11.5 is 1.8 pixels from the edge: in the negative lobe.
  EXPECT_LT(mitchell.Integral(kEdgeX - 11.5, 10), 0);
  EXPECT_LT(image.pixel(11, 4)[0], 0.0f);
}

// At equal samples the Gaussian's image of an edge is closer to the step convolved with it
// than the box's is to the step box-filtered: each pixel weighs the samples of its
// neighbours too. RMSE over the 8 columns about edges at four sub-pixel offsets, 64 rows
// each, against the closed forms, with 4, 12 and 128 samples a pixel and with edge
// anti-aliasing's 1 and 12 at edges (where the pixels it judged smooth count by their mean,
// render/filter_splats.h: weighed by their lone sample's position, the ratio was 1.09).
// Near 1.6, under the bound of independently placed samples, 1 / integral of f^2 = 1.77
// (docs/pixel-filters.md). At 128 samples it is 1.65 because the film sampler stratifies
// samples across pixels: the box's error at this axis-aligned edge falls about as 1/n
// (each pixel's samples are stratified in x), and the filter's as fast only if the samples
// of the pixels it spans are stratified together (drawn per pixel, the ratio was 1.54 at
// 128 samples and 1.46 at 256).
TEST(PixelFilterEdge, AtEqualSamplesTheGaussianIsCloserToItsStepThanTheBoxToItsOwn) {
  struct Sampling {
    uint32_t spp;
    pb::AntialiasingMode mode;
    double least;  // the smallest ratio box / Gaussian accepted
  };
  for (const Sampling sampling : {Sampling{4, pb::ANTIALIASING_MODE_NONE, 1.4},
                                  Sampling{12, pb::ANTIALIASING_MODE_NONE, 1.4},
                                  Sampling{128, pb::ANTIALIASING_MODE_NONE, 1.6},
                                  Sampling{1, pb::ANTIALIASING_MODE_EDGES, 1.4}}) {
    double box2 = 0, gaussian2 = 0;
    for (const double edge : {13.3, 13.55, 13.8, 14.05}) {
      const int height = 64;
      pb::Scene s = EdgeScene(sampling.spp, edge, height);
      s.mutable_antialiasing()->set_mode(sampling.mode);
      const Image box = RenderTile(Scene::Build(s, NoBlobs()), nullptr, {0, 0, kWidth, height});
      s.mutable_film()->mutable_filter()->mutable_gaussian()->set_radius(2);
      const Image gaussian = RenderTile(Scene::Build(s, NoBlobs()), nullptr, {0, 0, kWidth, height});
      for (int y = 0; y < height; ++y)
        for (int x = 10; x < 18; ++x) {
          const double centre = x + 0.5;
          box2 += std::pow(box.pixel(x, y)[0] - kRadiance * std::clamp(centre + 0.5 - edge, 0.0, 1.0), 2);
          gaussian2 += std::pow(gaussian.pixel(x, y)[0] - kRadiance * GaussianUpperShare(edge - centre, 2, 0.5), 2);
        }
    }
    const double ratio = std::sqrt(box2 / gaussian2);
    std::printf("%u samples a pixel, antialiasing mode %d: RMSE box / Gaussian %.2f\n", sampling.spp, sampling.mode,
                ratio);
    EXPECT_GT(ratio, sampling.least) << sampling.spp << " mode " << sampling.mode;
  }
}

}  // namespace
}  // namespace farm
