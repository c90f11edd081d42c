#include "scene/dispersion.h"

#include <cmath>
#include <sstream>

#include "util/overloaded.h"

namespace farm {

double IndexAt(const Dispersion& d, double lambda_nm) {
  const double l2 = (lambda_nm / 1000) * (lambda_nm / 1000);
  return std::visit(Overloaded{
                        [&](const CauchyDispersion& c) { return c.a + c.b / l2 + c.c / (l2 * l2); },
                        [&](const SellmeierDispersion& s) {
                          double n2 = 1;
                          for (size_t i = 0; i < s.b.size(); ++i) n2 += s.b[i] * l2 / (l2 - s.c[i]);
                          return std::sqrt(n2);
                        },
                    },
                    d);
}

double AbbeNumber(const Dispersion& d) {
  return (IndexAt(d, kFraunhoferD) - 1) / (IndexAt(d, kFraunhoferF) - IndexAt(d, kFraunhoferC));
}

CauchyDispersion CauchyFromAbbe(double n_d, double abbe_number) {
  const auto inverse_square = [](double lambda_nm) { return 1e6 / (lambda_nm * lambda_nm); };  // 1/µm²
  const double b = (n_d - 1) / (abbe_number * (inverse_square(kFraunhoferF) - inverse_square(kFraunhoferC)));
  return CauchyDispersion{n_d - b * inverse_square(kFraunhoferD), b, 0};
}

double ScaledIndexAt(const Dispersion& law, double ior, double lambda_nm) {
  return 1 + (ior - 1) * (IndexAt(law, lambda_nm) - 1) / (IndexAt(law, kFraunhoferD) - 1);
}

std::optional<SellmeierDispersion> NamedGlass(std::string_view name) {
  // Schott's optical glass data sheets (N-BK7, SF11); Malitson, J. Opt. Soc. Am. 55 (1965)
  // 1205 for fused silica (his resonance wavelengths squared); Peter, Z. Phys. 15 (1923)
  // 358 for diamond, which needs two terms.
  if (name == "BK7") return SellmeierDispersion{{1.03961212, 0.231792344, 1.01046945}, {0.00600069867, 0.0200179144, 103.560653}};
  if (name == "fused-silica") return SellmeierDispersion{{0.6961663, 0.4079426, 0.8974794}, {0.0684043 * 0.0684043, 0.1162414 * 0.1162414, 9.896161 * 9.896161}};
  if (name == "diamond") return SellmeierDispersion{{0.3306, 4.3356, 0}, {0.175 * 0.175, 0.106 * 0.106, 0}};
  if (name == "flint-SF11") return SellmeierDispersion{{1.73759695, 0.313747346, 1.89878101}, {0.013188707, 0.0623068142, 155.23629}};
  return std::nullopt;
}

std::string ToString(const Dispersion& d) {
  std::ostringstream out;
  std::visit(Overloaded{
                 [&](const CauchyDispersion& c) { out << "Cauchy{a=" << c.a << " b=" << c.b << " c=" << c.c << "}"; },
                 [&](const SellmeierDispersion& s) {
                   out << "Sellmeier{b=(" << s.b[0] << ", " << s.b[1] << ", " << s.b[2] << ") c=(" << s.c[0] << ", "
                       << s.c[1] << ", " << s.c[2] << ")}";
                 },
             },
             d);
  return out.str();
}

}  // namespace farm
