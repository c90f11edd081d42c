#include "image/stitch.h"

#include <algorithm>

#include "image/image_error.h"
#include "image/tile_exr.h"
#include "image/tile_grid.h"

namespace farm {

Image StitchTiles(ImageSize size, int tile_size, std::span<const EncodedTile> tiles,
                  Progress progress) {
  TileGrid grid(size, tile_size);
  if (tiles.empty()) throw ImageError("no tiles to stitch");
  Image image({0, 0, size.width, size.height}, CompositeChannels(tiles.front().exr));
  const std::size_t channels = image.channels().size();
  for (const EncodedTile& t : tiles) {
    grid.Check(t.rect);
    const Image tile = DecodeTileExr(t.exr, size, t.rect, image.channels());
    for (int y = t.rect.y; y < t.rect.y_end(); ++y) {
      std::copy_n(tile.pixel(t.rect.x, y), channels * t.rect.width, image.pixel(t.rect.x, y));
    }
    grid.Mark(t.rect);
    progress.Advance();
  }
  grid.CheckComplete();
  return image;
}

}  // namespace farm
