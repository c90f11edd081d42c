#include "scene/dispersion.h"

#include <gtest/gtest.h>

namespace farm {
namespace {

Dispersion Glass(std::string_view name) {
  const std::optional<SellmeierDispersion> glass = NamedGlass(name);
  EXPECT_TRUE(glass.has_value()) << name;
  return glass.value_or(SellmeierDispersion{});
}

// Against the makers' catalogue values of n_d and V_d (Schott's data sheets list n_d to 5
// decimals and V_d to 2; Malitson's paper and gemmology tables give silica and diamond).
TEST(Dispersion, NamedGlassesMatchTheirCatalogueIndexAndAbbeNumber) {
  struct Case {
    std::string_view name;
    double n_d, n_tolerance, v_d, v_tolerance;
  };
  for (const Case& c : {Case{"BK7", 1.5168, 2e-5, 64.17, 0.01}, Case{"flint-SF11", 1.78472, 2e-5, 25.68, 0.01},
                        Case{"fused-silica", 1.4585, 1e-4, 67.8, 0.1}, Case{"diamond", 2.4175, 5e-4, 55.3, 0.5}}) {
    const Dispersion glass = Glass(c.name);
    EXPECT_NEAR(IndexAt(glass, kFraunhoferD), c.n_d, c.n_tolerance) << c.name << " " << ToString(glass);
    EXPECT_NEAR(AbbeNumber(glass), c.v_d, c.v_tolerance) << c.name << " " << ToString(glass);
  }
}

TEST(Dispersion, UnknownGlassHasNoCoefficients) {
  EXPECT_FALSE(NamedGlass("bk7").has_value());
  EXPECT_FALSE(NamedGlass("").has_value());
}

// Transparent glass disperses normally: blue bends more than red across the visible range.
TEST(Dispersion, NamedGlassesIndexFallsWithWavelengthOverTheVisibleRange) {
  for (std::string_view name : {"BK7", "fused-silica", "diamond", "flint-SF11"}) {
    const Dispersion glass = Glass(name);
    for (double lambda = 360; lambda < 830; lambda += 10) {
      EXPECT_GT(IndexAt(glass, lambda), IndexAt(glass, lambda + 10)) << name << " at " << lambda << " nm";
    }
  }
}

// Cauchy's series evaluated by hand: at 500 nm (0.5 µm), 1.5 + 0.01 / 0.25 + 0.001 / 0.0625.
TEST(Dispersion, CauchySeriesInMicrometres) {
  const Dispersion glass = CauchyDispersion{1.5, 0.01, 0.001};
  EXPECT_NEAR(IndexAt(glass, 500), 1.5 + 0.04 + 0.016, 1e-12) << ToString(glass);
  const Dispersion two_term = CauchyDispersion{1.5046, 0.0042, 0};
  const double n_f_minus_n_c = 0.0042 * (1e6 / (kFraunhoferF * kFraunhoferF) - 1e6 / (kFraunhoferC * kFraunhoferC));
  EXPECT_NEAR(AbbeNumber(two_term), (IndexAt(two_term, kFraunhoferD) - 1) / n_f_minus_n_c, 1e-9);
}

// A Sellmeier term with a resonance far in the ultraviolet (c -> 0) is a constant index:
// n² = 1 + b.
TEST(Dispersion, SellmeierWithoutResonanceIsConstant) {
  const Dispersion glass = SellmeierDispersion{{1.25, 0, 0}, {0, 0, 0}};
  EXPECT_NEAR(IndexAt(glass, 400), 1.5, 1e-12);
  EXPECT_NEAR(IndexAt(glass, 700), 1.5, 1e-12);
}

TEST(Dispersion, CauchyFromAbbeHasThatIndexAndAbbeNumber) {
  for (const double n_d : {1.0001, 1.5, 2.4, 4.0}) {
    for (const double v : {15.0, 20.0, 64.17, 90.0, 100.0}) {
      const Dispersion law = CauchyFromAbbe(n_d, v);
      EXPECT_NEAR(IndexAt(law, kFraunhoferD), n_d, 1e-12) << n_d << " " << v;
      EXPECT_NEAR(AbbeNumber(law), v, 1e-9 * v) << n_d << " " << v;
    }
  }
}

TEST(Dispersion, ScaledIndexIsTheLawsAtItsOwnIndexAndKeepsItsAbbeNumber) {
  const Dispersion bk7 = *NamedGlass("BK7");
  const double n_d = IndexAt(bk7, kFraunhoferD);
  for (double lambda = 360; lambda <= 830; lambda += 10) {
    EXPECT_NEAR(ScaledIndexAt(bk7, n_d, lambda), IndexAt(bk7, lambda), 1e-12) << lambda;
    // A lower ior spreads colours less, by the same ratio; never below 1.
    EXPECT_NEAR(ScaledIndexAt(bk7, 1.25, lambda) - 1, (IndexAt(bk7, lambda) - 1) * 0.25 / (n_d - 1), 1e-12);
    EXPECT_GE(ScaledIndexAt(bk7, 1.0001, lambda), 1) << lambda;
    EXPECT_EQ(ScaledIndexAt(bk7, 1, lambda), 1) << lambda;
  }
  // The scaled law's Abbe number is the glass's.
  const auto scaled = [&](double lambda) { return ScaledIndexAt(bk7, 1.8, lambda); };
  EXPECT_NEAR((scaled(kFraunhoferD) - 1) / (scaled(kFraunhoferF) - scaled(kFraunhoferC)), AbbeNumber(bk7), 1e-9);
}

}  // namespace
}  // namespace farm
