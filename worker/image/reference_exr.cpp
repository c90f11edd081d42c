#include "image/reference_exr.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>

#include <cmath>
#include <exception>

#include "image/exr_memory_stream.h"
#include "image/exr_util.h"
#include "image/image_error.h"

namespace farm {

Image ReadReferenceExr(std::string_view bytes, ImageSize size) {
  const PixelRect whole{0, 0, size.width, size.height};
  Image image(whole, {"R", "G", "B"});
  try {
    ExrMemoryIStream stream(bytes);
    Imf::InputFile file(stream);
    const Imf::Header& header = file.header();
    RequireWholeImage(header, size, "reference image");
    const std::size_t x_stride = sizeof(float) * 3;
    const std::size_t y_stride = x_stride * static_cast<std::size_t>(size.width);
    Imf::FrameBuffer fb;
    for (int c = 0; c < 3; ++c) {
      const std::string& name = image.channels()[c];
      const Imf::Channel* ch = header.channels().findChannel(name);
      if (!ch) throw ImageError("reference image has no channel " + name);
      if (ch->xSampling != 1 || ch->ySampling != 1) {
        throw ImageError("reference image channel " + name + " is subsampled");
      }
      fb.insert(name, Imf::Slice::Make(Imf::FLOAT, image.data().data() + c, ToBox(whole),
                                       x_stride, y_stride));
    }
    file.setFrameBuffer(fb);
    file.readPixels(whole.y, whole.y_end() - 1);
  } catch (const ImageError&) {
    throw;
  } catch (const std::exception& e) {
    throw ImageError(std::string("reference image is not a readable OpenEXR file: ") + e.what());
  }
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        if (std::isfinite(image.pixel(x, y)[c])) continue;
        throw ImageError("reference image channel " + image.channels()[c] + " at pixel (" +
                         std::to_string(x) + ", " + std::to_string(y) + ") is not finite");
      }
    }
  }
  return image;
}

double BeautyRmse(const Image& a, const Image& b) {
  if (a.rect() != b.rect() || a.channel_count() < 3 || b.channel_count() < 3) {
    throw ImageError("BeautyRmse: images of different extents or without R, G, B");
  }
  const PixelRect& r = a.rect();
  double sum = 0;
  for (int y = r.y; y < r.y_end(); ++y) {
    for (int x = r.x; x < r.x_end(); ++x) {
      for (int c = 0; c < 3; ++c) {
        const double d = double(a.pixel(x, y)[c]) - double(b.pixel(x, y)[c]);
        sum += d * d;
      }
    }
  }
  return std::sqrt(sum / (3.0 * r.width * r.height));
}

}  // namespace farm
