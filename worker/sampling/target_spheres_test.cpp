// The hierarchy that aims caustic photons, against brute force over every sphere: the
// probabilities it picks with partition [0, 1), the density it reports is the mixture's
// summed over all spheres, and its culled walks miss no sphere they should visit.

#include "sampling/target_spheres.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "math/math.h"
#include "sampling/warps.h"

namespace farm {
namespace {

// n spheres scattered in a box of side 10 around the origin, radii 0.01 to 0.5: far apart,
// touching and overlapping ones, so that cones overlap seen from some points.
std::vector<BoundingSphere> Scattered(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> position(-5, 5), radius(0.01f, 0.5f);
  std::vector<BoundingSphere> spheres;
  for (int i = 0; i < n; ++i) spheres.push_back({Vec3(position(rng), position(rng), position(rng)), radius(rng)});
  return spheres;
}

// A point outside every sphere, drawn from a box of side 16 (inside and outside the spheres'
// box).
Vec3 OutsidePoint(const std::vector<BoundingSphere>& spheres, std::mt19937& rng) {
  std::uniform_real_distribution<float> position(-8, 8);
  for (;;) {
    const Vec3 p(position(rng), position(rng), position(rng));
    bool inside = false;
    for (const BoundingSphere& s : spheres) inside |= LengthSquared(s.center - p) <= s.radius * s.radius;
    if (!inside) return p;
  }
}

// Every sphere's probability seen from p, read from the picks of a fine grid of u: the
// descent maps [0, 1) onto the leaves in intervals of their probabilities, so the grid finds
// every sphere whose probability is above its spacing.
std::map<int, double> ProbabilitiesByGrid(const TargetSpheres& targets, const Vec3& p, int steps) {
  std::map<int, double> probability;
  for (int i = 0; i < steps; ++i) {
    const auto pick = targets.PickFrom(p, (i + 0.5f) / steps);
    EXPECT_TRUE(pick.has_value());
    if (!pick) continue;
    const auto [it, fresh] = probability.emplace(pick->index, pick->probability);
    if (!fresh) {
      EXPECT_EQ(it->second, pick->probability) << "sphere " << pick->index << " picked with two probabilities";
    }
  }
  return probability;
}

TEST(TargetSpheres, OneSphereIsPickedSurelyWithItsConeDensity) {
  const BoundingSphere s{Vec3(1, 2, 3), 0.5f};
  const TargetSpheres targets({s});
  const Vec3 p(-2, 0, 1);
  const auto pick = targets.PickFrom(p, 0.7f);
  ASSERT_TRUE(pick);
  EXPECT_EQ(pick->index, 0);
  EXPECT_EQ(pick->probability, 1.0);
  const Vec3 w = Normalize(s.center - p);
  EXPECT_EQ(targets.DirectionPdf(p, w), SphereFromPointPdf(s.center, s.radius, p, w));
  EXPECT_EQ(targets.DirectionPdf(p, -w), 0.0f);
}

TEST(TargetSpheres, PickProbabilitiesSumToOneAndMatchTheirFrequencies) {
  const std::vector<BoundingSphere> spheres = Scattered(300, 1);
  const TargetSpheres targets(spheres);
  std::mt19937 rng(2);
  for (int trial = 0; trial < 5; ++trial) {
    const Vec3 p = OutsidePoint(spheres, rng);
    const std::map<int, double> probability = ProbabilitiesByGrid(targets, p, 1 << 20);
    double sum = 0;
    for (const auto& [index, pr] : probability) sum += pr;
    // Spheres below the grid's spacing may be missed: at most 300 of them, 2^-20 each.
    EXPECT_NEAR(sum, 1.0, 300.0 / (1 << 20)) << "p = " << ToString(p);

    // Frequencies of random picks: each within 5 standard deviations of its probability.
    const int n = 200'000;
    std::map<int, int> count;
    std::uniform_real_distribution<float> u(0, 1);
    for (int i = 0; i < n; ++i) ++count[targets.PickFrom(p, u(rng))->index];
    for (const auto& [index, pr] : probability) {
      const double sigma = std::sqrt(pr * (1 - pr) / n);
      EXPECT_NEAR(count[index] / double(n), pr, 5 * sigma + 1e-6) << "sphere " << index;
    }
  }
}

TEST(TargetSpheres, DirectionPdfIsTheMixtureOverEverySphere) {
  const std::vector<BoundingSphere> spheres = Scattered(300, 3);
  const TargetSpheres targets(spheres);
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(0, 1);
  int compared = 0;
  for (int trial = 0; trial < 4; ++trial) {
    const Vec3 p = OutsidePoint(spheres, rng);
    const std::map<int, double> probability = ProbabilitiesByGrid(targets, p, 1 << 20);
    for (int i = 0; i < 2000; ++i) {
      // Directions as emission draws them, where the density matters.
      const auto pick = targets.PickFrom(p, u(rng));
      const BoundingSphere& s = spheres[pick->index];
      const Vec3 w = Normalize(SampleSphereFromPoint(s.center, s.radius, p, Vec2(u(rng), u(rng))).p - p);
      double brute = 0;
      for (const auto& [index, pr] : probability)
        brute += pr * SphereFromPointPdf(spheres[index].center, spheres[index].radius, p, w);
      const float pdf = targets.DirectionPdf(p, w);
      ASSERT_GT(pdf, 0) << "a sampled direction has no density";
      EXPECT_NEAR(pdf, brute, 1e-5 * brute) << "p = " << ToString(p) << " w = " << ToString(w);
      ++compared;
    }
  }
  EXPECT_EQ(compared, 8000);
}

TEST(TargetSpheres, ImportanceSamplingMeasuresTheConesSolidAngle) {
  // Spheres on a ring around p whose cones do not overlap: E[1 / pdf] over the mixture is
  // the total solid angle, sum of 2 pi (1 - cos theta_max), known exactly.
  std::vector<BoundingSphere> spheres;
  double solid_angle = 0;
  for (int i = 0; i < 500; ++i) {
    const double a = 2 * kPi * i / 500, r = 0.002 + 0.004 * (i % 7) / 7.0, d = 1 + 0.5 * (i % 3);
    spheres.push_back({Vec3(float(d * std::cos(a)), float(d * std::sin(a)), 0.1f * (i % 5)), float(r)});
    const double sin2 = r * r / (d * d + 0.01 * (i % 5) * (i % 5));
    solid_angle += 2 * kPi * (1 - std::sqrt(1 - sin2));
  }
  const TargetSpheres targets(spheres);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0, 1);
  const Vec3 p(0, 0, 0);
  const int n = 400'000;
  double sum = 0, sum2 = 0;
  int dropped = 0;
  for (int i = 0; i < n; ++i) {
    const auto pick = targets.PickFrom(p, u(rng));
    const BoundingSphere& s = spheres[pick->index];
    const Vec3 w = Normalize(SampleSphereFromPoint(s.center, s.radius, p, Vec2(u(rng), u(rng))).p - p);
    // Every sampled direction has a density, even at the rim of cones 0.002 radians wide.
    const float pdf = targets.DirectionPdf(p, w);
    dropped += !(pdf > 0);
    const double x = pdf > 0 ? 1 / double(pdf) : 0;
    sum += x;
    sum2 += x * x;
  }
  const double mean = sum / n, sigma = std::sqrt((sum2 / n - mean * mean) / n);
  EXPECT_NEAR(mean, solid_angle, 5 * sigma + 1e-4 * solid_angle) << "sigma " << sigma;
  EXPECT_EQ(dropped, 0) << "directions sampled in a cone that have no density";
}

TEST(TargetSpheres, WalksMissNoSphereThatHoldsThePointOrMeetsTheLine) {
  const std::vector<BoundingSphere> spheres = Scattered(1000, 6);
  const TargetSpheres targets(spheres);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> position(-6, 6);
  int inside = 0, met = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 p(position(rng), position(rng), position(rng));
    bool brute_inside = false;
    for (const BoundingSphere& s : spheres) brute_inside |= LengthSquared(s.center - p) <= s.radius * s.radius;
    EXPECT_EQ(targets.AnyContains(p), brute_inside) << ToString(p);
    inside += brute_inside;

    const Vec3 w = SampleUniformSphere(Vec2(position(rng) / 12 + 0.5f, position(rng) / 12 + 0.5f));
    std::vector<bool> visited(spheres.size());
    targets.ForEachNearLine(p, w, [&](int k) { visited[k] = true; });
    for (std::size_t k = 0; k < spheres.size(); ++k) {
      const Vec3 to = spheres[k].center - p;
      const bool meets = LengthSquared(to - w * Dot(to, w)) <= spheres[k].radius * spheres[k].radius;
      if (meets) {
        EXPECT_TRUE(visited[k]) << "sphere " << k << " missed";
        ++met;
      }
    }
  }
  EXPECT_GT(inside, 10);
  EXPECT_GT(met, 1000);
}

}  // namespace
}  // namespace farm
