#pragma once

// The grid of render tiles over an image: which rectangles are tiles, and bookkeeping of
// which have arrived. Shared by the compositor and the round accumulator, so both refuse
// the same misplaced tiles with the same words.

#include <cstddef>
#include <string>
#include <vector>

#include "image/image.h"

namespace farm {

class TileGrid {
 public:
  // Throws ImageError for an empty image or a non-positive tile size.
  TileGrid(ImageSize size, int tile_size);

  ImageSize size() const { return size_; }
  int tile_size() const { return tile_size_; }
  std::size_t cell_count() const { return seen_.size(); }

  // The cell's rectangle; the last column and row may be partial.
  PixelRect CellRect(int tx, int ty) const;

  // Checks that rect is a cell of the grid not marked yet. Throws ImageError naming the tile
  // ("outside", "not a cell of the ... grid", "overlaps").
  void Check(const PixelRect& rect) const;
  // Marks a checked cell as arrived.
  void Mark(const PixelRect& rect) { seen_[CellIndex(rect)] = true; }

  // Throws ImageError if a cell was never marked ("N of M tiles are missing, the first ...").
  void CheckComplete() const;

 private:
  std::size_t CellIndex(const PixelRect& rect) const {
    return static_cast<std::size_t>(rect.y / tile_size_) * tiles_x_ + rect.x / tile_size_;
  }

  ImageSize size_;
  int tile_size_ = 0;
  int tiles_x_ = 0;
  int tiles_y_ = 0;
  std::vector<bool> seen_;  // per cell, row-major
};

}  // namespace farm
