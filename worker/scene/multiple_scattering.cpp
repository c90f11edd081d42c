#include "scene/multiple_scattering.h"

#include <cmath>

#include "contract/rules.h"

namespace farm {

bool PathTracesMultipleScattering(const Medium& medium) {
  // Homogeneous or grid alike: g is the medium's. In float, as the medium holds g: rounding
  // is monotonic, so a medium the planner path traces (|g| >= the threshold in double) is
  // path traced here too, and it gets no volume map it would need.
  return std::abs(medium.g()) >= static_cast<float>(contract::SceneLimits().path_traced_media_min_abs_g());
}

}  // namespace farm
