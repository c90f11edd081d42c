#pragma once

// A reference image to measure a render's error against: a converged render of the same
// scene, supplied by the user (untrusted bytes).

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "image/image.h"
#include "image/image_error.h"

namespace farm {

// The reference image is wrong: the user's input, not a fault of the farm (the executor
// fails the task as bad input, so the job fails at once with the reason).
class ReferenceImageError : public ImageError {
 public:
  using ImageError::ImageError;
};

// Reads the R, G and B channels (any pixel type; converted to float) of a single-part
// OpenEXR whose data and display windows are both the whole `size` image, and the R, G, B
// of each of `layers` ("direct" for direct.R, direct.G, direct.B) the file has all three
// of (the image's channels are R, G, B, then those). The layers are the light components
// whose error is measured apart from the beauty's (RoundInputs::measured_layers): the
// beauty's error is often dominated by one term (a bright emitter's edges), which hides
// how well another (the indirect light) has converged. Throws ReferenceImageError naming
// what is wrong: unreadable bytes, another size, a missing beauty channel, a NaN or
// infinite value (with its pixel).
Image ReadReferenceExr(std::string_view bytes, ImageSize size, std::span<const std::string> layers);

// Root mean square of a - b over every pixel and the channels R, G, B of `layer` ("" for
// the beauty, "indirect" for indirect.R, indirect.G, indirect.B). Nothing if either image
// lacks one of them. The images must cover the same rectangle.
std::optional<double> LayerRmse(const Image& a, const Image& b, std::string_view layer);

}  // namespace farm
