#include "image/composite.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfTileDescription.h>
#include <OpenEXR/ImfTiledOutputFile.h>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <vector>

#include "image/exr_memory_stream.h"
#include "image/exr_util.h"
#include "image/image_error.h"
#include "image/srgb_preview.h"
#include "image/tile_exr.h"

namespace farm {
namespace {

// The output's channels: red, green, blue and alpha first (the order viewers expect), then
// the passes the first tile carries.
std::vector<std::string> ChannelsOfFirstTile(std::string_view tile_exr) {
  const std::vector<std::string> found = ReadTileExrChannels(tile_exr);
  std::vector<std::string> channels = RgbaChannels();
  for (const auto& name : channels) {
    if (std::find(found.begin(), found.end(), name) == found.end()) {
      throw ImageError("tile has no channel " + name + "; tiles need R, G, B and A");
    }
  }
  for (const auto& name : found) {
    if (std::find(channels.begin(), channels.end(), name) == channels.end()) {
      channels.push_back(name);
    }
  }
  return channels;
}

}  // namespace

struct Compositor::State {
  ImageSize size;
  int tile_size = 0;
  int tiles_x = 0;
  int tiles_y = 0;
  std::optional<std::filesystem::path> path;  // Unset: the EXR goes to `exr`.
  std::vector<bool> written;                  // Per grid cell, row-major.
  std::vector<std::string> channels;          // Fixed by the first tile.
  std::string exr;
  // The file is opened with the first tile, when the channels are known. It comes after
  // `stream` so that it is destroyed (and writes its offset table) before the stream.
  std::unique_ptr<ExrStringOStream> stream;
  std::unique_ptr<Imf::TiledOutputFile> file;
  std::vector<std::uint8_t> preview;  // Straight-alpha sRGB RGBA8, whole image.
  bool finished = false;

  PixelRect CellRect(int tx, int ty) const {
    const int x = tx * tile_size;
    const int y = ty * tile_size;
    return {x, y, std::min(tile_size, size.width - x), std::min(tile_size, size.height - y)};
  }

  void CheckPlacement(const PixelRect& rect) const {
    if (rect.width <= 0 || rect.height <= 0 ||
        !PixelRect{0, 0, size.width, size.height}.Contains(rect)) {
      throw ImageError("tile " + ToString(rect) + " lies outside the " + ToString(size) +
                       " image");
    }
    if (rect.x % tile_size != 0 || rect.y % tile_size != 0 ||
        rect != CellRect(rect.x / tile_size, rect.y / tile_size)) {
      throw ImageError("tile " + ToString(rect) + " is not a cell of the " +
                       std::to_string(tile_size) + "-pixel tile grid");
    }
    if (written[static_cast<std::size_t>(rect.y / tile_size) * tiles_x + rect.x / tile_size]) {
      throw ImageError("tile " + ToString(rect) + " overlaps a tile already composited");
    }
  }

  void Open(const std::vector<std::string>& tile_channels) {
    channels = tile_channels;
    Imf::Header header(size.width, size.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    header.setTileDescription(Imf::TileDescription(tile_size, tile_size, Imf::ONE_LEVEL));
    for (const auto& name : channels) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    if (path) {
      file = std::make_unique<Imf::TiledOutputFile>(path->c_str(), header);
    } else {
      stream = std::make_unique<ExrStringOStream>(exr);
      file = std::make_unique<Imf::TiledOutputFile>(*stream, header);
    }
  }
};

Compositor::Compositor(ImageSize size, int tile_size) : state_(std::make_unique<State>()) {
  if (size.width <= 0 || size.height <= 0) {
    throw ImageError("image size " + ToString(size) + " is empty");
  }
  if (tile_size <= 0) throw ImageError("tile size " + std::to_string(tile_size) + " is not positive");
  state_->size = size;
  state_->tile_size = tile_size;
  state_->tiles_x = (size.width + tile_size - 1) / tile_size;
  state_->tiles_y = (size.height + tile_size - 1) / tile_size;
  state_->written.assign(static_cast<std::size_t>(state_->tiles_x) * state_->tiles_y, false);
  state_->preview.assign(static_cast<std::size_t>(size.width) * size.height * 4, 0);
}

Compositor::Compositor(ImageSize size, int tile_size, const std::filesystem::path& path)
    : Compositor(size, tile_size) {
  state_->path = path;
}

Compositor::Compositor(Compositor&&) noexcept = default;
Compositor& Compositor::operator=(Compositor&&) noexcept = default;
Compositor::~Compositor() = default;

void Compositor::Add(const PixelRect& rect, std::string_view tile_exr) {
  State& s = *state_;
  if (s.finished) throw ImageError("compositor already finished");
  s.CheckPlacement(rect);
  const bool first = !s.file;
  const std::vector<std::string> channels = first ? ChannelsOfFirstTile(tile_exr) : s.channels;
  const Image tile = DecodeTileExr(tile_exr, s.size, rect, channels);
  if (first) s.Open(channels);

  const std::size_t x_stride = sizeof(float) * s.channels.size();
  const std::size_t y_stride = x_stride * static_cast<std::size_t>(rect.width);
  Imf::FrameBuffer fb;
  for (std::size_t c = 0; c < s.channels.size(); ++c) {
    fb.insert(s.channels[c], Imf::Slice::Make(Imf::FLOAT, tile.data().data() + c, ToBox(rect),
                                              x_stride, y_stride));
  }
  try {
    s.file->setFrameBuffer(fb);
    s.file->writeTile(rect.x / s.tile_size, rect.y / s.tile_size);
  } catch (const std::exception& e) {
    throw ImageError("cannot write tile " + ToString(rect) + ": " + e.what());
  }
  s.written[static_cast<std::size_t>(rect.y / s.tile_size) * s.tiles_x + rect.x / s.tile_size] =
      true;
  WritePreviewPixels(tile, s.size, s.preview);
}

CompositeOutput Compositor::Finish() {
  State& s = *state_;
  if (s.finished) throw ImageError("compositor already finished");
  int missing = 0;
  std::string first_missing;
  for (int ty = 0; ty < s.tiles_y; ++ty) {
    for (int tx = 0; tx < s.tiles_x; ++tx) {
      if (s.written[static_cast<std::size_t>(ty) * s.tiles_x + tx]) continue;
      if (missing++ == 0) first_missing = ToString(s.CellRect(tx, ty));
    }
  }
  if (missing > 0) {
    throw ImageError(std::to_string(missing) + " of " + std::to_string(s.written.size()) +
                     " tiles are missing, the first " + first_missing);
  }
  s.finished = true;
  try {
    s.file.reset();  // Writes the tile offset table and flushes.
  } catch (const std::exception& e) {
    throw ImageError(std::string("cannot complete the EXR: ") + e.what());
  }
  s.stream.reset();
  CompositeOutput out;
  out.exr = std::move(s.exr);
  out.preview_png = EncodePngRgba8(s.size, s.preview);
  return out;
}

CompositeOutput Composite(ImageSize size, int tile_size, std::span<const EncodedTile> tiles) {
  Compositor compositor(size, tile_size);
  for (const auto& t : tiles) compositor.Add(t.rect, t.exr);
  return compositor.Finish();
}

}  // namespace farm
