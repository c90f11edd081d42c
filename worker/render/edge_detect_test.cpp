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

TEST(EdgeDetect, TheBorderIsMirroredSoAFlatImageHasNoEdgesAnywhere) {
  const PixelRect area{0, 0, 3, 3};
  const LogLuminanceGrid grid = Fill(area, [](int, int) { return -1.5; });
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) EXPECT_EQ(SobelGradient(grid, x, y), 0.0) << x << ", " << y;
  // Mirrored at the border (x - 1 of column 0 reads column 1), a ramp's slope along the
  // border is still read in full there and nothing across it: the pixel's own value never
  // enters its test, there as anywhere.
  const LogLuminanceGrid ramp = Fill({0, 0, 5, 5}, [](int x, int) { return 0.8 * x; });
  EXPECT_NEAR(SobelGradient(ramp, 0, 0), 0.0, 1e-12);
  EXPECT_NEAR(SobelGradient(ramp, 2, 0), 0.8, 1e-12);
  EXPECT_NEAR(SobelGradient(ramp, 4, 4), 0.0, 1e-12);
}

TEST(EdgeDetect, EdgesAreThePixelsStrictlyOverTheThreshold) {
  const PixelRect area{0, 0, 6, 3};
  const LogLuminanceGrid grid = Fill(area, [](int x, int) { return x < 3 ? 0.0 : 0.5; });
  // Gradient 0.25 at x = 2 and 3, else 0.
  const std::vector<std::uint8_t> edges = DetectEdges(grid, {1, 1, 4, 1}, 0.2);
  EXPECT_EQ(edges, (std::vector<std::uint8_t>{0, 1, 1, 0}));
  EXPECT_EQ(DetectEdges(grid, {1, 1, 4, 1}, 0.25), (std::vector<std::uint8_t>{0, 0, 0, 0}));
}

// A plane seen by the camera: one surface, one normal, 1/depth linear across the image.
SurfaceCues Plane(int x, int y) { return {7, false, {0, 1, 0}, 0.5 + 0.01 * x - 0.02 * y}; }

SurfaceCueGrid FillCues(const PixelRect& area, SurfaceCues (*f)(int x, int y)) {
  SurfaceCueGrid grid(area);
  for (int y = area.y; y < area.y_end(); ++y)
    for (int x = area.x; x < area.x_end(); ++x) grid.set(x, y, f(x, y));
  return grid;
}

std::vector<std::uint8_t> SurfaceEdges(const SurfaceCueGrid& grid) {
  // A light grid that marks nothing, so only the surface cues count.
  const LogLuminanceGrid dark(grid.area());
  return DetectEdges(grid, dark, grid.area(), 0.1);
}

// A per-column pattern repeated on each of `rows` rows.
std::vector<std::uint8_t> Columns(const std::vector<std::uint8_t>& row, int rows) {
  std::vector<std::uint8_t> all;
  for (int y = 0; y < rows; ++y) all.insert(all.end(), row.begin(), row.end());
  return all;
}

TEST(EdgeDetect, APlaneHasNoSurfaceEdgesUpToTheImageBorder) {
  const SurfaceCueGrid grid = FillCues({0, 0, 5, 4}, Plane);
  EXPECT_EQ(SurfaceEdges(grid), std::vector<std::uint8_t>(20, 0));
}

TEST(EdgeDetect, AnotherSurfaceInTheNeighbourhoodIsAnEdge) {
  const SurfaceCueGrid grid = FillCues({0, 0, 6, 3}, [](int x, int y) {
    SurfaceCues c = Plane(x, y);
    if (x >= 3) c.surface = 8;
    return c;
  });
  EXPECT_EQ(SurfaceEdges(grid), Columns({0, 0, 1, 1, 0, 0}, 3));
}

TEST(EdgeDetect, ANeighboursBaseSamplesOnDifferentSurfacesMakeAnEdge) {
  // Pixel (2, 1)'s base samples met two surfaces: its eight neighbours are edges, and it
  // is not (its own samples are not read).
  const SurfaceCueGrid grid = FillCues({0, 0, 5, 3}, [](int x, int y) {
    SurfaceCues c = Plane(x, y);
    c.mixed = x == 2 && y == 1;
    return c;
  });
  EXPECT_EQ(SurfaceEdges(grid), (std::vector<std::uint8_t>{0, 1, 1, 1, 0,  //
                                                          0, 1, 0, 1, 0,  //
                                                          0, 1, 1, 1, 0}));
}

// The property that keeps the estimate unbiased: whatever a pixel's own base samples saw,
// its decision is the same (edge_detect.h, "Unbiased").
TEST(EdgeDetect, APixelsOwnCuesNeverChangeItsDecision) {
  const PixelRect area{0, 0, 7, 6};
  const std::vector<SurfaceCues> owns = {
      {7, false, {0, 1, 0}, 0.5}, {8, false, {0, 1, 0}, 0.5},  {7, true, {0, 1, 0}, 0.5},
      {7, false, {1, 0, 0}, 0.5}, {7, false, {0, 1, 0}, 0.9},  {0, false, {}, 0},
  };
  const std::vector<double> lights = {-5.0, 0.0, 3.0};
  // Neighbourhoods of every kind: a plane, a silhouette, a crease, a depth step, a shadow.
  const std::vector<SurfaceCueGrid> scenes = {
      FillCues(area, Plane),
      FillCues(area, [](int x, int y) { return x + y >= 6 ? SurfaceCues{} : Plane(x, y); }),
      FillCues(area, [](int x, int y) {
        SurfaceCues c = Plane(x, y);
        if (y >= 3) c.normal = {0.6f, 0.8f, 0};
        return c;
      }),
      FillCues(area, [](int x, int y) {
        SurfaceCues c = Plane(x, y);
        if (x >= 4) c.inverse_depth += 0.2;
        return c;
      }),
  };
  const LogLuminanceGrid shadow = Fill(area, [](int x, int) { return x < 3 ? -4.0 : 0.0; });
  for (std::size_t s = 0; s < scenes.size(); ++s)
    for (int y = 0; y < area.height; ++y)
      for (int x = 0; x < area.width; ++x) {
        const PixelRect one{x, y, 1, 1};
        SurfaceCueGrid cues = scenes[s];
        LogLuminanceGrid light = shadow;
        const std::vector<std::uint8_t> first = DetectEdges(cues, light, one, 0.1);
        for (const SurfaceCues& own : owns)
          for (double l : lights) {
            cues.set(x, y, own);
            light.set(x, y, l);
            ASSERT_EQ(DetectEdges(cues, light, one, 0.1), first)
                << "scene " << s << ", pixel " << x << ", " << y << ", own surface " << own.surface;
          }
      }
}

// The pixel's pilot (a camera ray of its own, apart from its samples) sees what its own
// base samples may not be read for: another surface, a crease or a step in depth among
// neighbours that agree.
TEST(EdgeDetect, APilotThatDiffersFromTheNeighboursMakesAnEdge) {
  const SurfaceCueGrid grid = FillCues({0, 0, 5, 5}, Plane);
  EXPECT_FALSE(SurfaceEdge(grid, 2, 2, nullptr));
  const SurfaceCues same = Plane(2, 2);
  EXPECT_FALSE(SurfaceEdge(grid, 2, 2, &same));
  SurfaceCues other = same;
  other.surface = 9;
  EXPECT_TRUE(SurfaceEdge(grid, 2, 2, &other));
  SurfaceCues missed;  // saw nothing
  EXPECT_TRUE(SurfaceEdge(grid, 2, 2, &missed));
  SurfaceCues turned = same;
  turned.normal = {0.6f, 0.8f, 0};  // 37 degrees
  EXPECT_TRUE(SurfaceEdge(grid, 2, 2, &turned));
  SurfaceCues nearer = same;
  nearer.inverse_depth *= 1.2;  // second differences of -0.4 d against 0.1 x 1.2 d
  EXPECT_TRUE(SurfaceEdge(grid, 2, 2, &nearer));
  nearer.inverse_depth = same.inverse_depth * 1.04;  // -0.08 d against 0.104 d
  EXPECT_FALSE(SurfaceEdge(grid, 2, 2, &nearer));
}

TEST(EdgeDetect, ACreaseOverTheAngleIsAnEdgeAndAGentleBendIsNot) {
  // Normals turning by 30 degrees at x = 3 (cos 0.866 < 0.9), by 20 at x = 3 (0.940).
  for (const auto& [degrees, expected] :
       {std::pair{30.0, std::vector<std::uint8_t>{0, 0, 1, 1, 0, 0}}, std::pair{20.0, std::vector<std::uint8_t>(6, 0)}}) {
    SurfaceCueGrid grid({0, 0, 6, 3});
    const double a = degrees * std::acos(-1.0) / 180;
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 6; ++x) {
        SurfaceCues c = Plane(x, y);
        // Not unit, as a pixel's mean normal need not be: only the angle counts.
        if (x >= 3) c.normal = {2 * float(std::sin(a)), 2 * float(std::cos(a)), 0};
        grid.set(x, y, c);
      }
    EXPECT_EQ(SurfaceEdges(grid), Columns(expected, 3)) << degrees << " degrees";
  }
}

TEST(EdgeDetect, AStepInDepthOnOneSurfaceIsAnEdge) {
  // 1/depth 0.5 then 0.6: beside the step the row's sum of opposite neighbours is 1.1 and
  // the column's 1.0 (x = 2) or 1.2 (x = 3), a difference of 0.1 > 0.1 x 0.5.
  const SurfaceCueGrid grid = FillCues({0, 0, 6, 3}, [](int x, int) {
    return SurfaceCues{7, false, {0, 1, 0}, x < 3 ? 0.5 : 0.6};
  });
  // On the border rows only the row lies inside the image: one line, nothing to compare.
  EXPECT_EQ(SurfaceEdges(grid), (std::vector<std::uint8_t>{0, 0, 0, 0, 0, 0,  //
                                                          0, 0, 1, 1, 0, 0,  //
                                                          0, 0, 0, 0, 0, 0}));
}

TEST(EdgeDetect, TheLightCueAddsItsEdges) {
  const SurfaceCueGrid surfaces = FillCues({0, 0, 6, 1}, Plane);
  const LogLuminanceGrid light = Fill({0, 0, 6, 1}, [](int x, int) { return x < 3 ? 0.0 : 0.5; });
  EXPECT_EQ(DetectEdges(surfaces, light, {0, 0, 6, 1}, 0.2), (std::vector<std::uint8_t>{0, 0, 1, 1, 0, 0}));
}

// Bright edges: a light on one side of an edge multiplies its samples by the square root
// of the light's ratio to the darkest neighbour over 4, rounded, from 1 to 8.
SurfaceCues Lit(float luminance, float emitted) {
  SurfaceCues c = Plane(0, 0);
  c.luminance = luminance;
  c.emitted = emitted;
  return c;
}

// A 3 x 3 neighbourhood: the left column (x = 0) shows a light, the others a wall.
SurfaceCueGrid LightBeside(float light, float wall) {
  SurfaceCueGrid grid({0, 0, 3, 3});
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) grid.set(x, y, x == 0 ? Lit(light, light) : Lit(wall, 0));
  return grid;
}

TEST(EdgeDetect, AnEdgeBesideALightTakesTheSquareRootOfItsContrastOverFourTimesTheSamples) {
  const SurfaceCues pilot;  // saw no light
  const auto factor = [&](float light, float wall) { return EdgeSampleFactor(LightBeside(light, wall), 1, 1, pilot); };
  const float f = kEdgeLuminanceFloor;
  // (light + floor) / (wall + floor) = 64: sqrt(16) = 4.
  EXPECT_EQ(factor(64 * (0.2f + f) - f, 0.2f), 4u);
  EXPECT_EQ(factor(16 * (0.2f + f) - f, 0.2f), 2u);
  // Up to a ratio of 9 (sqrt(9 / 4) = 1.5) an edge takes edge_samples, as any other.
  EXPECT_EQ(factor(8.9f * (0.2f + f) - f, 0.2f), 1u);
  EXPECT_EQ(factor(9.1f * (0.2f + f) - f, 0.2f), 2u);
  // However bright, at most kMaxEdgeSampleFactor; a black wall is the floor's black.
  EXPECT_EQ(factor(1e6f, 0.2f), kMaxEdgeSampleFactor);
  EXPECT_EQ(factor(13, 0), kMaxEdgeSampleFactor);
}

TEST(EdgeDetect, OnlyEmittedLightMakesABrightEdge) {
  // The same neighbourhood, its bright side a white wall lit by the sun (luminance 50) that
  // emits nothing: an ordinary edge.
  SurfaceCueGrid grid = LightBeside(50, 0.2f);
  for (int y = 0; y < 3; ++y) grid.set(0, y, Lit(50, 0));
  EXPECT_EQ(EdgeSampleFactor(grid, 1, 1, SurfaceCues{}), 1u);
}

TEST(EdgeDetect, APilotThatSeesALightMakesABrightEdgeAndThePixelsOwnCuesNever) {
  // A light in a mirror smaller than a pixel: no neighbour sees it, the pilot does.
  SurfaceCueGrid grid = LightBeside(0.3f, 0.3f);
  for (int y = 0; y < 3; ++y) grid.set(0, y, Lit(0.3f, 0));
  EXPECT_EQ(EdgeSampleFactor(grid, 1, 1, SurfaceCues{}), 1u);
  EXPECT_EQ(EdgeSampleFactor(grid, 1, 1, Lit(0, 12)), 3u);  // sqrt(40 / 4) = 3.2
  // The pixel's own base samples (the centre) are never read: bright or dark, the same.
  for (const SurfaceCues& own : {Lit(1e4f, 1e4f), Lit(0, 0)}) {
    grid.set(1, 1, own);
    EXPECT_EQ(EdgeSampleFactor(grid, 1, 1, SurfaceCues{}), 1u);
    EXPECT_EQ(EdgeSampleFactor(grid, 1, 1, Lit(0, 12)), 3u);
  }
}

TEST(EdgeDetect, TheApronGrowsTheTileByOnePixelInsideTheImage) {
  EXPECT_EQ(ApronArea({32, 32, 32, 32}, {100, 80}), (PixelRect{31, 31, 34, 34}));
  EXPECT_EQ(ApronArea({0, 0, 32, 32}, {100, 80}), (PixelRect{0, 0, 33, 33}));
  EXPECT_EQ(ApronArea({96, 64, 4, 16}, {100, 80}), (PixelRect{95, 63, 5, 17}));
  EXPECT_EQ(ApronArea({0, 0, 1, 1}, {1, 1}), (PixelRect{0, 0, 1, 1}));
}

}  // namespace
}  // namespace farm
