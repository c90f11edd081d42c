#include "texture/footprint.h"

#include <cmath>

#include "math/frame.h"
#include "math/math.h"

namespace farm {
namespace {

// The slant no footprint exceeds (1e4 times the pixel): keeps it finite at grazing angles,
// where it already reads the coarsest level.
constexpr float kMinCos = 1e-4f;

}  // namespace

FootprintAxes FootprintOf(const Vec3& d, const Vec3& n, const Vec3& dpdu, const Vec3& dpdv, float width) {
  if (!(width > 0) || !std::isfinite(width)) return {};
  // The Gram matrix of (dpdu, dpdv); a tangent vector a has texture coordinates
  // G^-1 (a.dpdu, a.dpdv).
  const float guu = Dot(dpdu, dpdu), guv = Dot(dpdu, dpdv), gvv = Dot(dpdv, dpdv);
  const float det = guu * gvv - guv * guv;
  if (!(det > 1e-12f * guu * gvv) || !std::isfinite(det)) return {};
  const auto to_uv = [&](const Vec3& a) {
    const float au = Dot(a, dpdu), av = Dot(a, dpdv);
    return Vec2{(gvv * au - guv * av) / det, (guu * av - guv * au) / det};
  };
  const float cos_theta = std::max(kMinCos, AbsDot(d, n));
  const Vec3 along = d - n * Dot(d, n);  // the incidence plane's trace on the surface
  const float along_len = Length(along);
  Vec3 t1, t2;
  if (along_len > 1e-6f) {
    t1 = along / along_len;
    t2 = Cross(n, t1);
  } else {  // head-on: the section is a circle, any orthonormal pair of the plane will do
    const Frame frame = Frame::FromZ(n);
    t1 = frame.x;
    t2 = frame.y;
  }
  return {to_uv(t1 * (width / cos_theta)), to_uv(t2 * width)};
}

}  // namespace farm
