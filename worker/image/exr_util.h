#pragma once

// Small conversions shared by the EXR readers and writers. Internal to image/.

#include <Imath/ImathBox.h>

#include <string>

#include "image/image.h"

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

}  // namespace farm
