#pragma once

// A reference image to measure a render's error against: a converged render of the same
// scene, supplied by the user (untrusted bytes).

#include <string_view>

#include "image/image.h"

namespace farm {

// Reads the R, G and B channels (any pixel type; converted to float) of a single-part
// OpenEXR whose data and display windows are both the whole `size` image. Throws
// ImageError naming what is wrong: unreadable bytes, another size, a missing channel, a
// NaN or infinite value (with its pixel).
Image ReadReferenceExr(std::string_view bytes, ImageSize size);

// Root mean square of a - b over every pixel and channel R, G, B (the first three channels
// of both images, which must cover the same rectangle).
double BeautyRmse(const Image& a, const Image& b);

}  // namespace farm
