#pragma once

// Which way light scattered more than once in a medium is found (docs/media.md, "Multiple
// scattering"): from the volume photon map, whose estimate weighs each of its k nearest
// photons by the phase function, or, for a Henyey-Greenstein lobe too narrow for k photons
// to weigh (|g| at or above the contract's path_traced_media_min_abs_g, rules.proto), by
// volumetric path tracing: camera paths go on through the medium by sampling its phase
// function. The coordinator's planner reads the same value (no volume map when no medium
// needs one); photon paths store no volume photon in a path-traced medium.

#include "media/medium.h"

namespace farm {

bool PathTracesMultipleScattering(const Medium& medium);

}  // namespace farm
