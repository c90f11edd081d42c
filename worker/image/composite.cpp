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
#include "image/tile_grid.h"

namespace farm {
namespace {

bool BeginsRgba(const std::vector<std::string>& channels) {
  const std::vector<std::string> rgba = RgbaChannels();
  return channels.size() >= rgba.size() && std::equal(rgba.begin(), rgba.end(), channels.begin());
}

}  // namespace

std::vector<std::string> CompositeChannels(std::string_view tile_exr) {
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

struct Compositor::State {
  State(ImageSize size, int tile_size, const OutputSettings& settings) : grid(size, tile_size), settings(settings) {}

  TileGrid grid;
  OutputSettings settings;
  std::optional<std::filesystem::path> path;  // Unset: the EXR goes to `exr`.
  std::vector<std::string> channels;          // Fixed by the first tile.
  std::string exr;
  // The file is opened with the first tile, when the channels are known. It comes after
  // `stream` so that it is destroyed (and writes its offset table) before the stream.
  std::unique_ptr<ExrStringOStream> stream;
  std::unique_ptr<Imf::TiledOutputFile> file;
  std::vector<std::uint8_t> preview;  // Straight-alpha sRGB RGBA8, whole image.
  bool finished = false;

  void Open(const std::vector<std::string>& tile_channels) {
    channels = tile_channels;
    const ImageSize size = grid.size();
    Imf::Header header(size.width, size.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    header.setTileDescription(
        Imf::TileDescription(grid.tile_size(), grid.tile_size(), Imf::ONE_LEVEL));
    for (const auto& name : channels) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    AddExrMetadata(settings.metadata, header);
    if (path) {
      file = std::make_unique<Imf::TiledOutputFile>(path->c_str(), header);
    } else {
      stream = std::make_unique<ExrStringOStream>(exr);
      file = std::make_unique<Imf::TiledOutputFile>(*stream, header);
    }
  }

  // The tile's placement and channels are checked; writes it and marks its cell.
  void Write(const Image& tile) {
    const PixelRect& rect = tile.rect();
    const std::size_t x_stride = sizeof(float) * channels.size();
    const std::size_t y_stride = x_stride * static_cast<std::size_t>(rect.width);
    Imf::FrameBuffer fb;
    for (std::size_t c = 0; c < channels.size(); ++c) {
      fb.insert(channels[c], Imf::Slice::Make(Imf::FLOAT, tile.data().data() + c, ToBox(rect),
                                              x_stride, y_stride));
    }
    try {
      file->setFrameBuffer(fb);
      file->writeTile(rect.x / grid.tile_size(), rect.y / grid.tile_size());
    } catch (const std::exception& e) {
      throw ImageError("cannot write tile " + ToString(rect) + ": " + e.what());
    }
    grid.Mark(rect);
    WritePreviewPixels(tile, grid.size(), preview, settings.preview);
  }
};

Compositor::Compositor(ImageSize size, int tile_size, const OutputSettings& settings)
    : state_(std::make_unique<State>(size, tile_size, settings)) {
  state_->preview.assign(static_cast<std::size_t>(size.width) * size.height * 4, 0);
}

Compositor::Compositor(ImageSize size, int tile_size, const std::filesystem::path& path,
                       const OutputSettings& settings)
    : Compositor(size, tile_size, settings) {
  state_->path = path;
}

Compositor::Compositor(Compositor&&) noexcept = default;
Compositor& Compositor::operator=(Compositor&&) noexcept = default;
Compositor::~Compositor() = default;

void Compositor::Add(const PixelRect& rect, std::string_view tile_exr) {
  State& s = *state_;
  if (s.finished) throw ImageError("compositor already finished");
  s.grid.Check(rect);
  const bool first = !s.file;
  const std::vector<std::string> channels = first ? CompositeChannels(tile_exr) : s.channels;
  const Image tile = DecodeTileExr(tile_exr, s.grid.size(), rect, channels);
  if (first) s.Open(channels);
  s.Write(tile);
}

void Compositor::Add(const Image& tile) {
  State& s = *state_;
  if (s.finished) throw ImageError("compositor already finished");
  s.grid.Check(tile.rect());
  if (!s.file) {
    if (!BeginsRgba(tile.channels())) throw ImageError("tile channels must begin R, G, B, A");
    s.Open(tile.channels());
  } else if (tile.channels() != s.channels) {
    throw ImageError("tile " + ToString(tile.rect()) + " has other channels than the first tile");
  }
  s.Write(tile);
}

CompositeOutput Compositor::Finish() {
  State& s = *state_;
  if (s.finished) throw ImageError("compositor already finished");
  s.grid.CheckComplete();
  s.finished = true;
  try {
    s.file.reset();  // Writes the tile offset table and flushes.
  } catch (const std::exception& e) {
    throw ImageError(std::string("cannot complete the EXR: ") + e.what());
  }
  s.stream.reset();
  CompositeOutput out;
  out.exr = std::move(s.exr);
  out.preview_png = EncodePngRgba8(s.grid.size(), s.preview);
  return out;
}

CompositeOutput Composite(ImageSize size, int tile_size, std::span<const EncodedTile> tiles,
                          const OutputSettings& settings) {
  Compositor compositor(size, tile_size, settings);
  for (const auto& t : tiles) compositor.Add(t.rect, t.exr);
  return compositor.Finish();
}

CompositeOutput CompositeImage(const Image& image, int tile_size, const OutputSettings& settings) {
  const PixelRect& whole = image.rect();
  if (whole.x != 0 || whole.y != 0) {
    throw ImageError("image " + ToString(whole) + " does not start at the origin");
  }
  const ImageSize size{whole.width, whole.height};
  Compositor compositor(size, tile_size, settings);
  const TileGrid grid(size, tile_size);
  for (int y = 0; y < size.height; y += tile_size) {
    for (int x = 0; x < size.width; x += tile_size) {
      const PixelRect cell = grid.CellRect(x / tile_size, y / tile_size);
      Image tile(cell, image.channels());
      const std::size_t row = static_cast<std::size_t>(cell.width) * image.channel_count();
      for (int py = cell.y; py < cell.y_end(); ++py) {
        std::copy_n(image.pixel(cell.x, py), row, tile.pixel(cell.x, py));
      }
      compositor.Add(tile);
    }
  }
  return compositor.Finish();
}

}  // namespace farm
