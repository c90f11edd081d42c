#include "image/accumulation_exr.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>

#include <algorithm>
#include <cmath>
#include <exception>

#include "image/exr_memory_stream.h"
#include "image/exr_util.h"
#include "image/image_error.h"

namespace farm {
namespace {

const std::vector<std::string>& SquaredChannels() {
  static const std::vector<std::string> rgb = {"R", "G", "B"};
  return rgb;
}

// Slices over both images under their file names.
Imf::FrameBuffer SlicesOver(const Accumulation& a) {
  Imf::FrameBuffer fb;
  for (const auto* part : {&a.sums, &a.squares}) {
    const std::string prefix = part == &a.sums ? "sum." : "sumsq.";
    const std::size_t x_stride = sizeof(float) * part->channels().size();
    const std::size_t y_stride = x_stride * static_cast<std::size_t>(part->rect().width);
    for (std::size_t c = 0; c < part->channels().size(); ++c) {
      fb.insert(prefix + part->channels()[c],
                Imf::Slice::Make(Imf::FLOAT, part->data().data() + c, ToBox(part->rect()),
                                 x_stride, y_stride));
    }
  }
  return fb;
}

std::string JoinNames(std::vector<std::string> names) {
  std::sort(names.begin(), names.end());
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ",") + n;
  return "[" + s + "]";
}

void CheckValues(const Image& image, const std::string& prefix, bool non_negative) {
  const PixelRect& r = image.rect();
  for (int y = r.y; y < r.y_end(); ++y) {
    for (int x = r.x; x < r.x_end(); ++x) {
      const float* p = image.pixel(x, y);
      for (int c = 0; c < image.channel_count(); ++c) {
        if (std::isfinite(p[c]) && (!non_negative || p[c] >= 0)) continue;
        throw ImageError("accumulation channel " + prefix + image.channels()[c] + " at pixel (" +
                         std::to_string(x) + ", " + std::to_string(y) + ") is " +
                         std::to_string(p[c]) + (non_negative ? ", not finite and >= 0" :
                                                                ", not finite"));
      }
    }
  }
}

}  // namespace

std::vector<std::string> AccumulationChannels(const std::vector<std::string>& image_channels) {
  std::vector<std::string> names;
  for (const auto& c : image_channels) names.push_back("sum." + c);
  for (const auto& c : SquaredChannels()) names.push_back("sumsq." + c);
  return names;
}

std::string EncodeAccumulationExr(const Accumulation& a) {
  const PixelRect& whole = a.sums.rect();
  if (whole.x != 0 || whole.y != 0 || whole.width <= 0 || whole.height <= 0 ||
      a.squares.rect() != whole) {
    throw ImageError("accumulation images must both cover the same whole image");
  }
  if (a.squares.channels() != SquaredChannels()) {
    throw ImageError("accumulation squares must be channels R, G, B");
  }
  if (a.rounds < 1) throw ImageError("accumulation must hold at least one round");
  Imf::Header header(ToBox(whole), ToBox(whole));
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const auto& name : AccumulationChannels(a.sums.channels())) {
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
  }
  header.insert(kRoundsAttribute, Imf::IntAttribute(a.rounds));
  std::string bytes;
  try {
    ExrStringOStream stream(bytes);
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(SlicesOver(a));
    file.writePixels(whole.height);
  } catch (const std::exception& e) {
    throw ImageError(std::string("cannot encode the accumulation EXR: ") + e.what());
  }
  return bytes;
}

Accumulation DecodeAccumulationExr(std::string_view bytes, ImageSize size,
                                   const std::vector<std::string>& image_channels, int rounds) {
  const PixelRect whole{0, 0, size.width, size.height};
  Accumulation a{rounds, Image(whole, image_channels), Image(whole, SquaredChannels())};
  try {
    ExrMemoryIStream stream(bytes);
    Imf::InputFile file(stream);
    const Imf::Header& header = file.header();
    RequireWholeImage(header, size, "accumulation");
    const auto* count = header.findTypedAttribute<Imf::IntAttribute>(kRoundsAttribute);
    if (!count) throw ImageError(std::string("accumulation has no int attribute ") + kRoundsAttribute);
    if (count->value() != rounds) {
      throw ImageError("accumulation holds " + std::to_string(count->value()) +
                       " rounds, expected " + std::to_string(rounds));
    }
    std::vector<std::string> found;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
      found.emplace_back(it.name());
      const Imf::Channel& ch = it.channel();
      if (ch.type != Imf::FLOAT || ch.xSampling != 1 || ch.ySampling != 1) {
        throw ImageError(std::string("accumulation channel ") + it.name() +
                         " is not full-resolution FLOAT");
      }
    }
    const std::vector<std::string> wanted = AccumulationChannels(image_channels);
    if (JoinNames(found) != JoinNames(wanted)) {
      throw ImageError("accumulation has channels " + JoinNames(found) + ", expected " +
                       JoinNames(wanted));
    }
    file.setFrameBuffer(SlicesOver(a));
    file.readPixels(whole.y, whole.y_end() - 1);
  } catch (const ImageError&) {
    throw;
  } catch (const std::exception& e) {
    throw ImageError(std::string("accumulation is not a readable OpenEXR file: ") + e.what());
  }
  CheckValues(a.sums, "sum.", false);
  CheckValues(a.squares, "sumsq.", true);
  return a;
}

}  // namespace farm
