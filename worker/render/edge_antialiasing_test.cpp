// Edge anti-aliasing in RenderTile, checked against independent ground truth: the base pass
// and the fully supersampled render of the same scene, and the scene's surfaces and light
// worked out here from its geometry.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <numbers>
#include <vector>

#include "image/reference_exr.h"
#include "sampling/film_sampler.h"
#include "sampling/pixel_sampler.h"
#include "render/edge_detect.h"
#include "render/integrator.h"
#include "render/thin_bars_scene.h"
#include "render/tile_renderer.h"

namespace farm {
namespace {

using namespace farm::testing;

constexpr int kW = 64, kH = 48;
const int kEdgeChannel = RenderChannelIndex("edge.Y");

Scene Bars(pb::AntialiasingMode mode, uint32_t edges = 12, double threshold = 0) {
  pb::Scene s = ThinBarsScene(kW, kH, mode, edges);
  s.mutable_antialiasing()->set_edge_threshold(threshold);
  return Scene::Build(s, NoBlobs());
}

bool SamePixel(const Image& a, const Image& b, int x, int y) {
  return std::memcmp(a.pixel(x, y), b.pixel(x, y), a.channel_count() * sizeof(float)) == 0;
}

// Every pixel of the tiles equals, bit for bit, the whole-image render: all channels, the
// edge mask included.
void ExpectTilesStitch(const Scene& scene, const RoundSettings& round, int tile) {
  const Image whole = RenderTile(scene, nullptr, {0, 0, kW, kH}, round);
  for (int ty = 0; ty < kH; ty += tile)
    for (int tx = 0; tx < kW; tx += tile) {
      const PixelRect r{tx, ty, std::min(tile, kW - tx), std::min(tile, kH - ty)};
      const Image part = RenderTile(scene, nullptr, r, round);
      for (int y = r.y; y < r.y_end(); ++y)
        for (int x = r.x; x < r.x_end(); ++x)
          ASSERT_TRUE(SamePixel(whole, part, x, y)) << "pixel " << x << ", " << y << " of tile "
                                                    << tx << ", " << ty;
    }
}

TEST(EdgeAntialiasing, TilesStitchBitForBitIntoTheWholeImage) {
  const Scene scene = Bars(pb::ANTIALIASING_MODE_EDGES);
  ExpectTilesStitch(scene, {}, 16);
  ExpectTilesStitch(scene, {}, 7);  // tile borders cut edges at every offset
  ExpectTilesStitch(scene, {.radius_scale = 0.5, .first_sample = 3}, 13);
}

// A base sample: its camera ray and what the integrator made of it.
struct BaseSample {
  Ray ray;
  SampleResult result;
};

// The base pass alone, drawn here as the tile renderer draws it: the bars take 1 sample a
// pixel, sample 0 of the film sampler and of the pixel sampler whose permutation domain is
// the 12 samples of an edge pixel, keyed by the scene seed in round 1. With pilots, the
// edge pilots instead: samples 0 to kEdgePilots - 1 of the set keyed by EdgePilotSeed
// (domain kEdgePilots), their cues, kEdgePilots a pixel.
std::vector<BaseSample> BasePass(bool pilots = false) {
  const Scene scene = Bars(pb::ANTIALIASING_MODE_EDGES);
  const SceneData& data = scene.data();
  const PhotonMappingIntegrator integrator(data, PhotonMaps{});
  const FilmSampler film(kW, kH);
  const uint64_t seed = pilots ? EdgePilotSeed(data.seed) : data.seed;
  const uint32_t per_pixel = pilots ? kEdgePilots : 1;
  PixelSampler sampler(pilots ? kEdgePilots : 12, seed);
  std::vector<PhotonNeighbour> scratch;
  std::vector<BaseSample> base;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (uint32_t j = 0; j < per_pixel; ++j) {
        sampler.StartPixelSample(uint64_t(y) * kW + x, j);
        const Vec2 u = film.Sample(x, y, j, seed);
        const Ray ray = data.camera.GenerateRay({x + u.x, y + u.y});
        base.push_back({ray, pilots ? integrator.Cues(ray, sampler) : integrator.Li(ray, sampler, scratch)});
      }
  return base;
}

// The bars scene's parallelograms, the floor first, read back from its description.
struct Quad {
  Vec3d o, u, v;
};

std::vector<Quad> BarsQuads() {
  std::vector<Quad> quads;
  const auto v = [](const pb::Vec3& p) { return Vec3d(p.x(), p.y(), p.z()); };
  const pb::Scene scene = ThinBarsScene(kW, kH, pb::ANTIALIASING_MODE_EDGES, 12);
  for (const pb::Shape& s : scene.shapes())
    quads.push_back({v(s.quad().origin()), v(s.quad().edge_u()), v(s.quad().edge_v())});
  return quads;
}

// What a ray from o along d meets first before t_max, worked out in double precision:
// the quad's index (-1 for none), the distance, and how near (in scene units) the ray
// passes to the outline of any quad whose plane it crosses in range, below which float
// arithmetic may decide otherwise.
struct AnalyticHit {
  int quad = -1;
  double t = 0;
  double margin = std::numeric_limits<double>::infinity();
};

AnalyticHit FirstHit(const std::vector<Quad>& quads, const Vec3d& o, const Vec3d& d, double t_max) {
  AnalyticHit hit;
  hit.t = t_max;
  for (int i = 0; i < int(quads.size()); ++i) {
    const Quad& q = quads[i];
    const Vec3d n = Cross(q.u, q.v);
    const double t = Dot(q.o - o, n) / Dot(d, n);
    if (!(t > 1e-6 && t < t_max - 1e-6)) continue;
    const Vec3d w = o + d * t - q.o;
    const double a = Dot(Cross(w, q.v), n) / Dot(n, n), b = Dot(Cross(q.u, w), n) / Dot(n, n);
    // Signed distances to the quad along u and along v, positive outside (the quads are
    // rectangles): the larger is the distance to its outline.
    const auto outside = [](double c, double length) { return std::max(-c, c - 1) * length; };
    const double d_outline = std::max(outside(a, Length(q.u)), outside(b, Length(q.v)));
    hit.margin = std::min(hit.margin, std::abs(d_outline));
    if (d_outline > 0) continue;
    // Bars at one height overlap: which of two coplanar quads a renderer reports is not
    // the geometry's to say.
    if (hit.quad >= 0 && std::abs(t - hit.t) < 1e-4) hit.margin = 0;
    if (t < hit.t) hit = {i, t, hit.margin};
  }
  return hit;
}

// The analytic cues of a base sample: the quad its ray hits, and the point light's
// irradiance there (intensity 40 at (1.5, 6, 2), shadowed by the quads; every quad faces
// +y, the camera's side); close is set where float arithmetic may decide otherwise.
struct AnalyticCues {
  int quad = -1;
  double irradiance = 0;
  bool close = false;
};

AnalyticCues Analytic(const std::vector<Quad>& quads, const Ray& ray) {
  const Vec3d o(ray.origin), d(ray.direction);
  const AnalyticHit hit = FirstHit(quads, o, d, 1e9);
  AnalyticCues c{hit.quad, 0, hit.margin < 1e-3};
  if (hit.quad < 0) return c;
  const Vec3d p = o + d * hit.t, to_light = Vec3d(1.5, 6, 2) - p;
  const double r = Length(to_light);
  const AnalyticHit shadow = FirstHit(quads, p, to_light / r, r);
  c.close = c.close || shadow.margin < 1e-3;
  if (shadow.quad < 0) c.irradiance = 40 * std::max(0.0, to_light.y / r) / (r * r);
  return c;
}

// The integrator's cues on the base pass are the analytic ones: one surface id per quad,
// the same id exactly where the quad is the same, and the light's irradiance.
TEST(EdgeAntialiasing, TheBasePassCuesAreTheAnalyticSurfacesAndIrradiance) {
  const std::vector<BaseSample> base = BasePass();
  const std::vector<Quad> quads = BarsQuads();
  std::vector<AnalyticCues> truth;
  for (const BaseSample& b : base) truth.push_back(Analytic(quads, b.ray));
  int close = 0, shadowed = 0;
  std::map<int, std::uint32_t> id_of;  // quad -> the surface id its samples carry
  std::map<std::uint32_t, int> quad_of;
  for (std::size_t i = 0; i < base.size(); ++i) {
    const SampleResult& r = base[i].result;
    const AnalyticCues& t = truth[i];
    if (t.close) {
      ++close;
      continue;
    }
    EXPECT_EQ(r.surface == 0, t.quad < 0) << "sample " << i;
    if (t.quad >= 0) {
      EXPECT_EQ(id_of.emplace(t.quad, r.surface).first->second, r.surface) << "sample " << i;
      EXPECT_EQ(quad_of.emplace(r.surface, t.quad).first->second, t.quad) << "sample " << i;
    }
    shadowed += t.quad >= 0 && t.irradiance == 0;
    const double e = 0.2126 * r.light_irradiance.r + 0.7152 * r.light_irradiance.g + 0.0722 * r.light_irradiance.b;
    ASSERT_NEAR(e, t.irradiance, 1e-4 * t.irradiance + 1e-6) << "sample " << i;
  }
  EXPECT_EQ(id_of.size(), quads.size());  // the floor and every bar were seen
  EXPECT_GT(shadowed, kW * kH / 50);      // the bars' shadows are in view
  EXPECT_LT(close, kW * kH / 100);
}

// In the bars scene (a flat floor, flat bars above it, one sample per pixel) the surface
// cues reduce to a change of quad among the eight neighbours (the bars are flat and face up,
// so no crease or depth step adds to them), and the light cue is a Sobel of the point
// light's irradiance: both worked out here from the geometry.
TEST(EdgeAntialiasing, EdgePixelsAreWhereTheQuadOrTheLightsIrradianceChanges) {
  const std::vector<BaseSample> base = BasePass();
  const std::vector<Quad> quads = BarsQuads();
  std::vector<AnalyticCues> truth, pilot;
  for (const BaseSample& b : base) truth.push_back(Analytic(quads, b.ray));
  for (const BaseSample& b : BasePass(/*pilots=*/true)) pilot.push_back(Analytic(quads, b.ray));
  const Image aa = RenderTile(Bars(pb::ANTIALIASING_MODE_EDGES), nullptr, {0, 0, kW, kH});
  // Mirrored at the image border: column -1 reads column 1.
  const auto mirror = [](int v, int n) { return v < 0 ? -v : v >= n ? 2 * (n - 1) - v : v; };
  const auto at = [&](int x, int y) -> const AnalyticCues& {
    return truth[std::size_t(mirror(y, kH)) * kW + mirror(x, kW)];
  };
  // log(luminance + 1/256); the light is white.
  const auto f = [&](int x, int y) { return std::log(at(x, y).irradiance + 1.0 / 256); };
  int edges = 0, mismatches = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      // The eight neighbours and the pixel's pilot rays decide, never its own base sample.
      bool close = false, quad_changes = false;
      for (uint32_t j = 0; j < kEdgePilots; ++j) {
        const AnalyticCues& own = pilot[(std::size_t(y) * kW + x) * kEdgePilots + j];
        close = close || own.close;
        quad_changes = quad_changes || own.quad != at(x - 1, y).quad;
      }
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (dx == 0 && dy == 0) continue;
          close = close || at(x + dx, y + dy).close;
          quad_changes = quad_changes || at(x + dx, y + dy).quad != at(x - 1, y).quad;
        }
      double gx = 0, gy = 0;
      for (int d = -1; d <= 1; ++d) {
        const double w = d == 0 ? 2 : 1;
        gx += w * (f(x + 1, y + d) - f(x - 1, y + d));
        gy += w * (f(x + d, y + 1) - f(x + d, y - 1));
      }
      const double gradient = std::hypot(gx, gy) / 8;
      if (close || (std::abs(gradient - 0.1) < 1e-3 && !quad_changes)) continue;  // too close to call
      const bool edge = gradient > 0.1 || quad_changes;
      edges += edge;
      if ((aa.pixel(x, y)[kEdgeChannel] == 1.0f) != edge && mismatches++ < 5)
        ADD_FAILURE() << "pixel " << x << ", " << y << ": gradient " << gradient << ", quad "
                      << at(x, y).quad << (quad_changes ? " (changes)" : "");
    }
  EXPECT_EQ(mismatches, 0);
  // The bars cover a good part of the view, but edges are a minority of pixels.
  EXPECT_GT(edges, kW * kH / 20);
  EXPECT_LT(edges, kW * kH / 2);
}

TEST(EdgeAntialiasing, EdgePixelsEqualFullSupersamplingAndOthersTheBasePass) {
  const std::vector<BaseSample> base = BasePass();
  const Image full = RenderTile(Bars(pb::ANTIALIASING_MODE_FULL), nullptr, {0, 0, kW, kH});
  const Image aa = RenderTile(Bars(pb::ANTIALIASING_MODE_EDGES), nullptr, {0, 0, kW, kH});
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const bool edge = aa.pixel(x, y)[kEdgeChannel] == 1.0f;
      EXPECT_EQ(full.pixel(x, y)[kEdgeChannel], 1.0f);
      if (edge) {
        ASSERT_TRUE(SamePixel(aa, full, x, y)) << "pixel " << x << ", " << y << " (edge)";
        continue;
      }
      // One sample: the pixel is that sample's beauty (and its alpha).
      const Rgb& r = base[std::size_t(y) * kW + x].result.radiance;
      const float* p = aa.pixel(x, y);
      ASSERT_TRUE(p[0] == r.r && p[1] == r.g && p[2] == r.b) << "pixel " << x << ", " << y;
    }
}

TEST(EdgeAntialiasing, NoneModeSupersamplesNothing) {
  const Image none = RenderTile(Bars(pb::ANTIALIASING_MODE_NONE), nullptr, {0, 0, kW, kH});
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) ASSERT_EQ(none.pixel(x, y)[kEdgeChannel], 0.0f);
}

double BeautyRmse(const Image& a, const Image& b) { return LayerRmse(a, b, "").value(); }

TEST(EdgeAntialiasing, EdgeSupersamplingRemovesMostOfTheAliasing) {
  const Image reference =
      RenderTile(Bars(pb::ANTIALIASING_MODE_FULL, 64), nullptr, {0, 0, kW, kH});
  const double aa = BeautyRmse(
      RenderTile(Bars(pb::ANTIALIASING_MODE_EDGES), nullptr, {0, 0, kW, kH}), reference);
  const double one = BeautyRmse(
      RenderTile(Bars(pb::ANTIALIASING_MODE_NONE), nullptr, {0, 0, kW, kH}), reference);
  EXPECT_LT(aa, one / 2) << "edges " << aa << ", 1 spp " << one;
}

TEST(EdgeAntialiasing, RoundsDrawFreshSamplesAndRound1IsTheDefault) {
  const Scene scene = Bars(pb::ANTIALIASING_MODE_FULL);
  const Image first = RenderTile(scene, nullptr, {0, 0, kW, kH});
  EXPECT_EQ(first, RenderTile(scene, nullptr, {0, 0, kW, kH}, {.first_sample = 0}));
  const Image second = RenderTile(scene, nullptr, {0, 0, kW, kH}, {.first_sample = 12});
  const Image second_again = RenderTile(scene, nullptr, {0, 0, kW, kH}, {.first_sample = 12});
  EXPECT_EQ(second, second_again);
  // On an edge the samples land elsewhere, so nearly every edge pixel changes value.
  int edge_pixels = 0, changed = 0;
  const Image aa = RenderTile(Bars(pb::ANTIALIASING_MODE_EDGES), nullptr, {0, 0, kW, kH});
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      if (aa.pixel(x, y)[kEdgeChannel] != 1.0f) continue;
      ++edge_pixels;
      changed += first.pixel(x, y)[0] != second.pixel(x, y)[0];
    }
  EXPECT_GT(changed, edge_pixels * 8 / 10) << changed << " of " << edge_pixels;
}

// Edge anti-aliasing must not bias a pixel: its number of samples may not depend on what
// its own base samples saw (edge_detect.h, "Unbiased"). Tiny lights of a quarter of a
// pixel's area, seen head-on against black, each in one pixel or straddling a few: over
// many rounds the image holds their exact total area times their radiance. Deciding on
// the pixel's own sample (hit: supersample; miss: keep the black sample) gave a quarter of it.
TEST(EdgeAntialiasing, SubPixelLightsKeepTheirTotalOverRounds) {
  constexpr int kSize = 24, kRounds = 400;
  constexpr double kDistance = 10, kPixel = 0.1, kSide = 0.05;  // a light: 0.5 x 0.5 pixels
  const double fov = 2 * std::atan(kSize * kPixel / 2 / kDistance) * 180 / std::numbers::pi;
  pb::Scene s = MakeScene(kSize, kSize, {0, 0, -kDistance}, {0, 0, 0}, {0, 1, 0}, fov, 1);
  s.mutable_indirect()->set_mode(pb::INDIRECT_MODE_PHOTON_MAP);
  AddEmissive(s, "lamp", Rgb(1.0f));
  int lights = 0;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 5; ++i, ++lights) {
      // Spread over the view at offsets that fall anywhere inside or across pixels; facing
      // the camera (cross(edge_u, edge_v) = -z).
      const Vec3d corner(-1.0 + 0.43 * i + 0.017 * j, -1.0 + 0.41 * j + 0.023 * i, 0);
      AddQuad(s, "lamp", corner, {0, kSide, 0}, {kSide, 0, 0});
    }
  const Scene scene = Scene::Build(s, NoBlobs());
  double total = 0;
  int supersampled = 0;
  for (int round = 0; round < kRounds; ++round) {
    const Image image = RenderTile(scene, nullptr, {0, 0, kSize, kSize}, {.first_sample = std::uint32_t(round)});
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        total += image.pixel(x, y)[0];
        supersampled += image.pixel(x, y)[kEdgeChannel] == 1.0f;
      }
  }
  const double expected = lights * (kSide / kPixel) * (kSide / kPixel);  // radiance 1
  // Per round the total's spread is at most sqrt(25 x 1/4 x 3/4) = 2.2 pixels' worth, over
  // 400 rounds 0.11 of the expected 6.25: 0.08 is 4.5 of those.
  EXPECT_NEAR(total / kRounds / expected, 1.0, 0.08) << "lights' total " << total / kRounds << " of " << expected;
  EXPECT_GT(supersampled, kRounds * lights) << "edge anti-aliasing ran";
}

// Bright edges (edge_detect.h): a lamp of radiance 1 seen head-on against black, and an
// unlit white quad farther back, each pixel 0.1 units at the lamp's depth (image x runs
// along world -x). The lamp's outline runs through the middle of columns 34 and 40 and
// rows 18 and 29; the quad's right edge through column 29 (x = 0.3 at depth 11).
Scene LampAndQuad() {
  constexpr double kDistance = 10, kPixel = 0.1;
  const double fov = 2 * std::atan(kH * kPixel / 2 / kDistance) * 180 / std::numbers::pi;
  pb::Scene s = MakeScene(kW, kH, {0, 0, -kDistance}, {0, 0, 0}, {0, 1, 0}, fov, 1);
  s.mutable_indirect()->set_mode(pb::INDIRECT_MODE_PHOTON_MAP);
  s.mutable_antialiasing()->set_edge_samples(12);
  AddEmissive(s, "lamp", Rgb(1.0f));
  AddLambert(s, "white", Rgb(0.8f));
  AddQuad(s, "lamp", {-0.85, -0.55, 0}, {0, 1.1, 0}, {0.6, 0, 0});  // facing the camera
  AddQuad(s, "white", {0.3, -0.8, 1}, {0, 1.6, 0}, {3.7, 0, 0});
  return Scene::Build(s, NoBlobs());
}

TEST(EdgeAntialiasing, ALampsOutlineTakesItsContrastsSamplesAndAnUnlitEdgeTheEdgeSamples) {
  const int samples = RenderChannelIndex("samples.Y");
  const Image image = RenderTile(LampAndQuad(), nullptr, {0, 0, kW, kH});
  const auto at = [&](int x, int y) { return image.pixel(x, y)[samples]; };
  // The lamp against black: (1 + 1/256) / (1/256), over 4, square root 8: the cap.
  for (int y = 19; y <= 28; ++y)
    for (const int x : {34, 40}) {
      ASSERT_EQ(at(x, y), 12.0f * kMaxEdgeSampleFactor) << x << ", " << y;
      // Half covered; 96 stratified samples place the outline to within a few hundredths.
      EXPECT_NEAR(image.pixel(x, y)[0], 0.5, 0.08) << x << ", " << y;
    }
  for (int x = 35; x <= 39; ++x)
    for (const int y : {18, 29}) EXPECT_EQ(at(x, y), 12.0f * kMaxEdgeSampleFactor) << x << ", " << y;
  // The unlit quad's edge is an edge (another surface) with nothing emitted beside it.
  for (int y = 19; y <= 28; ++y) EXPECT_EQ(at(29, y), 12.0f) << "29, " << y;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x <= 31; ++x) EXPECT_LE(at(x, y), 12.0f) << x << ", " << y;
}

TEST(EdgeAntialiasing, BrightEdgesStitchBitForBitIntoTheWholeImage) {
  const Scene scene = LampAndQuad();
  ExpectTilesStitch(scene, {}, 16);
  ExpectTilesStitch(scene, {.first_sample = 5}, 7);
}

TEST(EdgeAntialiasing, RefusesANonPositiveRadiusScale) {
  const Scene scene = Bars(pb::ANTIALIASING_MODE_EDGES);
  EXPECT_THROW(RenderTile(scene, nullptr, {0, 0, 8, 8}, {.radius_scale = 0}),
               std::invalid_argument);
  EXPECT_THROW(RenderTile(scene, nullptr, {0, 0, 8, 8}, {.radius_scale = NAN}),
               std::invalid_argument);
}

}  // namespace
}  // namespace farm
