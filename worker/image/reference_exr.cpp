#include "image/reference_exr.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <string>
#include <vector>

#include "image/exr_memory_stream.h"
#include "image/exr_util.h"
#include "image/image_error.h"

namespace farm {

namespace {

// The names of layer's R, G and B channels: "R", "G", "B" for the beauty ("").
std::array<std::string, 3> RgbNames(std::string_view layer) {
  const std::string prefix = layer.empty() ? "" : std::string(layer) + ".";
  return {prefix + "R", prefix + "G", prefix + "B"};
}

// Index of each of names in image's channels; nothing if one is missing.
std::optional<std::array<int, 3>> ChannelIndices(const Image& image, const std::array<std::string, 3>& names) {
  std::array<int, 3> out{};
  for (int c = 0; c < 3; ++c) {
    const auto& all = image.channels();
    const auto it = std::find(all.begin(), all.end(), names[c]);
    if (it == all.end()) return std::nullopt;
    out[c] = int(it - all.begin());
  }
  return out;
}

// R, G, B, then the channels of each of layers the header has all three of.
std::vector<std::string> ReferenceChannels(const Imf::Header& header, std::span<const std::string> layers) {
  std::vector<std::string> channels;
  for (const std::string& name : RgbNames("")) channels.push_back(name);
  for (std::string_view layer : layers) {
    const std::array<std::string, 3> names = RgbNames(layer);
    if (std::all_of(names.begin(), names.end(),
                    [&](const std::string& n) { return header.channels().findChannel(n) != nullptr; })) {
      channels.insert(channels.end(), names.begin(), names.end());
    }
  }
  return channels;
}

}  // namespace

Image ReadReferenceExr(std::string_view bytes, ImageSize size, std::span<const std::string> layers) {
  const PixelRect whole{0, 0, size.width, size.height};
  Image image(whole, {});
  try {
    ExrMemoryIStream stream(bytes);
    Imf::InputFile file(stream);
    const Imf::Header& header = file.header();
    RequireWholeImage(header, size, "reference image");
    image = Image(whole, ReferenceChannels(header, layers));
    const std::size_t x_stride = sizeof(float) * image.channels().size();
    const std::size_t y_stride = x_stride * static_cast<std::size_t>(size.width);
    Imf::FrameBuffer fb;
    for (int c = 0; c < image.channel_count(); ++c) {
      const std::string& name = image.channels()[c];
      const Imf::Channel* ch = header.channels().findChannel(name);
      if (!ch) throw ReferenceImageError("reference image has no channel " + name);
      if (ch->xSampling != 1 || ch->ySampling != 1) {
        throw ReferenceImageError("reference image channel " + name + " is subsampled");
      }
      fb.insert(name, Imf::Slice::Make(Imf::FLOAT, image.data().data() + c, ToBox(whole),
                                       x_stride, y_stride));
    }
    file.setFrameBuffer(fb);
    file.readPixels(whole.y, whole.y_end() - 1);
  } catch (const ReferenceImageError&) {
    throw;
  } catch (const std::exception& e) {
    throw ReferenceImageError(std::string("reference image is not a readable OpenEXR file: ") + e.what());
  }
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      for (int c = 0; c < image.channel_count(); ++c) {
        if (std::isfinite(image.pixel(x, y)[c])) continue;
        throw ReferenceImageError("reference image channel " + image.channels()[c] + " at pixel (" +
                         std::to_string(x) + ", " + std::to_string(y) + ") is not finite");
      }
    }
  }
  return image;
}

std::optional<double> LayerRmse(const Image& a, const Image& b, std::string_view layer) {
  if (a.rect() != b.rect()) throw ReferenceImageError("LayerRmse: images of different extents");
  const std::array<std::string, 3> names = RgbNames(layer);
  const std::optional<std::array<int, 3>> ia = ChannelIndices(a, names);
  const std::optional<std::array<int, 3>> ib = ChannelIndices(b, names);
  if (!ia || !ib) return std::nullopt;
  const PixelRect& r = a.rect();
  double sum = 0;
  for (int y = r.y; y < r.y_end(); ++y) {
    for (int x = r.x; x < r.x_end(); ++x) {
      for (int c = 0; c < 3; ++c) {
        const double d = double(a.pixel(x, y)[(*ia)[c]]) - double(b.pixel(x, y)[(*ib)[c]]);
        sum += d * d;
      }
    }
  }
  return std::sqrt(sum / (3.0 * r.width * r.height));
}

}  // namespace farm
