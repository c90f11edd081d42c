#pragma once

// The farm grid file (docs/grid-format.md): a heterogeneous medium's densities on a dense
// voxel grid, read from bytes. The checks are contract/assets' (farmgrid.go) in the same
// order, refusing at the same byte offset with the same words, so that the worker refuses
// exactly what the client and the coordinator refuse (tests/vectors/grids/*.farmgrid).

#include <cstdint>
#include <string>
#include <string_view>

#include "contract/failure.h"
#include "media/dense_grid.h"

namespace farm {

// A farm grid file that breaks the format's rules: bad input, at a byte offset.
class FarmGridError : public BadInputError {
 public:
  FarmGridError(std::uint64_t offset, const std::string& reason);  // what(): "byte N: reason"
  std::uint64_t offset() const { return offset_; }
  const std::string& reason() const { return reason_; }

 private:
  std::uint64_t offset_;
  std::string reason_;
};

// The limits a file is held to: Scene's max_asset_bytes, max_grid_cells and
// max_grid_axis_cells unless a test says otherwise.
struct FarmGridLimits {
  std::uint64_t max_bytes = 0, max_cells = 0;
  std::uint32_t max_axis_cells = 0;
  static FarmGridLimits OfScene();
};

// The grid the file holds, its box the file's own. Throws FarmGridError.
DenseGrid ReadFarmGrid(std::string_view bytes, const FarmGridLimits& limits = FarmGridLimits::OfScene());

}  // namespace farm
