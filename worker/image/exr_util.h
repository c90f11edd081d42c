#pragma once

// Small conversions shared by the EXR readers and writers. Internal to image/.

#include <Imath/ImathBox.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <algorithm>
#include <string>
#include <vector>

#include "image/exr_metadata.h"
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

// Adds one FLOAT slice per channel of image, named prefix + the channel, over its
// interleaved pixels.
inline void InsertSlices(Imf::FrameBuffer& fb, const Image& image, const std::string& prefix = "") {
  const std::size_t x_stride = sizeof(float) * image.channels().size();
  const std::size_t y_stride = x_stride * static_cast<std::size_t>(image.rect().width);
  for (std::size_t c = 0; c < image.channels().size(); ++c) {
    fb.insert(prefix + image.channels()[c],
              Imf::Slice::Make(Imf::FLOAT, image.data().data() + c, ToBox(image.rect()), x_stride,
                               y_stride));
  }
}

// The names of header's channels (sorted, as OpenEXR keeps them), each of which must be
// full-resolution FLOAT; what names the file in the message ("tile", "accumulation").
inline std::vector<std::string> FloatChannels(const Imf::Header& header, const std::string& what) {
  std::vector<std::string> names;
  for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
    names.emplace_back(it.name());
    const Imf::Channel& ch = it.channel();
    if (ch.type != Imf::FLOAT || ch.xSampling != 1 || ch.ySampling != 1) {
      throw ImageError(what + " channel " + it.name() + " is not full-resolution FLOAT");
    }
  }
  return names;
}

// "[a,b,c]": channel names sorted, for messages and for comparing sets of names.
inline std::string JoinNames(std::vector<std::string> names) {
  std::sort(names.begin(), names.end());
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ",") + n;
  return "[" + s + "]";
}

// Writes m into the header (exr_metadata.h names the attributes).
inline void AddExrMetadata(const ExrMetadata& m, Imf::Header& header) {
  Imf::addChromaticities(header, Imf::Chromaticities());  // OpenEXR's default: Rec. 709, D65
  const auto matrix = [](const std::array<double, 16>& v) {
    Imath::M44f out;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) out[i][j] = static_cast<float>(v[i * 4 + j]);
    return out;
  };
  if (m.world_to_camera) Imf::addWorldToCamera(header, matrix(*m.world_to_camera));
  if (m.world_to_ndc) Imf::addWorldToNDC(header, matrix(*m.world_to_ndc));
  if (m.render_seconds) header.insert("renderTime", Imf::DoubleAttribute(*m.render_seconds));
  if (m.samples_per_pixel) header.insert("samplesPerPixel", Imf::IntAttribute(*m.samples_per_pixel));
  if (m.rounds) header.insert("rounds", Imf::IntAttribute(*m.rounds));
  if (!m.software.empty()) header.insert("software", Imf::StringAttribute(m.software));
}

}  // namespace farm
