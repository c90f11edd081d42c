#include "scene/pixel_filter.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "contract/rules.h"
#include "renderfarm/v1/scene.pb.h"

namespace farm {
namespace {

namespace pb = renderfarm::v1;

// Mitchell and Netravali's cubic (1988) over |t| in [0, 2) with B = C = 1/3, their
// recommendation; it integrates to 1 over [-2, 2] for any B and C.
double MitchellCubic(double t) {
  constexpr double b = 1.0 / 3.0;
  constexpr double c = 1.0 / 3.0;
  t = std::abs(t);
  if (t < 1)
    return ((12 - 9 * b - 6 * c) * t * t * t + (-18 + 12 * b + 6 * c) * t * t + (6 - 2 * b)) / 6;
  if (t < 2)
    return ((-b - 6 * c) * t * t * t + (6 * b + 30 * c) * t * t + (-12 * b - 48 * c) * t + (8 * b + 24 * c)) / 6;
  return 0;
}

double GaussianBump(double x, double sigma) { return std::exp(-x * x / (2 * sigma * sigma)); }

// Simpson's rule of f over [a, b] in n (even) pieces: exact for cubics.
template <typename F>
double Simpson(F f, double a, double b, int n) {
  if (!(b > a)) return 0;
  const double h = (b - a) / n;
  double sum = f(a) + f(b);
  for (int i = 1; i < n; ++i) sum += f(a + i * h) * (i % 2 == 1 ? 4 : 2);
  return sum * h / 3;
}

}  // namespace

PixelFilter::PixelFilter(PixelFilterKind kind, double radius, double sigma)
    : kind_(kind), radius_(radius), sigma_(sigma) {
  switch (kind_) {
    case PixelFilterKind::kBox: normaliser_ = 2 * radius_; break;
    case PixelFilterKind::kTent: normaliser_ = radius_ * radius_; break;
    case PixelFilterKind::kGaussian:
      // The integral of exp(-x^2 / 2 sigma^2) - exp(-r^2 / 2 sigma^2) over [-r, r].
      normaliser_ = sigma_ * std::sqrt(2 * std::numbers::pi) * std::erf(radius_ / (sigma_ * std::numbers::sqrt2)) -
                    2 * radius_ * GaussianBump(radius_, sigma_);
      break;
    case PixelFilterKind::kMitchell: normaliser_ = radius_ / 2; break;
  }
}

PixelFilter PixelFilter::FromProto(const pb::PixelFilter& filter) {
  using contract::OrDefault;
  switch (filter.kind_case()) {
    case pb::PixelFilter::kBox:
      return {PixelFilterKind::kBox, OrDefault<pb::BoxFilter>(filter.box().radius(), "radius")};
    case pb::PixelFilter::kTent:
      return {PixelFilterKind::kTent, OrDefault<pb::TentFilter>(filter.tent().radius(), "radius")};
    case pb::PixelFilter::kGaussian:
      return {PixelFilterKind::kGaussian, OrDefault<pb::GaussianFilter>(filter.gaussian().radius(), "radius"),
              OrDefault<pb::GaussianFilter>(filter.gaussian().sigma(), "sigma")};
    case pb::PixelFilter::kMitchell:
      return {PixelFilterKind::kMitchell, OrDefault<pb::MitchellFilter>(filter.mitchell().radius(), "radius")};
    case pb::PixelFilter::KIND_NOT_SET: return {};
  }
  return {};
}

double PixelFilter::Profile(double x) const {
  if (kind_ == PixelFilterKind::kBox) return x >= -radius_ && x < radius_ ? 1 / normaliser_ : 0;
  if (!(std::abs(x) < radius_)) return 0;
  switch (kind_) {
    case PixelFilterKind::kBox: break;  // above
    case PixelFilterKind::kTent: return (radius_ - std::abs(x)) / normaliser_;
    case PixelFilterKind::kGaussian:
      return std::max(0.0, GaussianBump(x, sigma_) - GaussianBump(radius_, sigma_)) / normaliser_;
    case PixelFilterKind::kMitchell: return MitchellCubic(2 * x / radius_) / normaliser_;
  }
  return 0;
}

double PixelFilter::Integral(double a, double b) const {
  a = std::max(a, -radius_);
  b = std::min(b, radius_);
  if (!(b > a)) return 0;
  if (kind_ == PixelFilterKind::kBox) return (b - a) / normaliser_;
  // The other profiles are smooth between their knots (0 for the tent, -r/2, 0 and r/2
  // for Mitchell's pieces) and 0 at +-r: integrate piece by piece.
  const double knots[] = {-radius_, -radius_ / 2, 0, radius_ / 2, radius_};
  double sum = 0;
  for (int i = 0; i + 1 < 5; ++i)
    sum += Simpson([this](double x) { return Profile(x); }, std::max(a, knots[i]), std::min(b, knots[i + 1]), 64);
  return sum;
}

int PixelFilter::margin() const { return static_cast<int>(std::ceil(radius_ - 0.5)); }

std::string PixelFilter::ToString() const {
  const char* name = "box";
  switch (kind_) {
    case PixelFilterKind::kBox: name = "box"; break;
    case PixelFilterKind::kTent: name = "tent"; break;
    case PixelFilterKind::kGaussian: name = "gaussian"; break;
    case PixelFilterKind::kMitchell: name = "mitchell"; break;
  }
  std::string s = std::string("PixelFilter{") + name + ", radius=" + std::to_string(radius_);
  if (kind_ == PixelFilterKind::kGaussian) s += ", sigma=" + std::to_string(sigma_);
  return s + "}";
}

}  // namespace farm
