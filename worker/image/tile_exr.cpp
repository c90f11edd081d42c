#include "image/tile_exr.h"

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

// One FLOAT slice per channel over the Image's interleaved pixels.
Imf::FrameBuffer SlicesOver(const Image& image) {
  Imf::FrameBuffer fb;
  InsertSlices(fb, image);
  return fb;
}

}  // namespace

std::string EncodeTileExr(const Image& tile, ImageSize image_size) {
  const PixelRect& rect = tile.rect();
  if (rect.width <= 0 || rect.height <= 0) throw ImageError("tile " + ToString(rect) + " is empty");
  if (!PixelRect{0, 0, image_size.width, image_size.height}.Contains(rect)) {
    throw ImageError("tile " + ToString(rect) + " lies outside the " + ToString(image_size) +
                     " image");
  }
  Imf::Header header(Imath::Box2i(Imath::V2i(0, 0),
                                  Imath::V2i(image_size.width - 1, image_size.height - 1)),
                     ToBox(rect));
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const auto& name : tile.channels()) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
  return EncodeExr(header, SlicesOver(tile), "tile EXR");
}

std::vector<std::string> ReadTileExrChannels(std::string_view bytes) {
  try {
    ExrMemoryIStream stream(bytes);
    Imf::InputFile file(stream);
    std::vector<std::string> names;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
      names.emplace_back(it.name());
    }
    return names;
  } catch (const std::exception& e) {
    throw ImageError(std::string("tile is not a readable OpenEXR file: ") + e.what());
  }
}

Image DecodeTileExr(std::string_view bytes, ImageSize image_size, const PixelRect& rect,
                    const std::vector<std::string>& channels) {
  try {
    ExrMemoryIStream stream(bytes);
    Imf::InputFile file(stream);
    const Imf::Header& header = file.header();

    const PixelRect display = ToRect(header.displayWindow());
    if (display != PixelRect{0, 0, image_size.width, image_size.height}) {
      throw ImageError("tile's display window " + ToString(display) + " is not the " +
                       ToString(image_size) + " image");
    }
    const PixelRect data = ToRect(header.dataWindow());
    if (data != rect) {
      throw ImageError("tile's data window " + ToString(data) + " is not the expected " +
                       ToString(rect));
    }
    const std::vector<std::string> found = FloatChannels(header, "tile");
    if (JoinNames(found) != JoinNames(channels)) {  // Sorted: set equality.
      throw ImageError("tile has channels " + JoinNames(found) + ", expected " + JoinNames(channels));
    }

    Image image(rect, channels);
    file.setFrameBuffer(SlicesOver(image));
    file.readPixels(data.y, data.y_end() - 1);
    return image;
  } catch (const ImageError&) {
    throw;
  } catch (const std::exception& e) {
    throw ImageError(std::string("tile is not a readable OpenEXR file: ") + e.what());
  }
}

}  // namespace farm
