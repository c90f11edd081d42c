#include "scene/environment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "contract/rules.h"
#include "math/math.h"
#include "sampling/sobol.h"
#include "scene/environment_image.h"
#include "scene/test_environment.h"

namespace farm {
namespace {

constexpr double kPiD = std::numbers::pi;

// An 8 x 4 map: one channel per texel index, so a lookup names the texel it read.
EnvironmentImage IndexedImage(int w = 8, int h = 4) {
  EnvironmentImage image{w, h, {}};
  for (int i = 0; i < w * h; ++i) image.texels.push_back(Rgb(float(i), 1, 0));
  return image;
}

// A non-uniform map: a gradient from the top down, a bright patch, and black texels.
EnvironmentImage PatchyImage() {
  EnvironmentImage image{16, 8, {}};
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) {
      float v = 0.2f + 0.1f * float(8 - y);
      if (x >= 10 && x <= 11 && y >= 2 && y <= 3) v = 20;
      if (x <= 1) v = 0;
      image.texels.push_back(Rgb(v, 0.5f * v, 0.25f * v));
    }
  return image;
}

// Texel centre (x, y) of a w x h map as a direction, by the convention of environment.h.
Vec3 TexelDirection(int x, int y, int w, int h) {
  const double theta = (y + 0.5) / h * kPiD, phi = ((x + 0.5) / w - 0.5) * 2 * kPiD;
  return Vec3(Vec3d(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)));
}

TEST(Environment, MapIsUpAlongYMiddleColumnAlongMinusZAndLongitudeTowardsPlusX) {
  const Environment e = Environment::Map(IndexedImage(), Rgb(1), 0);
  SCOPED_TRACE(e.ToString());
  // Texel centres read back exactly: the middle columns look along -Z, u = 0.75 (column 6)
  // along +X, the top row up.
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) EXPECT_NEAR(e.Radiance(TexelDirection(x, y, 8, 4)).r, y * 8 + x, 1e-3);
  EXPECT_NEAR(e.Radiance({0, 0, -1}).r, (12 + 11 + 20 + 19) / 4.0, 1e-3);  // between columns 3, 4 and rows 1, 2
  EXPECT_NEAR(e.Radiance({1, 0, 0}).r, (13 + 14 + 21 + 22) / 4.0, 1e-3);   // u = 0.75: columns 5, 6
  EXPECT_NEAR(e.Radiance({0, 1, 0}).g, 1, 1e-6);
}

TEST(Environment, RotationTurnsTheMapAboutY) {
  const Environment straight = Environment::Map(IndexedImage(), Rgb(1), 0);
  const Environment turned = Environment::Map(IndexedImage(), Rgb(1), 90);
  // Turned by 90 degrees, what the middle column showed along -Z is seen along -X: the
  // map turns by the right-hand rule about +Y, (x, y, z) -> (z, y, -x).
  EXPECT_NEAR(turned.Radiance({-1, 0, 0}).r, straight.Radiance({0, 0, -1}).r, 1e-3);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) {
      const Vec3 w = TexelDirection(x, y, 8, 4);
      EXPECT_NEAR(turned.Radiance(Vec3(w.z, w.y, -w.x)).r, straight.Radiance(w).r, 1e-3);
    }
}

TEST(Environment, SampledDensityIntegratesToOneAndMatchesPdf) {
  for (const double rotation : {0.0, 37.0}) {
    const Environment e = Environment::Map(PatchyImage(), Rgb(1), rotation);
    SCOPED_TRACE(e.ToString());
    // The density over the sphere integrates to 1 (midpoint rule in cos theta and phi), and
    // is positive wherever the lookup is: every direction that lights can be drawn.
    double integral = 0;
    const int n = 800;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < 2 * n; ++j) {
        const double z = -1 + 2 * (i + 0.5) / n, phi = 2 * kPiD * (j + 0.5) / (2 * n);
        const double r = std::sqrt(1 - z * z);
        const Vec3 w(Vec3d(r * std::cos(phi), z, r * std::sin(phi)));
        const float pdf = e.Pdf(w);
        integral += pdf * (2.0 / n) * (kPiD / n);
        if (e.Radiance(w).g > 0) {
          ASSERT_GT(pdf, 0) << ToString(w);
        }
      }
    EXPECT_NEAR(integral, 1, 2e-3);
    // Samples carry the lookup's radiance and the density Pdf gives them.
    for (int i = 0; i < 4096; ++i) {
      const auto s = e.SampleDirection({SobolSample(i, 0, 11), SobolSample(i, 1, 12)});
      ASSERT_TRUE(s);
      EXPECT_NEAR(Length(s->w), 1, 1e-5);
      EXPECT_NEAR(s->pdf, e.Pdf(s->w), 1e-3 * s->pdf);
      const Rgb l = e.Radiance(s->w);
      EXPECT_NEAR(s->radiance.r, l.r, 1e-3 * l.r + 1e-5);
    }
  }
}

TEST(Environment, SphereIntegralIsTheRadianceOverAllDirections) {
  const Environment e = Environment::Map(PatchyImage(), Rgb(2), 0);
  double integral = 0;
  const int n = 1000;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double z = -1 + 2 * (i + 0.5) / n, phi = 2 * kPiD * (j + 0.5) / (2 * n);
      const double r = std::sqrt(1 - z * z);
      integral += e.Radiance(Vec3(Vec3d(r * std::cos(phi), z, r * std::sin(phi)))).r * (2.0 / n) * (kPiD / n);
    }
  // The texels' sum is the bilinear lookup's integral up to the filtering at the patch.
  EXPECT_NEAR(e.SphereIntegral().r, integral, 0.02 * integral);
  EXPECT_FALSE(e.IsBlack());
  EXPECT_NEAR(Environment::Constant(Rgb(0.5f)).SphereIntegral().g, 2 * kPiD, 1e-5);
  EXPECT_TRUE(Environment::Constant(Rgb()).IsBlack());
}

TEST(Environment, WideMapsAreSampledOnCoarserCells) {
  EnvironmentImage image{Environment::kMaxDistributionWidth * 2 + 3, 4, {}};
  image.texels.assign(std::size_t(image.width) * image.height, Rgb(1));
  image.texels[5] = Rgb(1000);  // one bright texel
  const Environment e = Environment::Map(std::move(image), Rgb(1), 0);
  double mean = 0;
  for (int i = 0; i < 1024; ++i) {
    const auto s = e.SampleDirection({SobolSample(i, 0, 1), SobolSample(i, 1, 2)});
    ASSERT_TRUE(s);
    EXPECT_NEAR(s->pdf, e.Pdf(s->w), 1e-3 * s->pdf);
    mean += s->radiance.g / s->pdf / 1024;
  }
  EXPECT_NEAR(mean, e.SphereIntegral().g, 0.05 * e.SphereIntegral().g);
}

TEST(EnvironmentImage, DecodesRadianceHdrAndRefusesWhatIsNotAnImage) {
  const std::vector<Rgb> texels = {Rgb(1, 0.5f, 0.25f), Rgb(0, 0, 0), Rgb(4, 4, 4)};
  const EnvironmentImage image =
      DecodeEnvironmentImage(testing::EncodeRadianceHdr(3, 1, texels), EnvironmentEncoding::kByFormat, 100);
  ASSERT_EQ(image.width, 3);
  ASSERT_EQ(image.height, 1);
  EXPECT_EQ(image.at(0, 0), Rgb(1, 0.5f, 0.25f));  // RGBE holds these exactly; float files are linear
  EXPECT_EQ(image.at(2, 0), Rgb(4, 4, 4));
  EXPECT_THROW(DecodeEnvironmentImage("not an image", EnvironmentEncoding::kByFormat, 100), EnvironmentImageError);
  try {
    DecodeEnvironmentImage(testing::EncodeRadianceHdr(3, 1, texels), EnvironmentEncoding::kByFormat, 2);
    FAIL() << "a map of more pixels than the limit";
  } catch (const EnvironmentImageError& e) {
    EXPECT_STREQ(e.what(), "has 3x1 pixels, more than the 2 a texture may have");
  }
}

}  // namespace
}  // namespace farm
