#include "render/edge_detect.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace farm {
namespace {

// A pixel's normal as a unit vector, or none (zero) where it hit nothing. The cue is a sum,
// not unit: only its direction counts, and a pixel's samples may straddle a crease.
Vec3 Direction(const SurfaceCues& c) {
  if (c.inverse_depth == 0) return {};
  const double length = Length(c.normal);
  return length > 0 ? c.normal / float(length) : Vec3{};
}

// Two directions turn by more than the crease angle; never where either is none.
bool Crease(const Vec3& a, const Vec3& b) {
  return a != Vec3{} && b != Vec3{} && Dot(a, b) < kEdgeNormalCos;
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

bool SurfaceEdge(const SurfaceCueGrid& grid, int x, int y, const SurfaceCues* pilot) {
  // The eight neighbours, opposite ones kRing[i] and kRing[i + 4]: the row, the column and
  // the two diagonals through the pixel.
  constexpr int kRing[8][2] = {{-1, 0}, {-1, -1}, {0, -1}, {1, -1}, {1, 0}, {1, 1}, {0, 1}, {-1, 1}};
  std::array<const SurfaceCues*, 8> ring;
  for (int i = 0; i < 8; ++i) {
    ring[i] = &grid.at(x + kRing[i][0], y + kRing[i][1]);
    if (ring[i]->mixed || ring[i]->surface != ring[0]->surface) return true;
  }
  if (pilot && (pilot->mixed || pilot->surface != ring[0]->surface)) return true;
  const Vec3 own = pilot ? Direction(*pilot) : Vec3{};
  std::array<Vec3, 8> normals;
  for (int i = 0; i < 8; ++i) {
    normals[i] = Direction(*ring[i]);
    if (Crease(own, normals[i])) return true;
    for (int j = 0; j < i; ++j)
      if (Crease(normals[i], normals[j])) return true;
  }
  if (ring[0]->inverse_depth == 0) return false;  // no neighbour hit anything
  // The lines whose ends both lie in the image (at its border the others' ends are mirror
  // images, whose sums a slanted plane makes unequal). The grid holds every neighbour of a
  // tile pixel that the image holds, so its area's border is the image's there.
  const PixelRect& image = grid.area();
  const auto inside = [&](int dx, int dy) {
    return x + dx >= image.x && x + dx < image.x_end() && y + dy >= image.y && y + dy < image.y_end();
  };
  const double centre = pilot ? pilot->inverse_depth : 0;
  double low = 0, high = 0, sum = 0;
  int lines = 0;
  for (int i = 0; i < 4; ++i) {
    if (!inside(kRing[i][0], kRing[i][1]) || !inside(kRing[i + 4][0], kRing[i + 4][1])) continue;
    const double line = ring[i]->inverse_depth + ring[i + 4]->inverse_depth;
    // The pilot's second difference along the line, as a pixel's own depth would give it.
    if (centre > 0 && std::abs(line - 2 * centre) > kEdgeDepthStep * centre) return true;
    low = lines == 0 ? line : std::min(low, line);
    high = lines == 0 ? line : std::max(high, line);
    sum += line;
    ++lines;
  }
  if (lines < 2) return false;
  // Each sum is twice the pixel's 1/depth on a plane, so half their mean stands for it.
  return high - low > kEdgeDepthStep * sum / (2 * lines);
}

std::uint32_t EdgeSampleFactor(const SurfaceCueGrid& grid, int x, int y, const SurfaceCues& pilot) {
  double bright = pilot.emitted, dark = std::numeric_limits<double>::infinity();
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      if (dx == 0 && dy == 0) continue;  // never the pixel's own samples
      const SurfaceCues& n = grid.at(x + dx, y + dy);
      bright = std::max(bright, double(n.emitted));
      dark = std::min(dark, double(n.luminance));
    }
  const double floor = kEdgeLuminanceFloor;
  // Non-finite cues (which the integrator never gives) take the plain edge's samples.
  const double ratio = (bright + floor) / (std::max(0.0, dark) + floor);
  if (!std::isfinite(ratio)) return 1;
  const double factor = std::round(std::sqrt(ratio / kBrightEdgeRatio));
  return std::uint32_t(std::clamp(factor, 1.0, double(kMaxEdgeSampleFactor)));
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
                                      const PixelRect& tile, double threshold, const SurfaceCueGrid* pilots) {
  std::vector<std::uint8_t> edges = DetectEdges(light, tile, threshold);
  for (int y = tile.y; y < tile.y_end(); ++y)
    for (int x = tile.x; x < tile.x_end(); ++x) {
      std::uint8_t& e = edges[static_cast<std::size_t>(y - tile.y) * tile.width + (x - tile.x)];
      if (e == 0 && SurfaceEdge(surfaces, x, y, pilots ? &pilots->at(x, y) : nullptr)) e = 1;
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
