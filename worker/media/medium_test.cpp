#include "media/medium.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

namespace farm {
namespace {

// A grid of constant density 2 on [0, 1]^3 in its own space, placed by a transform that
// scales by 3, turns 30 degrees about (1, 1, 0) and moves by (5, -1, 2): a ball around
// the box's centre in the scene sees sigma_t = 2 x density_scale everywhere inside.
GridMedium ConstantGrid(float density_scale, const Rgb& albedo) {
  const Affine3d placement = Affine3d::ScaleRotateTranslate({3, 3, 3}, {1, 1, 0}, 30, {5, -1, 2});
  return GridMedium{std::make_shared<DenseGrid>(4, 4, 4, std::vector<float>(64, 2.0f), Bounds3{{0, 0, 0}, {1, 1, 1}}),
                    placement.Inverse(), density_scale, albedo, 0.3f};
}

// A chord of the placed box: from its centre, one unit along a slanted direction and back
// 0.4 (all inside: the box is 3 units wide).
struct Chord {
  Ray ray;
  float t0 = 0.6f, t1 = 1.0f;  // 0.4 units of the ray
};
Chord ChordOfTheBox() {
  const Vec3 centre(Affine3d::ScaleRotateTranslate({3, 3, 3}, {1, 1, 0}, 30, {5, -1, 2}).Apply({0.5, 0.5, 0.5}));
  const Vec3 d = Normalize(Vec3(0.3f, -0.5f, 0.8f));
  return {Ray{centre - d, d}};
}

TEST(GridMedium, TransmittanceThroughAPlacedConstantGridIsBeerLambertInSceneUnits) {
  const Medium m{ConstantGrid(0.75f, Rgb(0.5f))};
  const Chord c = ChordOfTheBox();
  const double want = std::exp(-2 * 0.75 * (c.t1 - c.t0));
  EXPECT_NEAR(Transmittance(m, c.ray, c.t0, c.t1).g / want, 1.0, 1e-5);
  EXPECT_EQ(Transmittance(m, c.ray, c.t1, c.t0), Rgb(1)) << "an empty stretch";
}

// A photon's free flight through the chord: it collides with probability 1 - T, carrying
// the albedo, and otherwise passes carrying 1 (delta tracking's weights).
TEST(GridMedium, FreeFlightsCollideWithProbabilityOneMinusTransmittance) {
  const Medium m{ConstantGrid(0.75f, Rgb(0.9f, 0.5f, 0.1f))};
  const Chord c = ChordOfTheBox();
  const int n = 100000;
  int collided = 0;
  for (int i = 0; i < n; ++i) {
    const FreeFlight f = SampleFlight(m, c.ray, c.t0, c.t1, 0, (float(i) + 0.5f) / n);
    if (f.t) {
      ++collided;
      ASSERT_GE(*f.t, c.t0);
      ASSERT_LE(*f.t, c.t1);
      ASSERT_EQ(f.weight, Rgb(0.9f, 0.5f, 0.1f));
    } else {
      ASSERT_EQ(f.weight, Rgb(1));
    }
  }
  const double want = 1 - std::exp(-2 * 0.75 * (c.t1 - c.t0));  // 0.45
  // Binomial: sigma = sqrt(p (1 - p) / n) = 0.16% of n, 1% is six of them.
  EXPECT_NEAR(double(collided) / n / want, 1.0, 0.01);
}

// The single-scattering integral over the chord of a grid and of the homogeneous medium of
// the same density, estimated by SampleDistance and weighed by the tracked transmittance
// and sigma_s, as media_transport.h does: both integral T(t) sigma_s dt = albedo (1 -
// exp(-sigma_t L)) in closed form. DistancePdf gives each sample's density.
TEST(GridMedium, DistanceSamplesEstimateTheSameIntegralAsTheHomogeneousMedium) {
  const Rgb albedo(0.8f, 0.6f, 0.4f);
  const Medium grid{ConstantGrid(0.75f, albedo)};
  const Medium homogeneous{HomogeneousMedium::FromAlbedo(albedo, 1.5f, 0.3f)};
  const Chord c = ChordOfTheBox();
  const Rgb want = albedo * float(-std::expm1(-1.5 * (c.t1 - c.t0)));
  for (const Medium* m : {&grid, &homogeneous}) {
    SCOPED_TRACE(m->ToString());
    const int n = 40000;
    Rgb sum;
    for (int i = 0; i < n; ++i) {
      const std::optional<DistanceSample> d = SampleDistance(*m, c.ray, c.t0, c.t1, 0.3f, (float(i) + 0.5f) / n);
      ASSERT_TRUE(d);
      ASSERT_NEAR(DistancePdf(*m, c.ray, c.t0, c.t1, d->t) / d->pdf, 1.0, 1e-4) << "the sampler's density at t";
      sum += Transmittance(*m, c.ray, c.t0, d->t) * ScatteringAt(*m, c.ray.At(d->t)) / d->pdf;
    }
    EXPECT_NEAR(sum.r / n / want.r, 1.0, 0.01);
    EXPECT_NEAR(sum.b / n / want.b, 1.0, 0.01);
  }
  EXPECT_FLOAT_EQ(grid.g(), 0.3f);
  EXPECT_TRUE(grid.Scatters());
  EXPECT_FALSE((Medium{ConstantGrid(1, Rgb(0))}.Scatters())) << "albedo 0 only absorbs";
}

}  // namespace
}  // namespace farm
