// The hierarchy that aims caustic photons, against brute force over every sphere: the
// probabilities it picks with partition [0, 1) and are its picks' frequencies; aiming, with
// a path owned by the sphere it hits first, measures the solid angle of all the cones
// (unbiased, overlaps and all); its point test misses no sphere.

#include "sampling/target_spheres.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
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

TEST(TargetSpheres, OneSphereIsPickedSurely) {
  const BoundingSphere s{Vec3(1, 2, 3), 0.5f};
  const TargetSpheres targets({s});
  const Vec3 p(-2, 0, 1);
  const auto pick = targets.PickFrom(p, 0.7f);
  ASSERT_TRUE(pick);
  EXPECT_EQ(pick->index, 0);
  EXPECT_EQ(pick->probability, 1.0);
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

// The sphere the ray from p along w (unit) hits first, by brute force; -1 if none.
int FirstHit(const std::vector<BoundingSphere>& spheres, const Vec3& p, const Vec3& w) {
  int first = -1;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    const Vec3 to = spheres[k].center - p;
    const double along = Dot(to, w), miss2 = LengthSquared(to) - along * along;
    const double r2 = double(spheres[k].radius) * spheres[k].radius;
    if (along <= 0 || miss2 > r2) continue;
    const double t = along - std::sqrt(r2 - miss2);
    if (t < nearest) {
      nearest = t;
      first = static_cast<int>(k);
    }
  }
  return first;
}

// E[1 / (P(j) pdf_j(w))] over directions aimed at sphere j that hit j first (0 for the
// others): the solid angle of the union of the cones, what unbiased aiming must measure.
struct AimedMeasure {
  double mean = 0, sigma = 0;
};
AimedMeasure MeasureByAiming(const std::vector<BoundingSphere>& spheres, const Vec3& p, int n, unsigned seed) {
  const TargetSpheres targets(spheres);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    const auto pick = targets.PickFrom(p, u(rng));
    const BoundingSphere& s = spheres[pick->index];
    const SphereSample sample = SampleSphereFromPoint(s.center, s.radius, p, Vec2(u(rng), u(rng)));
    const Vec3 w = Normalize(sample.p - p);
    const double x = FirstHit(spheres, p, w) == pick->index ? 1 / (pick->probability * sample.pdf) : 0;
    sum += x;
    sum2 += x * x;
  }
  const double mean = sum / n;
  return {mean, std::sqrt((sum2 / n - mean * mean) / n)};
}

TEST(TargetSpheres, AimingMeasuresTheSolidAngleOfConesApart) {
  // Spheres on a ring around p whose cones do not overlap: the solid angle is the sum of
  // 2 pi (1 - cos theta_max), known exactly; cones 0.002 to 0.006 radians wide.
  std::vector<BoundingSphere> spheres;
  double solid_angle = 0;
  for (int i = 0; i < 500; ++i) {
    const double a = 2 * kPi * i / 500, r = 0.002 + 0.004 * (i % 7) / 7.0, d = 1 + 0.5 * (i % 3);
    spheres.push_back({Vec3(float(d * std::cos(a)), float(d * std::sin(a)), 0.1f * (i % 5)), float(r)});
    const double sin2 = r * r / (d * d + 0.01 * (i % 5) * (i % 5));
    solid_angle += 2 * kPi * (1 - std::sqrt(1 - sin2));
  }
  const AimedMeasure m = MeasureByAiming(spheres, Vec3(0, 0, 0), 200'000, 5);
  EXPECT_NEAR(m.mean, solid_angle, 5 * m.sigma + 1e-4 * solid_angle) << "sigma " << m.sigma;
}

TEST(TargetSpheres, AimingMeasuresTheSolidAngleOfOverlappingCones) {
  // Spheres in a cluster that hide one another seen from p: the union's solid angle by
  // brute force (uniform directions, the fraction that hit any sphere).
  std::vector<BoundingSphere> spheres;
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> position(-1, 1), radius(0.05f, 0.3f);
  for (int i = 0; i < 200; ++i) spheres.push_back({Vec3(position(rng), position(rng), 4 + position(rng)), radius(rng)});
  const Vec3 p(0.3f, -0.2f, 0);
  std::uniform_real_distribution<float> u(0, 1);
  const int n = 2'000'000;
  int hits = 0;
  for (int i = 0; i < n; ++i) hits += FirstHit(spheres, p, SampleUniformSphere(Vec2(u(rng), u(rng)))) >= 0;
  const double f = double(hits) / n, brute = 4 * kPi * f, brute_sigma = 4 * kPi * std::sqrt(f * (1 - f) / n);
  const AimedMeasure m = MeasureByAiming(spheres, p, 200'000, 9);
  EXPECT_NEAR(m.mean, brute, 5 * std::hypot(m.sigma, brute_sigma)) << "sigmas " << m.sigma << ", " << brute_sigma;
}

TEST(TargetSpheres, TableFromAPointWeighsEachSphereByItsSolidAngle) {
  const std::vector<BoundingSphere> spheres = Scattered(200, 10);
  const TargetSpheres targets(spheres);
  std::mt19937 rng(11);
  const Vec3 p = OutsidePoint(spheres, rng);
  const std::optional<AliasTable> table = targets.TableFrom(p);
  ASSERT_TRUE(table);
  double total = 0;
  std::vector<double> solid(spheres.size());
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    const double sin2 = double(spheres[k].radius) * spheres[k].radius / LengthSquared(spheres[k].center - p);
    total += solid[k] = 2 * kPi * (1 - std::sqrt(1 - sin2));
  }
  // Within 1e-3: narrow cones take the small-angle form sin^2 / 2 of 1 - cos, off by sin^2 / 4.
  for (std::size_t k = 0; k < spheres.size(); ++k)
    EXPECT_NEAR(table->Pmf(static_cast<int>(k)), solid[k] / total, 1e-3 * solid[k] / total) << "sphere " << k;
  EXPECT_FALSE(TargetSpheres({{Vec3(0, 0, 0), 0.0f}}).TableFrom(Vec3(1, 0, 0)));
}

TEST(TargetSpheres, AnyContainsIsBruteForce) {
  const std::vector<BoundingSphere> spheres = Scattered(1000, 6);
  const TargetSpheres targets(spheres);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> position(-6, 6);
  int inside = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 p(position(rng), position(rng), position(rng));
    bool brute_inside = false;
    for (const BoundingSphere& s : spheres) brute_inside |= LengthSquared(s.center - p) <= s.radius * s.radius;
    EXPECT_EQ(targets.AnyContains(p), brute_inside) << ToString(p);
    inside += brute_inside;
  }
  EXPECT_GT(inside, 10);
}

}  // namespace
}  // namespace farm
