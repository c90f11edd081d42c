#pragma once

// Small conversions shared by the EXR readers and writers. Internal to image/.

#include <Imath/ImathBox.h>
#include <OpenEXR/ImfHeader.h>

#include <string>

#include "image/image.h"
#include "image/image_error.h"

namespace farm {

inline Imath::Box2i ToBox(const PixelRect& r) {
  return Imath::Box2i(Imath::V2i(r.x, r.y), Imath::V2i(r.x_end() - 1, r.y_end() - 1));
}

inline PixelRect ToRect(const Imath::Box2i& b) {
  return PixelRect{b.min.x, b.min.y, b.max.x - b.min.x + 1, b.max.y - b.min.y + 1};
}

inline std::string ToString(const PixelRect& r) {
  return "(x " + std::to_string(r.x) + ", y " + std::to_string(r.y) + ", " +
         std::to_string(r.width) + "x" + std::to_string(r.height) + ")";
}

inline std::string ToString(const ImageSize& s) {
  return std::to_string(s.width) + "x" + std::to_string(s.height);
}

// Refuses a header whose data or display window is not the whole image of this size;
// what names the file in the message ("reference image", "accumulation").
inline void RequireWholeImage(const Imf::Header& header, ImageSize size, const std::string& what) {
  const PixelRect whole{0, 0, size.width, size.height};
  const PixelRect display = ToRect(header.displayWindow());
  const PixelRect data = ToRect(header.dataWindow());
  if (display != whole || data != whole) {
    throw ImageError(what + " covers " + ToString(data) + " of " + ToString(display) +
                     ", not the whole " + ToString(size) + " image");
  }
}

}  // namespace farm
