#pragma once

// Three-component vectors and points.
//
// Why float: Embree stores geometry and returns hit distances in float, so a hit point is
// float-accurate whatever we compute it with afterwards; shading in float halves memory
// traffic and matches what photons will store later. The cost is self-intersection, which
// ray.h handles with a scale-aware offset, and cancellation in a few formulas (1 - cos of a
// small angle), which the code concerned avoids explicitly. Vec3d exists for the few places
// that build data once from the double-precision scene description (mesh transforms,
// camera basis) and for analytic ground truth in tests.

#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>

namespace farm {

template <typename T>
struct Vec3T {
  T x = 0, y = 0, z = 0;

  constexpr Vec3T() = default;
  constexpr Vec3T(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
  template <typename U>
  constexpr explicit Vec3T(const Vec3T<U>& v) : x(T(v.x)), y(T(v.y)), z(T(v.z)) {}

  constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }

  constexpr Vec3T operator-() const { return {-x, -y, -z}; }
  constexpr Vec3T operator+(const Vec3T& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vec3T operator-(const Vec3T& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vec3T operator*(T s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3T operator/(T s) const { return {x / s, y / s, z / s}; }
  constexpr Vec3T& operator+=(const Vec3T& o) { return *this = *this + o; }
  constexpr Vec3T& operator-=(const Vec3T& o) { return *this = *this - o; }
  constexpr Vec3T& operator*=(T s) { return *this = *this * s; }

  friend constexpr Vec3T operator*(T s, const Vec3T& v) { return v * s; }
  friend constexpr bool operator==(const Vec3T&, const Vec3T&) = default;
};

using Vec3 = Vec3T<float>;
using Vec3d = Vec3T<double>;

template <typename T>
constexpr T Dot(const Vec3T<T>& a, const Vec3T<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

template <typename T>
constexpr T AbsDot(const Vec3T<T>& a, const Vec3T<T>& b) {
  T d = Dot(a, b);
  return d < 0 ? -d : d;
}

template <typename T>
constexpr Vec3T<T> Cross(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

template <typename T>
constexpr T LengthSquared(const Vec3T<T>& v) {
  return Dot(v, v);
}

template <typename T>
T Length(const Vec3T<T>& v) {
  return std::sqrt(LengthSquared(v));
}

template <typename T>
T Distance(const Vec3T<T>& a, const Vec3T<T>& b) {
  return Length(a - b);
}

// Callers guarantee v is not zero (check LengthSquared first where it may be).
template <typename T>
Vec3T<T> Normalize(const Vec3T<T>& v) {
  return v / Length(v);
}

template <typename T>
Vec3T<T> Abs(const Vec3T<T>& v) {
  return {std::abs(v.x), std::abs(v.y), std::abs(v.z)};
}

template <typename T>
constexpr T MaxComponent(const Vec3T<T>& v) {
  return v.x > v.y ? (v.x > v.z ? v.x : v.z) : (v.y > v.z ? v.y : v.z);
}

template <typename T>
Vec3T<T> Min(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {std::fmin(a.x, b.x), std::fmin(a.y, b.y), std::fmin(a.z, b.z)};
}

template <typename T>
Vec3T<T> Max(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {std::fmax(a.x, b.x), std::fmax(a.y, b.y), std::fmax(a.z, b.z)};
}

template <typename T>
bool IsFinite(const Vec3T<T>& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// v flipped, if needed, into the hemisphere around n.
template <typename T>
constexpr Vec3T<T> FaceForward(const Vec3T<T>& v, const Vec3T<T>& n) {
  return Dot(v, n) < 0 ? -v : v;
}

template <typename T>
std::string ToString(const Vec3T<T>& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "[ %.9g, %.9g, %.9g ]", double(v.x), double(v.y), double(v.z));
  return buf;
}

// GoogleTest prints values through operator<<, so failing assertions show the vector.
template <typename T>
std::ostream& operator<<(std::ostream& os, const Vec3T<T>& v) {
  return os << ToString(v);
}

// Two floats: sample points on [0,1)^2, film positions, barycentrics.
struct Vec2 {
  float x = 0, y = 0;
  friend constexpr bool operator==(const Vec2&, const Vec2&) = default;
};

inline std::string ToString(const Vec2& v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "[ %.9g, %.9g ]", double(v.x), double(v.y));
  return buf;
}

inline std::ostream& operator<<(std::ostream& os, const Vec2& v) { return os << ToString(v); }

}  // namespace farm
