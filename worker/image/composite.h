#pragma once

// Compositing: the tile EXRs of a render stitched into the final tiled OpenEXR (the
// deliverable, opened by Nuke, Blender or oiiotool), with its metadata, plus an 8-bit
// sRGB PNG preview, exposed and tone-mapped.

#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "image/exr_metadata.h"
#include "image/image.h"
#include "image/tone_map.h"

namespace farm {

// A tile's rectangle and its tile EXR bytes (see tile_exr.h).
struct EncodedTile {
  PixelRect rect;
  std::string exr;
};

// How the composite's outputs are made besides their pixels.
struct OutputSettings {
  PreviewSettings preview;
  ExrMetadata metadata;
};

struct CompositeOutput {
  std::string exr;  // Empty when the EXR was written to a file.
  std::string preview_png;
};

// Writes a tiled OpenEXR (tile size = render tile size, ONE_LEVEL, ZIP, FLOAT channels: R,
// G, B, A and any others the tiles carry) one tile at a time, so the whole float image is
// never held in memory. Tiles must sit on the tile grid (the last row and column may be
// partial), each exactly once; they may arrive in any order and the bytes are the same
// (OpenEXR stores them in increasing y). Errors throw ImageError naming the tile.
class Compositor {
 public:
  // The EXR goes to memory and comes back from Finish.
  Compositor(ImageSize size, int tile_size, const OutputSettings& settings = {});
  // The EXR goes to `path`; a partial file is left behind if compositing fails.
  Compositor(ImageSize size, int tile_size, const std::filesystem::path& path,
             const OutputSettings& settings = {});
  Compositor(Compositor&&) noexcept;
  Compositor& operator=(Compositor&&) noexcept;
  ~Compositor();

  // Decodes, validates and writes one tile. The first tile fixes the channel set (it must
  // include R, G, B and A); every later tile must carry the same channels.
  void Add(const PixelRect& rect, std::string_view tile_exr);

  // Writes one tile already in memory (its rect places it). The first tile fixes the
  // channels, which must begin R, G, B, A; every later tile must have the same list.
  void Add(const Image& tile);

  // Checks that every tile of the grid arrived, completes the EXR and encodes the preview.
  // Call once.
  CompositeOutput Finish();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// Composites a complete list of tiles in memory.
CompositeOutput Composite(ImageSize size, int tile_size, std::span<const EncodedTile> tiles,
                          const OutputSettings& settings = {});

// Writes a whole image held in memory (its rect the whole image, channels beginning R, G,
// B, A) as the tiled EXR and preview. The same pixels give the same bytes as Composite of
// the image's tiles.
CompositeOutput CompositeImage(const Image& image, int tile_size, const OutputSettings& settings = {});

// The channels a composite of these tiles carries: R, G, B, A first (the order viewers
// expect), then the other channels of the tile, in the file's order. Throws ImageError if
// the tile lacks one of R, G, B, A or is not an OpenEXR file.
std::vector<std::string> CompositeChannels(std::string_view tile_exr);

}  // namespace farm
