#include "image/tile_grid.h"

#include <algorithm>

#include "image/exr_util.h"
#include "image/image_error.h"

namespace farm {

TileGrid::TileGrid(ImageSize size, int tile_size) : size_(size), tile_size_(tile_size) {
  if (size.width <= 0 || size.height <= 0) {
    throw ImageError("image size " + ToString(size) + " is empty");
  }
  if (tile_size <= 0) throw ImageError("tile size " + std::to_string(tile_size) + " is not positive");
  tiles_x_ = (size.width + tile_size - 1) / tile_size;
  tiles_y_ = (size.height + tile_size - 1) / tile_size;
  seen_.assign(static_cast<std::size_t>(tiles_x_) * tiles_y_, false);
}

PixelRect TileGrid::CellRect(int tx, int ty) const {
  const int x = tx * tile_size_;
  const int y = ty * tile_size_;
  return {x, y, std::min(tile_size_, size_.width - x), std::min(tile_size_, size_.height - y)};
}

void TileGrid::Check(const PixelRect& rect) const {
  if (rect.width <= 0 || rect.height <= 0 ||
      !PixelRect{0, 0, size_.width, size_.height}.Contains(rect)) {
    throw ImageError("tile " + ToString(rect) + " lies outside the " + ToString(size_) + " image");
  }
  if (rect.x % tile_size_ != 0 || rect.y % tile_size_ != 0 ||
      rect != CellRect(rect.x / tile_size_, rect.y / tile_size_)) {
    throw ImageError("tile " + ToString(rect) + " is not a cell of the " +
                     std::to_string(tile_size_) + "-pixel tile grid");
  }
  if (seen_[CellIndex(rect)]) {
    throw ImageError("tile " + ToString(rect) + " overlaps a tile already composited");
  }
}

void TileGrid::CheckComplete() const {
  int missing = 0;
  std::string first_missing;
  for (int ty = 0; ty < tiles_y_; ++ty) {
    for (int tx = 0; tx < tiles_x_; ++tx) {
      if (seen_[static_cast<std::size_t>(ty) * tiles_x_ + tx]) continue;
      if (missing++ == 0) first_missing = ToString(CellRect(tx, ty));
    }
  }
  if (missing > 0) {
    throw ImageError(std::to_string(missing) + " of " + std::to_string(seen_.size()) +
                     " tiles are missing, the first " + first_missing);
  }
}

}  // namespace farm
