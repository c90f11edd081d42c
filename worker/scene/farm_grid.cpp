#include "scene/farm_grid.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <vector>

#include "contract/go_text.h"
#include "contract/rules.h"

namespace farm {
namespace {

constexpr std::string_view kMagic = "FARMGRID";
constexpr std::uint32_t kVersion = 1;
constexpr std::uint64_t kHeader = 48;
constexpr const char* kAxes[3] = {"x", "y", "z"};

static_assert(std::endian::native == std::endian::little, "the farm grid file is little-endian, as this machine");

template <typename T>
T Load(std::string_view bytes, std::size_t at) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof(T));
  return value;
}

}  // namespace

FarmGridError::FarmGridError(std::uint64_t offset, const std::string& reason)
    : BadInputError("byte " + std::to_string(offset) + ": " + reason), offset_(offset), reason_(reason) {}

FarmGridLimits FarmGridLimits::OfScene() {
  const auto& l = contract::SceneLimits();
  return {l.max_asset_bytes(), l.max_grid_cells(), l.max_grid_axis_cells()};
}

DenseGrid ReadFarmGrid(std::string_view bytes, const FarmGridLimits& limits) {
  using contract::GoNumber;
  // Go reads through a reader that fails past max_bytes: a file that large is refused where
  // that reader would notice.
  const std::uint64_t readable = std::min<std::uint64_t>(bytes.size(), limits.max_bytes);
  if (readable < kHeader) {
    if (bytes.size() > limits.max_bytes) throw FarmGridError(readable, "the file is larger than the limit of one asset");
    throw FarmGridError(bytes.size(), "the file ends inside its 48-byte header");
  }
  if (!bytes.starts_with(kMagic)) throw FarmGridError(0, "not a farm grid file (no \"FARMGRID\" magic)");
  if (const auto v = Load<std::uint32_t>(bytes, 8); v != kVersion)
    throw FarmGridError(8, "version " + std::to_string(v) + ", but this farm reads version " + std::to_string(kVersion));
  std::uint32_t n[3];
  std::uint64_t cells = 1;
  for (int a = 0; a < 3; ++a) {
    n[a] = Load<std::uint32_t>(bytes, 12 + 4 * a);
    if (n[a] == 0) throw FarmGridError(12 + 4 * a, std::string("the grid has no cells along ") + kAxes[a]);
    if (n[a] > limits.max_axis_cells)
      throw FarmGridError(12 + 4 * a, std::to_string(n[a]) + " cells along " + kAxes[a] + ", more than the " +
                                          std::to_string(limits.max_axis_cells) + " of one axis");
    cells *= n[a];
  }
  if (cells > limits.max_cells)
    throw FarmGridError(12, std::to_string(n[0]) + " x " + std::to_string(n[1]) + " x " + std::to_string(n[2]) + " = " +
                                std::to_string(cells) + " cells, more than the " + std::to_string(limits.max_cells) +
                                " of one grid");
  const double magnitude = contract::SceneLimits().max_magnitude();
  float corner[6];
  for (int i = 0; i < 6; ++i) {
    const std::size_t at = 24 + 4 * i;
    corner[i] = Load<float>(bytes, at);
    const std::string name = std::string(i < 3 ? "min." : "max.") + kAxes[i % 3];
    if (!std::isfinite(corner[i])) throw FarmGridError(at, "the box's " + name + " is not finite");
    if (std::abs(double(corner[i])) > magnitude)
      throw FarmGridError(at, "the box's " + name + " " + GoNumber(corner[i]) + " is out of range: numbers are at most ±" +
                                  GoNumber(magnitude));
  }
  for (int a = 0; a < 3; ++a)
    if (!(corner[3 + a] > corner[a]))
      throw FarmGridError(36 + 4 * a, std::string("the box's max.") + kAxes[a] + " " + GoNumber(corner[3 + a]) +
                                          " is not above its min." + kAxes[a] + " " + GoNumber(corner[a]));

  const std::uint64_t size = kHeader + 4 * cells;
  std::vector<float> values(cells);
  for (std::uint64_t i = 0; i < cells; ++i) {
    const std::uint64_t at = kHeader + 4 * i;
    if (readable < at + 4) {
      if (bytes.size() > limits.max_bytes) throw FarmGridError(readable, "the file is larger than the limit of one asset");
      throw FarmGridError(bytes.size(), "the file ends inside its densities");
    }
    const float d = Load<float>(bytes, at);
    if (std::isfinite(d) && d >= 0 && double(d) <= magnitude) {
      values[i] = d;
      continue;
    }
    const std::string cell = "the density of cell (" + std::to_string(i % n[0]) + ", " + std::to_string(i / n[0] % n[1]) +
                             ", " + std::to_string(i / n[0] / n[1]) + ")";
    if (!std::isfinite(d)) throw FarmGridError(at, cell + " is not finite");
    if (d < 0) throw FarmGridError(at, cell + " is negative: " + GoNumber(d));
    throw FarmGridError(at, cell + " " + GoNumber(d) + " is out of range: numbers are at most ±" + GoNumber(magnitude));
  }
  if (bytes.size() > size) {
    if (size == limits.max_bytes) throw FarmGridError(size, "the file is larger than the limit of one asset");
    throw FarmGridError(size, "the file goes on past its last cell");
  }
  return DenseGrid(int(n[0]), int(n[1]), int(n[2]), std::move(values),
                   Bounds3{{corner[0], corner[1], corner[2]}, {corner[3], corner[4], corner[5]}});
}

}  // namespace farm
