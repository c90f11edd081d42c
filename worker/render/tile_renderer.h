#pragma once

#include <stop_token>

#include "image/image.h"
#include "scene/scene.h"

namespace farm {

// Renders one rectangle of the scene's image into channels R, G, B, A (linear radiance,
// alpha 1 where a camera ray hit geometry). Uses all threads TBB allows. A pixel's value
// depends only on the scene (its seed included) and the pixel, never on the rectangle it
// was rendered in, so tiles rendered anywhere stitch into a bit-identical image. If stop is
// requested the render ends early and the returned image must be discarded.
Image RenderTile(const Scene& scene, const PixelRect& rect, std::stop_token stop = {});

}  // namespace farm
