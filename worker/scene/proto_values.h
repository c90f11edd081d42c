#pragma once

// The contract's value messages as the renderer's types. The scene has passed
// contract::CheckRules, so every component is finite and within the scene's magnitude
// limit, which float holds.

#include "math/rgb.h"
#include "math/vec3.h"
#include "renderfarm/v1/scene.pb.h"

namespace farm {

inline Vec3d Vec3dOf(const renderfarm::v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

inline Rgb RgbOf(const renderfarm::v1::Color& c) {
  return {static_cast<float>(c.r()), static_cast<float>(c.g()), static_cast<float>(c.b())};
}

}  // namespace farm
