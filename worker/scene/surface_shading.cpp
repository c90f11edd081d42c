#include "scene/surface_shading.h"

#include <algorithm>
#include <cmath>
#include <variant>

#include "contract/rules.h"
#include "scene/ggx.h"
#include "texture/footprint.h"

namespace farm {
namespace {

// The normal a tangent-space normal map's texel (RGB in [0, 1]) stands for about ns, or ns
// where the derivatives give no tangent.
Vec3 MappedNormal(const Vec3& ns, const Vec3& dpdu, const Vec3& dpdv, const Rgb& texel, float scale) {
  const Vec3 along = dpdu - ns * Dot(ns, dpdu);
  const float length = Length(along);
  if (!(length > 0)) return ns;
  const Vec3 t = along / length;
  Vec3 b = Cross(ns, t);
  if (Dot(b, dpdv) > 0) b = -b;  // +Y of the map is up the image: towards decreasing v
  const Vec3 m = t * ((2 * texel.r - 1) * scale) + b * ((2 * texel.g - 1) * scale) + ns * (2 * texel.b - 1);
  const float m_length = Length(m);
  return m_length > 0 && std::isfinite(m_length) ? m / m_length : ns;
}

// The lowest roughness a glossy principled material is shaded with (see the file comment).
float GlossyRoughnessFloor() {
  return static_cast<float>(contract::SceneLimits().principled_specular_roughness());
}

}  // namespace

Material MaterialAt(const SceneData& scene, const SurfaceHit& hit, const Vec3& direction, const TextureRead& read) {
  const Material& declared = scene.material_of(hit);
  const auto* principled = std::get_if<PrincipledMaterial>(&declared);
  if (!principled) return declared;
  PrincipledMaterial m = *principled;
  m.shading_normal = LengthSquared(hit.ns) > 0 ? hit.ns : hit.n;
  if (!hit.has_uv || !scene.texture_system) return m;
  const FootprintAxes footprint = FootprintOf(direction, hit.n, hit.dpdu, hit.dpdv, read.footprint_width);
  const TextureLookup at{hit.uv, footprint.axis1, footprint.axis2, read.filter};
  const auto texel = [&](TextureIndex index) {
    const SceneTexture& texture = scene.textures[index];
    return scene.texture_system->Lookup(texture.prepared, at, texture.wrap);
  };
  if (m.base_color_texture != kNoTexture) m.lobes.base_color = m.lobes.base_color * texel(m.base_color_texture).rgb;
  if (m.metallic_roughness_texture != kNoTexture) {
    const Rgb mr = texel(m.metallic_roughness_texture).rgb;
    m.lobes.metallic = std::clamp(m.lobes.metallic * mr.b, 0.0f, 1.0f);
    m.roughness = std::clamp(m.roughness * mr.g, m.lobes.specular ? 0.0f : GlossyRoughnessFloor(), 1.0f);
    m.lobes.alpha = std::max(kMinGgxAlpha, m.roughness * m.roughness);
  }
  if (m.normal_texture != kNoTexture)
    m.shading_normal = MappedNormal(m.shading_normal, hit.dpdu, hit.dpdv, texel(m.normal_texture).rgb, m.normal_scale);
  if (read.emission && m.emission_texture != kNoTexture) m.emission = m.emission * texel(m.emission_texture).rgb;
  return m;
}

bool IsCutOut(const SceneData& scene, const CutoutHit& hit) {
  const auto* m = std::get_if<PrincipledMaterial>(&scene.materials[hit.material]);
  if (!m || !m->alpha_mask) return false;
  float opacity = m->opacity;
  if (m->base_color_texture != kNoTexture && hit.has_uv && scene.texture_system) {
    const SceneTexture& texture = scene.textures[m->base_color_texture];
    opacity *= scene.texture_system->Lookup(texture.prepared, TextureLookup{hit.uv, {}, {}}, texture.wrap).alpha;
  }
  return opacity < m->alpha_cutoff;
}

CutoutTest CutoutOf(const SceneData& scene, int material) {
  const auto* m = std::get_if<PrincipledMaterial>(&scene.materials[material]);
  if (!m || !m->alpha_mask) return {};
  return [&scene](const CutoutHit& hit) { return IsCutOut(scene, hit); };
}

Rgb AreaLightRadiance(const SceneData& scene, const Material& material) {
  const Rgb radiance = Emission(material);
  const auto* m = std::get_if<PrincipledMaterial>(&material);
  if (!m || m->emission_texture == kNoTexture || !scene.texture_system || radiance.IsBlack()) return radiance;
  const SceneTexture& texture = scene.textures[m->emission_texture];
  return radiance * scene.texture_system->Average(texture.prepared).rgb;
}

}  // namespace farm
