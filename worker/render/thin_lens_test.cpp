// The thin lens: a small emitter at the focus distance is imaged sharply, one nearer or
// farther as a disc whose radius is the circle of confusion of the thin-lens formula,
// A |1/z - 1/F| on the image plane at unit distance (scene/camera.h).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "render/tile_renderer.h"
#include "scene/test_scenes.h"

namespace farm {
namespace {

using namespace farm::testing;

constexpr int kSize = 64;
constexpr double kFov = 20, kAperture = 0.4, kFocus = 5, kEmitterRadius = 0.03;

// Pixels per unit on the image plane at unit distance.
double PixelsPerUnit() { return kSize / 2.0 / std::tan(kFov / 2 * M_PI / 180); }

// The rms radius (in pixels) of the image of a small emitter at depth z on the axis:
// sqrt(2 <r^2>), which is the radius of a uniform disc.
double ImageRadius(double z) {
  pb::Scene s = MakeScene(kSize, kSize, {0, 0, 0}, {0, 0, -1}, {0, 1, 0}, kFov, 1024, 5);
  s.mutable_camera()->set_aperture_radius(kAperture);
  s.mutable_camera()->set_focus_distance(kFocus);
  s.mutable_antialiasing()->set_mode(pb::ANTIALIASING_MODE_NONE);
  AddEmissive(s, "glow", Rgb(1));
  AddSphere(s, "glow", {0, 0, -z}, kEmitterRadius);
  const Scene scene = Scene::Build(s, NoBlobs());
  const Image image = RenderTile(scene, nullptr, {0, 0, kSize, kSize});
  double sum = 0, moment = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const double v = image.pixel(x, y)[1], dx = x + 0.5 - kSize / 2.0, dy = y + 0.5 - kSize / 2.0;
      sum += v;
      moment += v * (dx * dx + dy * dy);
    }
  // Removes what is not the lens: the pixel's area (a variance of 1/12 per axis, twice
  // over: the box filter and reading at pixel centres) and the emitter's own image.
  const double own = kEmitterRadius / z * PixelsPerUnit();
  return std::sqrt(std::max(0.0, 2 * (moment / sum - 2 * 2.0 / 12) - own * own));
}

TEST(ThinLens, ImagesThePlaneInFocusSharplyAndOthersAsTheCircleOfConfusion) {
  EXPECT_LT(ImageRadius(kFocus), 0.5);
  for (const double z : {2.5, 3.5, 10.0}) {
    const double expected = kAperture * std::abs(1 / z - 1 / kFocus) * PixelsPerUnit();
    const double measured = ImageRadius(z);
    std::printf("thin lens: z = %.1f, circle of confusion %.3f px (formula %.3f)\n", z, measured, expected);
    EXPECT_NEAR(measured, expected, 0.02 * expected) << "z " << z;
  }
}

}  // namespace
}  // namespace farm
