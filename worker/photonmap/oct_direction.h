#pragma once

// Octahedral encoding of unit directions into 16 bits (docs/photon-snapshot.md, "Shared
// encodings"). Why octahedral: it spreads the codes almost uniformly over the sphere, so 8+8
// bits give ~0.6 degrees worst error where spherical angles would waste codes at the poles.
// Only the worker encodes or decodes directions; the coordinator copies the codes verbatim.

#include <cmath>
#include <cstdint>

#include "math/vec3.h"

namespace farm {
namespace oct_detail {

inline float SignNotZero(float v) { return v < 0 ? -1.0f : 1.0f; }

// Folds d onto the unit square [-1,1]^2; a zero or non-finite vector maps to +z (0,0).
inline void Fold(const Vec3& d, float& px, float& py) {
  float l1 = std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z);
  if (!(l1 > 0) || !std::isfinite(l1)) {
    px = py = 0;
    return;
  }
  px = d.x / l1;
  py = d.y / l1;
  if (d.z < 0) {
    float fx = (1 - std::fabs(py)) * SignNotZero(px);
    float fy = (1 - std::fabs(px)) * SignNotZero(py);
    px = fx;
    py = fy;
  }
}

// Signed-normalised quantisation: p in [-1,1] -> code in [0, 2h] with 0 -> h exactly, so the
// axes (the most common normals: walls, floors) survive a round trip without error. The top
// code (2h + 1) is never written; decoding clamps it.
inline std::uint32_t Quantize(float p, float h) {
  float q = std::floor(p * h + 0.5f);
  q = q < -h ? -h : (q > h ? h : q);
  return static_cast<std::uint32_t>(q + h);
}

inline float Dequantize(std::uint32_t code, float h) {
  float p = (float(code) - h) / h;
  return p > 1 ? 1 : p;
}

inline Vec3 Unfold(float x, float y) {
  float z = 1 - std::fabs(x) - std::fabs(y);
  if (z < 0) {
    float ux = (1 - std::fabs(y)) * SignNotZero(x);
    float uy = (1 - std::fabs(x)) * SignNotZero(y);
    x = ux;
    y = uy;
  }
  return Normalize(Vec3(x, y, z));
}

}  // namespace oct_detail

// wi: u in bits 0-7, v in bits 8-15.
inline std::uint16_t EncodeOct8(const Vec3& d) {
  float px, py;
  oct_detail::Fold(d, px, py);
  return static_cast<std::uint16_t>(oct_detail::Quantize(px, 127.0f) |
                                    (oct_detail::Quantize(py, 127.0f) << 8));
}

inline Vec3 DecodeOct8(std::uint16_t code) {
  float x = oct_detail::Dequantize(code & 0xffu, 127.0f);
  float y = oct_detail::Dequantize(code >> 8u, 127.0f);
  return oct_detail::Unfold(x, y);
}

// Normal: bits 0-1 zero (the snapshot keeps the split axis there), u in bits 2-8, v in 9-15.
inline std::uint16_t EncodeOct7Normal(const Vec3& n) {
  float px, py;
  oct_detail::Fold(n, px, py);
  return static_cast<std::uint16_t>((oct_detail::Quantize(px, 63.0f) << 2) |
                                    (oct_detail::Quantize(py, 63.0f) << 9));
}

// Ignores bits 0-1, so it also decodes a snapshot's normal-and-axis field.
inline Vec3 DecodeOct7Normal(std::uint16_t code) {
  float x = oct_detail::Dequantize((code >> 2u) & 0x7fu, 63.0f);
  float y = oct_detail::Dequantize(code >> 9u, 63.0f);
  return oct_detail::Unfold(x, y);
}

}  // namespace farm
