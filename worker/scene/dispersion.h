#pragma once

// Wavelength-dependent index of refraction of a dielectric (dispersion), as glass
// catalogues give it: Cauchy's empirical series or the Sellmeier equation, with
// wavelengths in micrometres as the catalogues write their coefficients. Named glasses
// are Sellmeier fits from their makers' data sheets (NamedGlass says whose).

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

namespace farm {

// n(λ) = a + b / λ² + c / λ⁴, λ in µm (b in µm², c in µm⁴).
struct CauchyDispersion {
  double a = 1;
  double b = 0;
  double c = 0;
};

// n²(λ) = 1 + Σ b_i λ² / (λ² - c_i), λ in µm (c_i in µm²).
struct SellmeierDispersion {
  std::array<double, 3> b{};
  std::array<double, 3> c{};
};

using Dispersion = std::variant<CauchyDispersion, SellmeierDispersion>;

// The Fraunhofer lines the Abbe number is defined at, in nm: helium d, hydrogen F and C.
inline constexpr double kFraunhoferD = 587.5618;
inline constexpr double kFraunhoferF = 486.1327;
inline constexpr double kFraunhoferC = 656.2725;

// The index at a vacuum wavelength in nm.
double IndexAt(const Dispersion& d, double lambda_nm);

// V_d = (n_d - 1) / (n_F - n_C): large for glass that spreads colours little (crown glass
// about 64), small for glass that spreads them much (dense flint about 25).
double AbbeNumber(const Dispersion& d);

// Cauchy's two-term law n(λ) = A + B / λ² with index n_d at the d line and Abbe number V_d.
CauchyDispersion CauchyFromAbbe(double n_d, double abbe_number);

// The index at λ of a dielectric whose index at the d line is ior and whose index varies as
// law's does: 1 + (ior - 1) (n(λ) - 1) / (n_d - 1), n the law's (scene.proto's Dispersion).
// At least 1 wherever the law's is; law's own index when ior is its n_d; the Abbe number is
// law's whatever ior.
double ScaledIndexAt(const Dispersion& law, double ior, double lambda_nm);

// "BK7", "fused-silica", "diamond" or "flint-SF11"; nothing for any other name.
std::optional<SellmeierDispersion> NamedGlass(std::string_view name);

std::string ToString(const Dispersion& d);

}  // namespace farm
