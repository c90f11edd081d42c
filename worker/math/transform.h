#pragma once

// Affine transforms of points, built once per mesh in double precision and applied to its
// vertices before they go to Embree as floats; and placements, which also move normals and
// tangents (mesh files and instances of meshes).

#include <cmath>
#include <string>

#include "math/math.h"
#include "math/vec3.h"

namespace farm {

struct Affine3d {
  // Row-major linear part; p' = m * p + t.
  double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3d t;

  Vec3d Apply(const Vec3d& p) const {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + t.x,
            m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + t.y,
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + t.z};
  }

  double Determinant() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }

  // The inverse map (the adjugate over the determinant); the caller makes sure the
  // determinant is not 0 (a scene's transforms are checked for it).
  Affine3d Inverse() const {
    Affine3d inv;
    const double det = Determinant();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
        inv.m[i][j] = (m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1]) / det;
      }
    inv.t = -Vec3d(inv.m[0][0] * t.x + inv.m[0][1] * t.y + inv.m[0][2] * t.z,
                   inv.m[1][0] * t.x + inv.m[1][1] * t.y + inv.m[1][2] * t.z,
                   inv.m[2][0] * t.x + inv.m[2][1] * t.y + inv.m[2][2] * t.z);
    return inv;
  }

  // The linear part applied to a direction.
  Vec3d ApplyLinear(const Vec3d& v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }

  // Scale per axis, then rotate by `degrees` about `axis` (through the origin, right-hand
  // rule), then translate: the order of renderfarm.v1.Transform. `axis` need not be unit
  // length but must not be zero when degrees is not.
  static Affine3d ScaleRotateTranslate(const Vec3d& scale, const Vec3d& axis, double degrees,
                                       const Vec3d& translation) {
    double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    if (degrees != 0) {
      // Rodrigues: R = cos I + sin [k]x + (1 - cos) k k^T.
      const Vec3d k = Normalize(axis);
      const double c = std::cos(Radians(degrees)), s = std::sin(Radians(degrees)), C = 1 - c;
      r[0][0] = c + k.x * k.x * C;
      r[0][1] = k.x * k.y * C - k.z * s;
      r[0][2] = k.x * k.z * C + k.y * s;
      r[1][0] = k.y * k.x * C + k.z * s;
      r[1][1] = c + k.y * k.y * C;
      r[1][2] = k.y * k.z * C - k.x * s;
      r[2][0] = k.z * k.x * C - k.y * s;
      r[2][1] = k.z * k.y * C + k.x * s;
      r[2][2] = c + k.z * k.z * C;
    }
    Affine3d a;
    const double sc[3] = {scale.x, scale.y, scale.z};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a.m[i][j] = r[i][j] * sc[j];  // R * diag(scale)
    a.t = translation;
    return a;
  }

  // renderfarm.v1.Transform.matrix: 3 rows of 4 (the linear part, then the translation).
  static Affine3d FromRows(const double (&rows)[12]) {
    Affine3d a;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a.m[i][j] = rows[4 * i + j];
    a.t = {rows[3], rows[7], rows[11]};
    return a;
  }
};

// An object placed in the world by an affine map: points by the map, tangents by its
// linear part M, normals by the inverse transpose of M. A mirroring map (determinant < 0)
// turns the counter-clockwise order of a triangle's corners around; normals moved by M^-T
// keep pointing to the front the corners' original order defined, and a tangent's
// bitangent sign flips (its bitangent is cross(normal, tangent) * w).
struct Placement {
  Affine3d to_world;
  // sign(det M) times the cofactor matrix of M: M^-T up to a positive factor, which a
  // normal loses when it is normalised (and which never overflows for a tiny determinant).
  double normal[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  bool mirrors = false;

  explicit Placement(const Affine3d& a = {}) : to_world(a), mirrors(a.Determinant() < 0) {
    const auto& m = a.m;
    const double sign = mirrors ? -1 : 1;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
        normal[i][j] = sign * (m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1]);
      }
  }

  Vec3 Point(const Vec3& p) const { return Vec3(to_world.Apply(Vec3d(p))); }
  Vec3 Vector(const Vec3& v) const {
    const auto& m = to_world.m;
    const Vec3d d(v);
    return Vec3(Vec3d(m[0][0] * d.x + m[0][1] * d.y + m[0][2] * d.z, m[1][0] * d.x + m[1][1] * d.y + m[1][2] * d.z,
                      m[2][0] * d.x + m[2][1] * d.y + m[2][2] * d.z));
  }
  // Not normalised (its length is meaningless).
  Vec3 Normal(const Vec3& n) const {
    const Vec3d d(n);
    return Vec3(Vec3d(normal[0][0] * d.x + normal[0][1] * d.y + normal[0][2] * d.z,
                      normal[1][0] * d.x + normal[1][1] * d.y + normal[1][2] * d.z,
                      normal[2][0] * d.x + normal[2][1] * d.y + normal[2][2] * d.z));
  }
};

inline std::string ToString(const Affine3d& a) {
  std::string s = "Affine3d{m=[";
  for (int i = 0; i < 3; ++i)
    s += ToString(Vec3d(a.m[i][0], a.m[i][1], a.m[i][2])) + (i < 2 ? ", " : "");
  return s + "], t=" + ToString(a.t) + "}";
}

}  // namespace farm
