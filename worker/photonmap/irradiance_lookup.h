#pragma once

// Final gathering's read of the precomputed irradiance (Christensen 1999): one nearest
// photon per gather ray instead of a k-nearest estimate.

#include <algorithm>
#include <cstdint>
#include <optional>
#include <vector>

#include "math/rgb.h"
#include "math/vec3.h"
#include "photonmap/photon_map.h"

namespace farm {

// Photons whose normal is more than 60 degrees from the query's are not used: the same rule
// as the radiance estimate (photons on the back of a thin wall, or on a perpendicular wall
// at a corner, hold another surface's light).
inline constexpr float kIrradianceMinNormalCosine = 0.5f;

// How many nearest photons a lookup considers before giving up: the nearest one is almost
// always usable; the others cover a photon across a thin wall or around a corner.
inline constexpr int kIrradianceCandidates = 8;

// The photon nearest to p, within max_radius, whose normal faces the same way as n and that
// `visible(photon)` accepts (the caller checks that no wall stands between p and the
// photon: light leaks through thin walls otherwise): the one whose precomputed irradiance
// final gathering reads. Nothing if no candidate qualifies or the map has no irradiance.
// scratch is reused between calls.
template <typename VisibleFn>
std::optional<std::uint32_t> NearestIrradiancePhoton(const PhotonMap& map, const Vec3& p, const Vec3& n,
                                                     float max_radius, const VisibleFn& visible,
                                                     std::vector<PhotonNeighbour>& scratch) {
  if (!map.has_irradiance()) return std::nullopt;
  const auto usable = [&](std::uint32_t index) {
    const DecodedPhoton photon = map.photon(index);
    return Dot(photon.normal, n) >= kIrradianceMinNormalCosine && visible(photon);
  };
  // The nearest photon almost always qualifies, and a 1-nearest search prunes from its
  // first hit on: several times cheaper than gathering every candidate up front.
  map.NearestK(p, 1, max_radius, scratch);
  if (scratch.empty()) return std::nullopt;
  const std::uint32_t nearest = scratch.front().index;
  if (usable(nearest)) return nearest;
  map.NearestK(p, kIrradianceCandidates, max_radius, scratch);
  // Nearest first; equal distances by index, so the choice is deterministic.
  std::sort(scratch.begin(), scratch.end(), [](const PhotonNeighbour& a, const PhotonNeighbour& b) {
    return a.distance_squared != b.distance_squared ? a.distance_squared < b.distance_squared
                                                    : a.index < b.index;
  });
  for (const PhotonNeighbour& nb : scratch)
    if (nb.index != nearest && usable(nb.index)) return nb.index;
  return std::nullopt;
}

// The irradiance of NearestIrradiancePhoton.
template <typename VisibleFn>
std::optional<Rgb> NearestIrradiance(const PhotonMap& map, const Vec3& p, const Vec3& n, float max_radius,
                                     const VisibleFn& visible, std::vector<PhotonNeighbour>& scratch) {
  const std::optional<std::uint32_t> photon = NearestIrradiancePhoton(map, p, n, max_radius, visible, scratch);
  if (!photon) return std::nullopt;
  return map.irradiance(*photon);
}

}  // namespace farm
