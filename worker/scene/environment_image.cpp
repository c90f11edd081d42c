#include "scene/environment_image.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace farm {
namespace {

// A file name whose extension picks OpenImageIO's reader, from the file's magic number.
const char* NameByContent(std::string_view b) {
  if (b.starts_with("\x76\x2f\x31\x01")) return "environment.exr";
  if (b.starts_with("#?")) return "environment.hdr";  // #?RADIANCE or #?RGBE
  if (b.starts_with("\x89PNG")) return "environment.png";
  if (b.starts_with("\xff\xd8\xff")) return "environment.jpg";
  return nullptr;
}

float SrgbToLinear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

}  // namespace

EnvironmentImage DecodeEnvironmentImage(std::string_view bytes, EnvironmentEncoding encoding,
                                        std::uint64_t max_pixels) {
  const char* name = NameByContent(bytes);
  if (!name) throw EnvironmentImageError("is not an OpenEXR, Radiance HDR, PNG or JPEG image");
  OIIO::Filesystem::IOMemReader proxy(const_cast<char*>(bytes.data()), bytes.size());
  const std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(name, nullptr, &proxy);
  if (!in) throw EnvironmentImageError("cannot be read: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  const std::uint64_t pixels = std::uint64_t(std::max(spec.width, 0)) * std::uint64_t(std::max(spec.height, 0));
  if (pixels == 0) throw EnvironmentImageError("has no pixels");
  if (pixels > max_pixels)
    throw EnvironmentImageError("has " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                                " pixels, more than the " + std::to_string(max_pixels) + " a texture may have");
  const int channels = spec.nchannels;
  std::vector<float> values(pixels * std::uint64_t(channels));
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, values.data()))
    throw EnvironmentImageError("cannot be decoded: " + in->geterror());
  const bool is_float = spec.format.basetype == OIIO::TypeDesc::FLOAT || spec.format.basetype == OIIO::TypeDesc::HALF;
  const bool srgb = encoding == EnvironmentEncoding::kSrgb || (encoding == EnvironmentEncoding::kByFormat && !is_float);

  EnvironmentImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.texels.resize(pixels);
  const bool grey = channels < 3;
  for (std::uint64_t i = 0; i < pixels; ++i) {
    const float* p = values.data() + i * channels;
    float c[3] = {p[0], grey ? p[0] : p[1], grey ? p[0] : p[2]};
    for (float& v : c) {
      if (!std::isfinite(v))
        throw EnvironmentImageError("pixel (" + std::to_string(i % spec.width) + ", " + std::to_string(i / spec.width) +
                                    ") is not finite");
      v = std::max(v, 0.0f);  // negative values (left by some filters) light nothing
      if (srgb) v = SrgbToLinear(v);
    }
    image.texels[i] = Rgb(c[0], c[1], c[2]);
  }
  return image;
}

}  // namespace farm
