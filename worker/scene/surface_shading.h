#pragma once

// A material as it is at one hit: its textures read there and its shading normal set.
//
// Only principled materials have textures (scene.proto); every other kind is returned as
// declared. For a principled material at a hit with texture coordinates:
//
//   base colour     RGB times the base colour texture's (sRGB decoded)
//   metallic        times the metallic-roughness texture's blue channel (linear)
//   roughness       times its green one; a material whose factor makes it glossy
//                   (roughness >= principled_specular_roughness) stays glossy: a textured
//                   roughness below the threshold is raised to it, since the capabilities
//                   (and so the photon maps the planner asked for) are the factors'
//   normal          the normal map (glTF: tangent space, +X along dp/du, +Y up the image,
//                   that is towards decreasing v; XY scaled by normal_scale) about the
//                   hit's shading normal
//   emission        RGB times the emission texture's (sRGB decoded)
//
// A lookup reads the texture over the footprint of the ray (texture/footprint.h): the
// width the ray's cone has reached where it meets the surface, with the cone's filter; 0
// for a point lookup at the finest level (photons, and the cut-out test, each one sample
// among very many). The emission texture is read only where the caller counts emission.
//
// Emitters: an area light is sampled (for direct light and photon emission) with its
// material's emission times the emission texture's mean, while rays that see it read the
// texture where they hit: a textured emitter's light is right on average, not in its
// pattern.

#include <functional>

#include "math/rgb.h"
#include "math/vec3.h"
#include "scene/materials.h"
#include "scene/scene_data.h"

namespace farm {

// How MaterialAt reads a hit's textures.
struct TextureRead {
  float footprint_width = 0;  // of the ray's cone at the hit
  TextureFilter filter = TextureFilter::kAnisotropic;
  // Whether the emission texture is read: only camera paths count what they see emitted;
  // gather rays, glossy bounces and photons leave emission to direct light.
  bool emission = true;
};

// The material of `hit` there, for a ray arriving along `direction` (unit), its textures
// read as `read` says (emission as declared where it is not read).
Material MaterialAt(const SceneData& scene, const SurfaceHit& hit, const Vec3& direction, const TextureRead& read);

// Whether the surface is not there at the hit: an alpha-masked principled material whose
// opacity (1 - transparency, times the base colour texture's alpha read at the finest
// level) is below its cutoff.
bool IsCutOut(const SceneData& scene, const CutoutHit& hit);

// The cut-out test of material `material` for the accelerator's per-material hook (true
// ignores the hit, for camera, shadow and photon rays alike): IsCutOut for an alpha-masked
// principled material, empty (cuts nothing) for every other. It reads `scene`, which must
// outlive it.
CutoutTest CutoutOf(const SceneData& scene, int material);

// The radiance an area light of this material is sampled with: Emission(material), times
// the emission texture's mean for a principled one.
Rgb AreaLightRadiance(const SceneData& scene, const Material& material);

}  // namespace farm
