#pragma once

// The alpha-test hook: whether a surface is not there at a hit (a cut-out, such as a
// leaf's outline in a texture's alpha). True ignores the hit, for camera, shadow and photon
// rays alike. Set per material when the scene is built (SceneOptions). The accelerator asks
// it about every candidate hit along a ray on the geometry of materials that have one, so
// it gets only what an alpha test reads (SceneData::CutoutHitOf), not a refined SurfaceHit.

#include <functional>

#include "math/vec3.h"

namespace farm {

// A candidate hit as the cut-out test sees it: its material (index into
// SceneData::materials) and texture coordinates (as SurfaceHit has them).
struct CutoutHit {
  int material = 0;
  Vec2 uv;
  bool has_uv = false;
};

using CutoutTest = std::function<bool(const CutoutHit& hit)>;

}  // namespace farm
