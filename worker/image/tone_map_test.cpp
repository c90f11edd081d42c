#include "image/tone_map.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace farm {
namespace {

constexpr PreviewSettings kClamp{0, ToneMap::kClamp};
constexpr PreviewSettings kFilmic{0, ToneMap::kFilmic};

std::array<float, 3> Grey(float v) { return {v, v, v}; }

TEST(ToneMap, ClampIsTheIdentityUpToOneAndClipsPastIt) {
  EXPECT_EQ(ToneMapColor(kClamp, {0.25f, 0.5f, 1.0f}), (std::array<float, 3>{0.25f, 0.5f, 1.0f}));
  EXPECT_EQ(ToneMapColor(kClamp, {2.0f, -1.0f, std::numeric_limits<float>::quiet_NaN()}),
            (std::array<float, 3>{1.0f, 0.0f, 0.0f}));
}

TEST(ToneMap, ExposureMultipliesByTwoToTheStops) {
  EXPECT_EQ(ToneMapColor({1, ToneMap::kClamp}, Grey(0.25f)), Grey(0.5f));
  EXPECT_EQ(ToneMapColor({-2, ToneMap::kClamp}, Grey(0.8f)), Grey(0.2f));
  // Exposure comes before the curve: +1 stop of 0.5 is the curve at 1.
  EXPECT_EQ(ToneMapColor({1, ToneMap::kFilmic}, Grey(0.5f)), ToneMapColor(kFilmic, Grey(1.0f)));
}

TEST(ToneMap, FilmicIsKhronosPbrNeutral) {
  // Below the start of compression (0.76 after the toe's offset) only the toe acts: 0.04
  // off above 0.08, 6.25 x^2 below.
  EXPECT_NEAR(ToneMapColor(kFilmic, Grey(0.5f))[0], 0.46f, 1e-6);
  EXPECT_NEAR(ToneMapColor(kFilmic, Grey(0.02f))[0], 6.25f * 0.02f * 0.02f, 1e-7);
  EXPECT_NEAR(ToneMapColor(kFilmic, {0.5f, 0.3f, 0.1f})[1], 0.26f, 1e-6);
  // White: the peak 0.96 rolls off to 1 - 0.24^2 / (0.96 + 0.24 - 0.76) = 0.869091.
  EXPECT_NEAR(ToneMapColor(kFilmic, Grey(1.0f))[0], 1 - 0.24f * 0.24f / 0.44f, 1e-6);
  // Huge and infinite values approach white; NaN is black.
  for (const float v : {1e6f, std::numeric_limits<float>::infinity()})
    for (const float c : ToneMapColor(kFilmic, {v, v / 2, 0})) EXPECT_NEAR(c, 1, 1e-4) << v;
  EXPECT_EQ(ToneMapColor(kFilmic, Grey(std::numeric_limits<float>::quiet_NaN())), Grey(0));
}

TEST(ToneMap, FilmicRollsHighlightsOffMonotonically) {
  float previous = -1;
  for (float v = 0; v < 64; v = v * 1.05f + 0.001f) {
    const float out = ToneMapColor(kFilmic, Grey(v))[0];
    EXPECT_GT(out, previous) << v;
    EXPECT_LT(out, 1) << v;
    previous = out;
  }
  // A bright saturated colour keeps its hue order and is desaturated, not clipped.
  const std::array<float, 3> c = ToneMapColor(kFilmic, {4, 2, 1});
  EXPECT_GT(c[0], c[1]);
  EXPECT_GT(c[1], c[2]);
  EXPECT_LT(c[0], 1);
  EXPECT_GT(c[2] / c[0], 0.25f);
}

}  // namespace
}  // namespace farm
