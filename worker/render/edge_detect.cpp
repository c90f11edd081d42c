#include "render/edge_detect.h"

#include <algorithm>
#include <cmath>

namespace farm {
namespace {

// Normals of two pixels that both hit something turn by more than the crease angle. The
// sums are not unit: only the angle counts, and a pixel's samples may straddle a crease.
bool Crease(const SurfaceCues& a, const SurfaceCues& b) {
  if (a.inverse_depth == 0 || b.inverse_depth == 0) return false;
  const double la = Length(a.normal), lb = Length(b.normal);
  if (!(la > 0) || !(lb > 0)) return false;
  return Dot(a.normal, b.normal) < kEdgeNormalCos * la * lb;
}

}  // namespace

double EdgeLogLuminance(float r, float g, float b) {
  // Non-finite or negative input cannot come from the integrator; clamp rather than let a
  // NaN make every neighbour an edge (NaN compares false, so it would make none).
  const double y = 0.2126 * double(r) + 0.7152 * double(g) + 0.0722 * double(b);
  return std::log(std::max(0.0, std::isfinite(y) ? y : 0.0) + double(kEdgeLuminanceFloor));
}

double SobelGradient(const LogLuminanceGrid& f, int x, int y) {
  const double gx = (f.at(x + 1, y - 1) + 2 * f.at(x + 1, y) + f.at(x + 1, y + 1)) -
                    (f.at(x - 1, y - 1) + 2 * f.at(x - 1, y) + f.at(x - 1, y + 1));
  const double gy = (f.at(x - 1, y + 1) + 2 * f.at(x, y + 1) + f.at(x + 1, y + 1)) -
                    (f.at(x - 1, y - 1) + 2 * f.at(x, y - 1) + f.at(x + 1, y - 1));
  return std::sqrt(gx * gx + gy * gy) / 8;
}

bool SurfaceEdge(const SurfaceCueGrid& grid, int x, int y) {
  const SurfaceCues& centre = grid.at(x, y);
  if (centre.mixed) return true;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const SurfaceCues& q = grid.at(x + dx, y + dy);
      if (q.surface != centre.surface || Crease(centre, q)) return true;
    }
  if (centre.inverse_depth == 0) return false;
  // The four lines through the pixel: a row, a column and the two diagonals.
  constexpr int kLines[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
  for (const auto& [dx, dy] : kLines) {
    const double second = grid.at(x - dx, y - dy).inverse_depth + grid.at(x + dx, y + dy).inverse_depth -
                          2 * centre.inverse_depth;
    if (std::abs(second) > kEdgeDepthStep * centre.inverse_depth) return true;
  }
  return false;
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

std::vector<std::uint8_t> DetectEdges(const SurfaceCueGrid& surfaces, const LogLuminanceGrid& light,
                                      const PixelRect& tile, double threshold) {
  std::vector<std::uint8_t> edges = DetectEdges(light, tile, threshold);
  for (int y = tile.y; y < tile.y_end(); ++y)
    for (int x = tile.x; x < tile.x_end(); ++x) {
      std::uint8_t& e = edges[static_cast<std::size_t>(y - tile.y) * tile.width + (x - tile.x)];
      if (e == 0 && SurfaceEdge(surfaces, x, y)) e = 1;
    }
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
