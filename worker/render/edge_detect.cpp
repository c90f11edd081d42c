#include "render/edge_detect.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace farm {

double EdgeLogLuminance(float r, float g, float b) {
  // Non-finite or negative input cannot come from the integrator; clamp rather than let a
  // NaN make every neighbour an edge (NaN compares false, so it would make none).
  const double y = 0.2126 * double(r) + 0.7152 * double(g) + 0.0722 * double(b);
  return std::log(std::max(0.0, std::isfinite(y) ? y : 0.0) + double(kEdgeLuminanceFloor));
}

LogLuminanceGrid::LogLuminanceGrid(const PixelRect& area)
    : area_(area), values_(static_cast<std::size_t>(area.width) * area.height, 0.0) {
  if (area.width <= 0 || area.height <= 0)
    throw std::invalid_argument("LogLuminanceGrid: empty area");
}

double LogLuminanceGrid::at(int x, int y) const {
  x = std::clamp(x, area_.x, area_.x_end() - 1);
  y = std::clamp(y, area_.y, area_.y_end() - 1);
  return values_[Index(x, y)];
}

double SobelGradient(const LogLuminanceGrid& f, int x, int y) {
  const double gx = (f.at(x + 1, y - 1) + 2 * f.at(x + 1, y) + f.at(x + 1, y + 1)) -
                    (f.at(x - 1, y - 1) + 2 * f.at(x - 1, y) + f.at(x - 1, y + 1));
  const double gy = (f.at(x - 1, y + 1) + 2 * f.at(x, y + 1) + f.at(x + 1, y + 1)) -
                    (f.at(x - 1, y - 1) + 2 * f.at(x, y - 1) + f.at(x + 1, y - 1));
  return std::sqrt(gx * gx + gy * gy) / 8;
}

std::vector<std::uint8_t> DetectEdges(const LogLuminanceGrid& grid, const PixelRect& tile,
                                      double threshold) {
  std::vector<std::uint8_t> edges(static_cast<std::size_t>(tile.width) * tile.height, 0);
  for (int y = tile.y; y < tile.y_end(); ++y)
    for (int x = tile.x; x < tile.x_end(); ++x)
      edges[static_cast<std::size_t>(y - tile.y) * tile.width + (x - tile.x)] =
          SobelGradient(grid, x, y) > threshold ? 1 : 0;
  return edges;
}

PixelRect ApronArea(const PixelRect& tile, ImageSize image) {
  const int x0 = std::max(0, tile.x - 1);
  const int y0 = std::max(0, tile.y - 1);
  const int x1 = std::min(image.width, tile.x_end() + 1);
  const int y1 = std::min(image.height, tile.y_end() + 1);
  return {x0, y0, x1 - x0, y1 - y0};
}

}  // namespace farm
