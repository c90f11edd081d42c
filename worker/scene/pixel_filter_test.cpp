#include "scene/pixel_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "renderfarm/v1/scene.pb.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

std::vector<PixelFilter> Filters() {
  return {{PixelFilterKind::kBox, 0.5},      {PixelFilterKind::kBox, 1.3},          {PixelFilterKind::kTent, 1},
          {PixelFilterKind::kTent, 0.7},     {PixelFilterKind::kGaussian, 1.5, 0.5}, {PixelFilterKind::kGaussian, 2, 0.5},
          {PixelFilterKind::kGaussian, 0.5, 2}, {PixelFilterKind::kMitchell, 2},    {PixelFilterKind::kMitchell, 1.5}};
}

// The midpoint rule of the profile over [a, b] in n steps: independent of Integral's
// Simpson pieces.
double Midpoint(const PixelFilter& f, double a, double b, int n) {
  double sum = 0;
  const double h = (b - a) / n;
  for (int i = 0; i < n; ++i) sum += f.Profile(a + (i + 0.5) * h);
  return sum * h;
}

TEST(PixelFilter, EveryProfileIntegratesToOneOverItsSupport) {
  for (const PixelFilter& f : Filters()) {
    // The midpoint rule errs by up to a step (4e-6 here) at the box's jumps.
    EXPECT_NEAR(Midpoint(f, -f.radius() - 0.25, f.radius() + 0.25, 400000), 1.0, 1e-5) << f.ToString();
    EXPECT_NEAR(f.Integral(-5, 5), 1.0, 1e-9) << f.ToString();
  }
}

TEST(PixelFilter, TheTwoDimensionalWeightIntegratesToOne) {
  for (const PixelFilter& f : Filters()) {
    const int n = 1000;
    const double h = 2 * f.radius() / n;
    double sum = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) sum += f.Weight(-f.radius() + (i + 0.5) * h, -f.radius() + (j + 0.5) * h);
    EXPECT_NEAR(sum * h * h, 1.0, 1e-5) << f.ToString();
  }
}

TEST(PixelFilter, PartialIntegralsMatchTheMidpointRule) {
  for (const PixelFilter& f : Filters()) {
    for (const auto& [a, b] : {std::pair{-10.0, 0.3}, {-0.2, 0.9}, {0.1, 10.0}, {-f.radius(), -f.radius() / 3}}) {
      EXPECT_NEAR(f.Integral(a, b), Midpoint(f, std::max(a, -f.radius()), std::min(b, f.radius()), 200000), 1e-7)
          << f.ToString() << " over [" << a << ", " << b << "]";
    }
    EXPECT_EQ(f.Integral(0.4, 0.4), 0) << f.ToString();
    EXPECT_EQ(f.Integral(f.radius(), f.radius() + 1), 0) << f.ToString();
  }
}

TEST(PixelFilter, MitchellWithBAndCOneThirdHasItsPublishedValues) {
  // Mitchell and Netravali's cubic at B = C = 1/3 over [-2, 2], worked from the paper's
  // polynomials: k(0) = (6 - 2B) / 6, k(1) = B / 6, and the lobe at 1.5 is negative.
  const PixelFilter f(PixelFilterKind::kMitchell, 2);
  EXPECT_NEAR(f.Profile(0), 8.0 / 9.0, 1e-12);
  EXPECT_NEAR(f.Profile(0.5), 77.0 / 144.0, 1e-12);
  EXPECT_NEAR(f.Profile(-1), 1.0 / 18.0, 1e-12);
  EXPECT_NEAR(f.Profile(1.5), -5.0 / 144.0, 1e-12);
  EXPECT_EQ(f.Profile(2), 0);
  // Its integer translates sum to 1 (a flat image stays flat): k(x) + k(x - 1) + ...
  for (double x : {0.0, 0.25, 0.5, 0.8}) {
    double sum = 0;
    for (int n = -3; n <= 3; ++n) sum += f.Profile(x - n);
    EXPECT_NEAR(sum, 1.0, 1e-12) << x;
  }
  // Stretched to radius 1, the same shape at half the offsets, twice as high.
  const PixelFilter half(PixelFilterKind::kMitchell, 1);
  EXPECT_NEAR(half.Profile(0.75), 2 * f.Profile(1.5), 1e-12);
}

TEST(PixelFilter, GaussianIsShiftedToZeroAtItsRadius) {
  const double r = 1.5, sigma = 0.5;
  const PixelFilter f(PixelFilterKind::kGaussian, r, sigma);
  const auto g = [&](double x) { return std::exp(-x * x / (2 * sigma * sigma)) - std::exp(-r * r / (2 * sigma * sigma)); };
  EXPECT_NEAR(f.Profile(0.7) / f.Profile(0), g(0.7) / g(0), 1e-12);
  EXPECT_NEAR(f.Profile(-1.2) / f.Profile(0), g(1.2) / g(0), 1e-12);
  EXPECT_EQ(f.Profile(r), 0);
  EXPECT_EQ(f.Profile(-r - 0.1), 0);
}

TEST(PixelFilter, TheHalfPixelBoxHoldsExactlyItsOwnPixel) {
  // Samples of pixel x lie in [x, x + 1), offsets [-1/2, 1/2) from its centre.
  const PixelFilter box;
  EXPECT_TRUE(box.is_pixel_box());
  EXPECT_EQ(box.Profile(-0.5), 1);
  EXPECT_EQ(box.Profile(0.4999), 1);
  EXPECT_EQ(box.Profile(0.5), 0);
  EXPECT_EQ(box.margin(), 0);
  EXPECT_FALSE(PixelFilter(PixelFilterKind::kBox, 1).is_pixel_box());
  EXPECT_FALSE(PixelFilter(PixelFilterKind::kTent, 0.5).is_pixel_box());
}

TEST(PixelFilter, TheMarginHoldsEveryPixelWhoseSamplesReach) {
  // A sample of pixel p + m lies at least m - 1/2 from p's centre.
  for (const auto& [radius, margin] : {std::pair{0.5, 0}, {0.75, 1}, {1.0, 1}, {1.5, 1}, {1.51, 2}, {2.0, 2}})
    EXPECT_EQ(PixelFilter(PixelFilterKind::kTent, radius).margin(), margin) << radius;
}

TEST(PixelFilter, FromProtoAppliesTheContractsDefaults) {
  EXPECT_TRUE(PixelFilter::FromProto(pb::PixelFilter()).is_pixel_box());
  pb::PixelFilter p;
  p.mutable_box();
  EXPECT_TRUE(PixelFilter::FromProto(p).is_pixel_box());
  p.mutable_tent();
  EXPECT_EQ(PixelFilter::FromProto(p).kind(), PixelFilterKind::kTent);
  EXPECT_EQ(PixelFilter::FromProto(p).radius(), 1);
  p.mutable_mitchell();
  EXPECT_EQ(PixelFilter::FromProto(p).radius(), 2);
  p.mutable_gaussian();
  const PixelFilter g = PixelFilter::FromProto(p);
  EXPECT_EQ(g.radius(), 1.5);
  EXPECT_EQ(g.ToString(), "PixelFilter{gaussian, radius=1.500000, sigma=0.500000}");
  p.mutable_gaussian()->set_radius(2);
  p.mutable_gaussian()->set_sigma(0.25);
  EXPECT_EQ(PixelFilter::FromProto(p).ToString(), "PixelFilter{gaussian, radius=2.000000, sigma=0.250000}");
}

}  // namespace
}  // namespace farm
