#include "image/tile_exr.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>

#include <algorithm>
#include <exception>

#include "image/exr_memory_stream.h"
#include "image/exr_util.h"
#include "image/image_error.h"

namespace farm {
namespace {

std::string JoinNames(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ",") + n;
  return "[" + s + "]";
}

// One FLOAT slice per channel over the Image's interleaved pixels.
Imf::FrameBuffer SlicesOver(const Image& image) {
  const std::size_t x_stride = sizeof(float) * image.channels().size();
  const std::size_t y_stride = x_stride * static_cast<std::size_t>(image.rect().width);
  const Imath::Box2i window = ToBox(image.rect());
  Imf::FrameBuffer fb;
  for (std::size_t c = 0; c < image.channels().size(); ++c) {
    fb.insert(image.channels()[c],
              Imf::Slice::Make(Imf::FLOAT, image.data().data() + c, window, x_stride, y_stride));
  }
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

  std::string bytes;
  try {
    ExrStringOStream stream(bytes);
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(SlicesOver(tile));
    file.writePixels(rect.height);
  } catch (const std::exception& e) {
    throw ImageError(std::string("cannot encode tile EXR: ") + e.what());
  }
  return bytes;
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
    std::vector<std::string> found;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
      found.emplace_back(it.name());
      const Imf::Channel& ch = it.channel();
      if (ch.type != Imf::FLOAT || ch.xSampling != 1 || ch.ySampling != 1) {
        throw ImageError(std::string("tile channel ") + it.name() +
                         " is not full-resolution FLOAT");
      }
    }
    std::vector<std::string> wanted = channels;
    std::sort(wanted.begin(), wanted.end());
    if (found != wanted) {  // OpenEXR keeps channels sorted by name, so this is set equality.
      throw ImageError("tile has channels " + JoinNames(found) + ", expected " + JoinNames(wanted));
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
