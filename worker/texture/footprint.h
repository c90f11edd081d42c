#pragma once

// The footprint of a texture lookup: what a pixel (or a photon, or a gather ray) covers of
// a surface, in texture coordinates.
//
// Rays carry a cone (Akenine-Moller et al., "Texture Level of Detail Strategies for
// Real-Time Ray Tracing", Ray Tracing Gems, 2019): a width at the origin and a spread
// angle, so the cone is width + spread * t wide at distance t. Camera rays start with the
// angle one pixel subtends at the image's centre (Camera::PixelSpreadAngle) and width 0;
// a specular bounce passes the cone on with the width it has reached and the same spread
// (surfaces are taken as flat: curvature's widening or narrowing is ignored); rays leaving
// a diffuse or glossy bounce get the spread of the lobe's share of directions (the
// integrator says which), and a cone that has left a diffuse bounce reads with the
// isotropic filter (TextureFilter::kIsotropic): it is then so wide that the footprint's
// shape no longer shows, only its size does (as in ray-differential practice, which reads
// coarse levels after the first diffuse bounce). Every camera sample filters over its whole pixel's footprint,
// whatever the number of samples: a pixel is never aliased, at the price of a slightly
// softer texture when many samples would have resolved it anyway.
//
// Where a cone of width w meets a surface along d, its section is an ellipse with axes w
// (across the incidence plane) and w / |cos theta| (along it, stretched by the slant);
// mapping both axes through the inverse of the surface's (dp/du, dp/dv) gives the texture
// footprint, which OIIO's anisotropic filter reads.

#include "math/vec3.h"
#include "texture/texture_system.h"

namespace farm {

struct RayCone {
  float width = 0;
  float spread = 0;  // radians
  TextureFilter filter = TextureFilter::kAnisotropic;

  float WidthAt(float t) const { return width + spread * t; }
};

// The two axes of the footprint (TextureLookup::axis1, axis2) of a cone `width` wide
// arriving along d (unit) at a point with unit normal n and derivatives dpdu, dpdv. Zero
// axes (the finest level) where the derivatives are degenerate or the width is 0.
struct FootprintAxes {
  Vec2 axis1, axis2;
};
FootprintAxes FootprintOf(const Vec3& d, const Vec3& n, const Vec3& dpdu, const Vec3& dpdv, float width);

}  // namespace farm
