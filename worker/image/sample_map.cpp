#include "image/sample_map.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>

#include <exception>

#include "image/exr_memory_stream.h"
#include "image/exr_util.h"
#include "image/image_error.h"

namespace farm {
namespace {

constexpr char kChannel[] = "N";

Imf::FrameBuffer SliceOver(const SampleMap& map, std::uint32_t* data) {
  const PixelRect whole{0, 0, map.size.width, map.size.height};
  Imf::FrameBuffer fb;
  fb.insert(kChannel, Imf::Slice::Make(Imf::UINT, data, ToBox(whole), sizeof(std::uint32_t),
                                       sizeof(std::uint32_t) * std::size_t(map.size.width)));
  return fb;
}

}  // namespace

std::string EncodeSampleMap(const SampleMap& map) {
  if (map.size.width <= 0 || map.size.height <= 0 ||
      map.counts.size() != std::size_t(map.size.width) * std::size_t(map.size.height)) {
    throw ImageError("sample map of " + ToString(map.size) + " holds " + std::to_string(map.counts.size()) +
                     " counts");
  }
  const Imath::Box2i whole = ToBox({0, 0, map.size.width, map.size.height});
  Imf::Header header(whole, whole);
  header.compression() = Imf::ZIP_COMPRESSION;
  header.channels().insert(kChannel, Imf::Channel(Imf::UINT));
  // OpenEXR reads from the slice only; the cast does not write.
  return EncodeExr(header, SliceOver(map, const_cast<std::uint32_t*>(map.counts.data())), "the sample map");
}

SampleMap DecodeSampleMap(std::string_view bytes, ImageSize size, std::uint32_t max_samples) {
  SampleMap map{size, std::vector<std::uint32_t>(std::size_t(size.width) * std::size_t(size.height), 0)};
  try {
    ExrMemoryIStream stream(bytes);
    Imf::InputFile file(stream);
    const Imf::Header& header = file.header();
    RequireWholeImage(header, size, "sample map");
    const Imf::ChannelList& channels = header.channels();
    const Imf::Channel* n = channels.findChannel(kChannel);
    if (!n || ++channels.begin() != channels.end() || n->type != Imf::UINT || n->xSampling != 1 ||
        n->ySampling != 1) {
      throw ImageError("sample map must have exactly one full-resolution UINT channel N");
    }
    file.setFrameBuffer(SliceOver(map, map.counts.data()));
    file.readPixels(0, size.height - 1);
  } catch (const ImageError&) {
    throw;
  } catch (const std::exception& e) {
    throw ImageError(std::string("sample map is not a readable OpenEXR file: ") + e.what());
  }
  for (std::size_t i = 0; i < map.counts.size(); ++i) {
    if (map.counts[i] >= 1 && map.counts[i] <= max_samples) continue;
    throw ImageError("sample map gives pixel (" + std::to_string(i % std::size_t(size.width)) + ", " +
                     std::to_string(i / std::size_t(size.width)) + ") " + std::to_string(map.counts[i]) +
                     " samples, not 1 to " + std::to_string(max_samples));
  }
  return map;
}

}  // namespace farm
