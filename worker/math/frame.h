#pragma once

// An orthonormal basis (x, y, z), usually built around a surface normal or a direction, to
// move vectors between world space and a local space where warps are written (z up).

#include <cmath>
#include <string>

#include "math/vec3.h"

namespace farm {

struct Frame {
  Vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};

  // A right-handed basis whose z is the unit vector n. Branchless construction of Duff et
  // al., "Building an Orthonormal Basis, Revisited" (JCGT 2017): continuous except at
  // n.z = -0 / +0, and free of the precision loss of cross products with a fixed axis.
  static Frame FromZ(const Vec3& n) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    Frame f;
    f.x = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.y = Vec3(b, sign + n.y * n.y * a, -n.y);
    f.z = n;
    return f;
  }

  Vec3 ToLocal(const Vec3& v) const { return {Dot(v, x), Dot(v, y), Dot(v, z)}; }
  Vec3 FromLocal(const Vec3& v) const { return x * v.x + y * v.y + z * v.z; }
};

inline std::string ToString(const Frame& f) {
  return "Frame{x=" + ToString(f.x) + ", y=" + ToString(f.y) + ", z=" + ToString(f.z) + "}";
}

}  // namespace farm
