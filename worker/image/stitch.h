#pragma once

// Tiles stitched into one float image in memory, for work that needs every pixel at once
// (combining progressive rounds). The tiled EXR of a single render never goes through this:
// the compositor streams it tile by tile.

#include <span>

#include "image/composite.h"
#include "image/image.h"
#include "util/progress.h"

namespace farm {

// Decodes and places every tile of the grid. The image's channels are CompositeChannels of
// the first tile; every tile must carry the same ones. Throws ImageError naming the tile
// that is misplaced, overlapping, missing, unreadable or differently channelled.
// progress advances by one per tile placed.
Image StitchTiles(ImageSize size, int tile_size, std::span<const EncodedTile> tiles,
                  Progress progress = {});

}  // namespace farm
