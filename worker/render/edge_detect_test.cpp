#include "render/edge_detect.h"

#include <gtest/gtest.h>

#include <cmath>

namespace farm {
namespace {

LogLuminanceGrid Fill(const PixelRect& area, double (*f)(int x, int y)) {
  LogLuminanceGrid grid(area);
  for (int y = area.y; y < area.y_end(); ++y)
    for (int x = area.x; x < area.x_end(); ++x) grid.set(x, y, f(x, y));
  return grid;
}

TEST(EdgeDetect, LogLuminanceIsTheLogOfRec709LuminancePlusTheFloor) {
  EXPECT_DOUBLE_EQ(EdgeLogLuminance(1, 1, 1), std::log(1.0 + 1.0 / 256));
  EXPECT_DOUBLE_EQ(EdgeLogLuminance(0, 0, 0), std::log(1.0 / 256));
  EXPECT_NEAR(EdgeLogLuminance(0, 2, 0), std::log(0.7152 * 2 + 1.0 / 256), 1e-12);
  // Never NaN, whatever comes in.
  EXPECT_TRUE(std::isfinite(EdgeLogLuminance(NAN, 0, 0)));
  EXPECT_TRUE(std::isfinite(EdgeLogLuminance(-1, -1, -1)));
}

TEST(EdgeDetect, SobelReadsTheSlopeOfALinearRampInEveryDirection) {
  const PixelRect area{0, 0, 9, 9};
  // slope 0.3 along x and 0.4 along y: magnitude 0.5.
  const LogLuminanceGrid grid = Fill(area, [](int x, int y) { return 0.3 * x + 0.4 * y; });
  EXPECT_NEAR(SobelGradient(grid, 4, 4), 0.5, 1e-12);
  EXPECT_NEAR(SobelGradient(grid, 1, 7), 0.5, 1e-12);
}

TEST(EdgeDetect, AStepReadsHalfItsHeightOnEitherSideAndNothingFurther) {
  const PixelRect area{10, 20, 8, 5};
  const LogLuminanceGrid grid = Fill(area, [](int x, int) { return x < 14 ? 0.0 : 2.0; });
  EXPECT_DOUBLE_EQ(SobelGradient(grid, 13, 22), 1.0);
  EXPECT_DOUBLE_EQ(SobelGradient(grid, 14, 22), 1.0);
  EXPECT_DOUBLE_EQ(SobelGradient(grid, 12, 22), 0.0);
  EXPECT_DOUBLE_EQ(SobelGradient(grid, 15, 22), 0.0);
}

TEST(EdgeDetect, TheBorderIsClampedSoAFlatImageHasNoEdgesAnywhere) {
  const PixelRect area{0, 0, 3, 3};
  const LogLuminanceGrid grid = Fill(area, [](int, int) { return -1.5; });
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) EXPECT_EQ(SobelGradient(grid, x, y), 0.0) << x << ", " << y;
  // Clamped at the border, a ramp's slope along the border is still read in full there and
  // half across it (one of the two differences is 0).
  const LogLuminanceGrid ramp = Fill({0, 0, 5, 5}, [](int x, int) { return 0.8 * x; });
  EXPECT_NEAR(SobelGradient(ramp, 0, 0), 0.4, 1e-12);
  EXPECT_NEAR(SobelGradient(ramp, 2, 0), 0.8, 1e-12);
}

TEST(EdgeDetect, EdgesAreThePixelsStrictlyOverTheThreshold) {
  const PixelRect area{0, 0, 6, 3};
  const LogLuminanceGrid grid = Fill(area, [](int x, int) { return x < 3 ? 0.0 : 0.5; });
  // Gradient 0.25 at x = 2 and 3, else 0.
  const std::vector<std::uint8_t> edges = DetectEdges(grid, {1, 1, 4, 1}, 0.2);
  EXPECT_EQ(edges, (std::vector<std::uint8_t>{0, 1, 1, 0}));
  EXPECT_EQ(DetectEdges(grid, {1, 1, 4, 1}, 0.25), (std::vector<std::uint8_t>{0, 0, 0, 0}));
}

TEST(EdgeDetect, TheApronGrowsTheTileByOnePixelInsideTheImage) {
  EXPECT_EQ(ApronArea({32, 32, 32, 32}, {100, 80}), (PixelRect{31, 31, 34, 34}));
  EXPECT_EQ(ApronArea({0, 0, 32, 32}, {100, 80}), (PixelRect{0, 0, 33, 33}));
  EXPECT_EQ(ApronArea({96, 64, 4, 16}, {100, 80}), (PixelRect{95, 63, 5, 17}));
  EXPECT_EQ(ApronArea({0, 0, 1, 1}, {1, 1}), (PixelRect{0, 0, 1, 1}));
}

}  // namespace
}  // namespace farm
