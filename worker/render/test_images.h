#pragma once

// Comparing rendered images in the render tests (not linked into the worker).

#include <gtest/gtest.h>

#include <cstring>

#include "image/image.h"

namespace farm::testing {

// Pixel values of `part` equal, bit for bit, those of `whole` at the same image pixels.
inline void ExpectSamePixels(const Image& whole, const Image& part) {
  const PixelRect r = part.rect();
  for (int y = r.y; y < r.y_end(); ++y)
    for (int x = r.x; x < r.x_end(); ++x)
      ASSERT_EQ(std::memcmp(whole.pixel(x, y), part.pixel(x, y), whole.channel_count() * sizeof(float)), 0)
          << "pixel " << x << ", " << y;
}

}  // namespace farm::testing
