#pragma once

// Tile EXRs: how a rendered tile travels from the worker that rendered it to the one that
// composites the image. Everything happens in memory; the blob store holds the bytes.

#include <string>
#include <string_view>
#include <vector>

#include "image/image.h"

namespace farm {

// Encodes a tile as a scanline OpenEXR: one FLOAT channel per channel of the Image, named
// alike, ZIP compression, data window = the tile's rect, display window = the whole image.
// The same pixels always give the same bytes (no timestamps or other varying metadata).
// Throws ImageError if the tile is empty or does not lie inside the image.
std::string EncodeTileExr(const Image& tile, ImageSize image_size);

// The channel names a tile EXR carries, in the file's order (OpenEXR sorts them). Reads the
// header only. Throws ImageError if the bytes are not an OpenEXR file.
std::vector<std::string> ReadTileExrChannels(std::string_view bytes);

// Decodes a tile EXR and checks it is the tile that was asked for: display window equal to
// image_size, data window equal to rect, exactly the channels named (any order in the file),
// all FLOAT and not subsampled. The Image's channels come in the order of `channels`.
// Throws ImageError naming the mismatch, or if the bytes are not a readable OpenEXR file.
Image DecodeTileExr(std::string_view bytes, ImageSize image_size, const PixelRect& rect,
                    const std::vector<std::string>& channels);

}  // namespace farm
