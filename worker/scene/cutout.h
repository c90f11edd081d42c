#pragma once

// The alpha-test hook: whether a surface is not there at a hit (a cut-out, such as a
// leaf's outline in a texture's alpha). True ignores the hit, for camera, shadow and photon
// rays alike. Set per material when the scene is built (SceneOptions); the hit it gets is
// refined as any other (SurfaceHit).

#include <functional>

namespace farm {

struct SurfaceHit;

using CutoutTest = std::function<bool(const SurfaceHit& hit)>;

}  // namespace farm
