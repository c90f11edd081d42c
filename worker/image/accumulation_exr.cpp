#include "image/accumulation_exr.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfIntAttribute.h>

#include <algorithm>
#include <cmath>
#include <exception>

#include "image/exr_memory_stream.h"
#include "image/exr_util.h"
#include "image/image_error.h"

namespace farm {
namespace {

const std::vector<std::string>& WeightChannels() {
  static const std::vector<std::string> w = {"W"};
  return w;
}

// The weights' file channel is "weight", not "weight.W": one value, not a layer.
constexpr char kWeightChannel[] = "weight";

// Slices over the three images under their file names.
Imf::FrameBuffer SlicesOver(const Accumulation& a) {
  Imf::FrameBuffer fb;
  InsertSlices(fb, a.sums, "sum.");
  InsertSlices(fb, a.squares, "sumsq.");
  const std::size_t stride = sizeof(float) * std::size_t(a.weights.rect().width);
  fb.insert(kWeightChannel, Imf::Slice::Make(Imf::FLOAT, a.weights.data().data(), ToBox(a.weights.rect()),
                                             sizeof(float), stride));
  return fb;
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

std::vector<std::string> SquaredChannels(const std::vector<std::string>& image_channels) {
  const std::vector<std::string> bias = BiasChannels();
  const bool has_bias = std::all_of(bias.begin(), bias.end(), [&](const std::string& c) {
    return std::find(image_channels.begin(), image_channels.end(), c) != image_channels.end();
  });
  if (has_bias) return {"R", "G", "B", kBiasSquares};
  return {"R", "G", "B"};
}

std::vector<std::string> AccumulationChannels(const std::vector<std::string>& image_channels) {
  std::vector<std::string> names;
  for (const auto& c : image_channels) names.push_back("sum." + c);
  for (const auto& c : SquaredChannels(image_channels)) names.push_back("sumsq." + c);
  names.emplace_back(kWeightChannel);
  return names;
}

std::string EncodeAccumulationExr(const Accumulation& a) {
  const PixelRect& whole = a.sums.rect();
  if (whole.x != 0 || whole.y != 0 || whole.width <= 0 || whole.height <= 0 ||
      a.squares.rect() != whole || a.weights.rect() != whole) {
    throw ImageError("accumulation images must both cover the same whole image");
  }
  if (a.squares.channels() != SquaredChannels(a.sums.channels())) {
    throw ImageError("accumulation squares must be channels " + JoinNames(SquaredChannels(a.sums.channels())));
  }
  if (a.weights.channels() != WeightChannels()) throw ImageError("accumulation weights must be channel W");
  if (a.rounds < 1) throw ImageError("accumulation must hold at least one round");
  Imf::Header header(ToBox(whole), ToBox(whole));
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const auto& name : AccumulationChannels(a.sums.channels())) {
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
  }
  header.insert(kRoundsAttribute, Imf::IntAttribute(a.rounds));
  header.insert(kDeviationsAttribute, Imf::DoubleAttribute(a.deviations));
  header.insert(kDeviationSquaresAttribute, Imf::DoubleAttribute(a.deviation_squares));
  return EncodeExr(header, SlicesOver(a), "the accumulation EXR");
}

Accumulation DecodeAccumulationExr(std::string_view bytes, ImageSize size,
                                   const std::vector<std::string>& image_channels, int rounds) {
  const PixelRect whole{0, 0, size.width, size.height};
  Accumulation a{rounds, Image(whole, image_channels), Image(whole, SquaredChannels(image_channels)),
                 Image(whole, WeightChannels()), 0, 0};
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
    for (const auto& [name, value] : {std::pair{kDeviationsAttribute, &a.deviations},
                                      std::pair{kDeviationSquaresAttribute, &a.deviation_squares}}) {
      const auto* v = header.findTypedAttribute<Imf::DoubleAttribute>(name);
      if (!v) throw ImageError(std::string("accumulation has no double attribute ") + name);
      if (!std::isfinite(v->value()) || v->value() < 0)
        throw ImageError(std::string("accumulation attribute ") + name + " is " + std::to_string(v->value()) +
                         ", not finite and >= 0");
      *value = v->value();
    }
    const std::vector<std::string> found = FloatChannels(header, "accumulation");
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
  CheckValues(a.weights, "weight.", true);
  for (float w : a.weights.data()) {
    if (w <= 0) throw ImageError("accumulation has a pixel of weight 0: every round weighs every pixel");
  }
  return a;
}

}  // namespace farm
