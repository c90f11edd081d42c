#pragma once

// Linear RGB (Rec. 709 primaries) radiance, irradiance or reflectance. A separate type from
// Vec3 so that a colour can never be passed where a direction is expected. Light is
// carried in RGB except past a dispersive surface, where a path carries one wavelength
// (spectral/monochrome.h) and converts back to this for the film.

#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>

namespace farm {

struct Rgb {
  float r = 0, g = 0, b = 0;

  constexpr Rgb() = default;
  constexpr Rgb(float r_, float g_, float b_) : r(r_), g(g_), b(b_) {}
  constexpr explicit Rgb(float v) : r(v), g(v), b(v) {}

  constexpr Rgb operator+(const Rgb& o) const { return {r + o.r, g + o.g, b + o.b}; }
  // Light is never negative, but a difference of two estimates of it (the bias layer) is.
  constexpr Rgb operator-(const Rgb& o) const { return {r - o.r, g - o.g, b - o.b}; }
  constexpr Rgb operator*(const Rgb& o) const { return {r * o.r, g * o.g, b * o.b}; }
  constexpr Rgb operator*(float s) const { return {r * s, g * s, b * s}; }
  constexpr Rgb operator/(float s) const { return {r / s, g / s, b / s}; }
  constexpr Rgb& operator+=(const Rgb& o) { return *this = *this + o; }
  constexpr Rgb& operator*=(float s) { return *this = *this * s; }
  friend constexpr Rgb operator*(float s, const Rgb& c) { return c * s; }
  friend constexpr bool operator==(const Rgb&, const Rgb&) = default;

  constexpr bool IsBlack() const { return r == 0 && g == 0 && b == 0; }
  bool IsFinite() const { return std::isfinite(r) && std::isfinite(g) && std::isfinite(b); }
  // Rec. 709 luminance: the weight by which lights are picked in proportion to power.
  constexpr float Luminance() const { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }
};

inline std::string ToString(const Rgb& c) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "rgb(%.9g, %.9g, %.9g)", double(c.r), double(c.g), double(c.b));
  return buf;
}

inline std::ostream& operator<<(std::ostream& os, const Rgb& c) { return os << ToString(c); }

}  // namespace farm
