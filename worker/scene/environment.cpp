#include "scene/environment.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "math/math.h"
#include "sampling/warps.h"

namespace farm {
namespace {

// The luminance a texel's cell of the bilinear lookup averages: the texel's own with
// weight 3/4 and each neighbour's with 1/8, along each axis (wrapping in x, clamped in y).
std::vector<float> CellMeanLuminance(const EnvironmentImage& image) {
  const int w = image.width, h = image.height;
  constexpr float kTap[3] = {0.125f, 0.75f, 0.125f};
  std::vector<float> luminance(image.texels.size());
  for (std::size_t i = 0; i < luminance.size(); ++i) luminance[i] = image.texels[i].Luminance();
  std::vector<float> along_x(luminance.size()), out(luminance.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float sum = 0;
      for (int d = -1; d <= 1; ++d) sum += kTap[d + 1] * luminance[std::size_t(y) * w + (x + d + w) % w];
      along_x[std::size_t(y) * w + x] = sum;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float sum = 0;
      for (int d = -1; d <= 1; ++d) sum += kTap[d + 1] * along_x[std::size_t(std::clamp(y + d, 0, h - 1)) * w + x];
      out[std::size_t(y) * w + x] = sum;
    }
  return out;
}

// Direction of map coordinates (u, v) in the map's own frame.
Vec3 MapDirection(Vec2 uv) {
  const float theta = uv.y * kPi, phi = (uv.x - 0.5f) * 2 * kPi;
  const float sin_theta = std::sin(theta);
  return {sin_theta * std::sin(phi), std::cos(theta), -sin_theta * std::cos(phi)};
}

// sin(theta) of a map direction, precise near the poles (unlike sqrt(1 - y^2)), and the
// same for a direction whichever way it was made.
float SinTheta(const Vec3& m) { return std::sqrt(m.x * m.x + m.z * m.z); }

}  // namespace

Environment Environment::Constant(const Rgb& radiance) {
  Environment e;
  e.scale_ = radiance;
  e.integral_ = radiance * (4 * kPi);
  return e;
}

Environment Environment::Map(EnvironmentImage image, const Rgb& scale, double rotation_degrees) {
  if (image.width <= 0 || image.height <= 0 || image.texels.size() != std::size_t(image.width) * image.height)
    throw std::invalid_argument("Environment::Map: an empty or misshapen image");
  Environment e;
  e.scale_ = scale;
  e.cos_rotation_ = static_cast<float>(std::cos(Radians(rotation_degrees)));
  e.sin_rotation_ = static_cast<float>(std::sin(Radians(rotation_degrees)));
  const int w = image.width, h = image.height;

  e.cell_ = (w + kMaxDistributionWidth - 1) / kMaxDistributionWidth;
  const int cw = (w + e.cell_ - 1) / e.cell_, ch = (h + e.cell_ - 1) / e.cell_;
  const std::vector<float> mean = CellMeanLuminance(image);
  // Each texel goes to the cell its centre lies in; a cell weighs its texels' mean.
  std::vector<double> sums(std::size_t(cw) * ch, 0.0);
  std::vector<int> counts(sums.size(), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int cx = std::min(int((x + 0.5) * cw / w), cw - 1), cy = std::min(int((y + 0.5) * ch / h), ch - 1);
      sums[std::size_t(cy) * cw + cx] += mean[std::size_t(y) * w + x];
      ++counts[std::size_t(cy) * cw + cx];
    }
  std::vector<float> weights(sums.size());
  for (int cy = 0; cy < ch; ++cy) {
    const double sin_theta = std::sin((cy + 0.5) / ch * std::numbers::pi);
    for (int cx = 0; cx < cw; ++cx) {
      const std::size_t i = std::size_t(cy) * cw + cx;
      weights[i] = counts[i] > 0 ? static_cast<float>(sums[i] / counts[i] * sin_theta) : 0.0f;
    }
  }
  e.distribution_ = Distribution2D(weights, cw, ch);

  // Each texel's radiance times the solid angle of its footprint.
  double integral[3] = {0, 0, 0};
  for (int y = 0; y < h; ++y) {
    const double solid_angle = 2 * std::numbers::pi / w *
                               (std::cos(std::numbers::pi * y / h) - std::cos(std::numbers::pi * (y + 1) / h));
    for (int x = 0; x < w; ++x) {
      const Rgb& t = image.at(x, y);
      integral[0] += t.r * solid_angle;
      integral[1] += t.g * solid_angle;
      integral[2] += t.b * solid_angle;
    }
  }
  e.integral_ = scale * Rgb(float(integral[0]), float(integral[1]), float(integral[2]));
  e.image_ = std::make_shared<const EnvironmentImage>(std::move(image));
  return e;
}

Vec3 Environment::ToMap(const Vec3& w) const {
  return {w.x * cos_rotation_ - w.z * sin_rotation_, w.y, w.x * sin_rotation_ + w.z * cos_rotation_};
}

Vec3 Environment::FromMap(const Vec3& m) const {
  return {m.x * cos_rotation_ + m.z * sin_rotation_, m.y, -m.x * sin_rotation_ + m.z * cos_rotation_};
}

Rgb Environment::Lookup(Vec2 uv) const {
  const EnvironmentImage& image = *image_;
  const float s = uv.x * image.width - 0.5f, t = uv.y * image.height - 0.5f;
  const float fs = std::floor(s), ft = std::floor(t);
  const float ds = s - fs, dt = t - ft;
  const int x0 = int(fs), y0 = int(ft);
  const auto texel = [&](int x, int y) -> const Rgb& {
    return image.at(((x % image.width) + image.width) % image.width, std::clamp(y, 0, image.height - 1));
  };
  const Rgb top = texel(x0, y0) * (1 - ds) + texel(x0 + 1, y0) * ds;
  const Rgb bottom = texel(x0, y0 + 1) * (1 - ds) + texel(x0 + 1, y0 + 1) * ds;
  return scale_ * (top * (1 - dt) + bottom * dt);
}

Rgb Environment::Radiance(const Vec3& w) const {
  if (!image_) return scale_;
  const Vec3 m = ToMap(w);
  const float u = 0.5f + std::atan2(m.x, -m.z) * kInv2Pi;
  const float v = SafeAcos(m.y) * kInvPi;
  return Lookup({u, v});
}

std::optional<Environment::Sample> Environment::SampleDirection(Vec2 u) const {
  if (!image_) return Sample{SampleUniformSphere(u), scale_, UniformSpherePdf()};
  const Distribution2D::Sample s = distribution_.Draw(u);
  const Vec3 m = MapDirection(s.uv);
  const float sin_theta = SinTheta(m);
  if (!(sin_theta > 0) || !(s.pdf > 0)) return std::nullopt;
  return Sample{FromMap(m), Lookup(s.uv), s.pdf / (2 * kPi * kPi * sin_theta)};
}

float Environment::Pdf(const Vec3& w) const {
  if (!image_) return UniformSpherePdf();
  const Vec3 m = ToMap(w);
  const float sin_theta = SinTheta(m);
  if (!(sin_theta > 0)) return 0;
  const Vec2 uv{0.5f + std::atan2(m.x, -m.z) * kInv2Pi, SafeAcos(m.y) * kInvPi};
  return distribution_.Pdf(uv) / (2 * kPi * kPi * sin_theta);
}

Rgb Environment::SphereIntegral() const { return integral_; }

std::string Environment::ToString() const {
  if (!image_) return "Environment{constant " + farm::ToString(scale_) + "}";
  return "Environment{map " + std::to_string(image_->width) + "x" + std::to_string(image_->height) +
         " times " + farm::ToString(scale_) + ", rotation cos " + std::to_string(cos_rotation_) + " sin " +
         std::to_string(sin_rotation_) + ", " + distribution_.ToString() + "}";
}

}  // namespace farm
