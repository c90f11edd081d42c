#pragma once

#include <cstdint>
#include <stop_token>
#include <string>
#include <vector>

#include "math/rgb.h"
#include "photonmap/photon_map.h"
#include "photonmap/photon_snapshot.h"
#include "photonmap/radiance_estimate.h"
#include "scene/scene.h"
#include "scene/scene_data.h"
#include "util/progress.h"

namespace farm {

// A site stands for at most 1/kSiteNeighbourShare of the photons of an estimate at it:
// the read of the site nearest to a point is then unbiased within 0.1%, what 8 x 40,000
// reads resolve. With a larger share the nearest site sits where the photons are denser
// than its estimate counts for: +0.1% to +0.8% at k/7, +2.4% at k/3, +11% at k/2
// (IrradiancePrecompute.SitesReadByTheNearestGiveTheirDensity).
inline constexpr std::uint64_t kSiteNeighbourShare = 16;

// How many of a global map's photons carry precomputed irradiance in a round whose
// estimates at them gather `neighbours` photons: the first ones in tree order, which are
// the kd-tree's top levels (2^L - 1 photons; any leading part of a left-balanced tree is a
// kd-tree itself, so final gathering searches them with the same code), the fewest levels
// with a site to every neighbours / kSiteNeighbourShare photons or fewer, all of them at
// most. A node of the tree is the median of its subtree, so the sites spread over the
// surfaces as the photons do (Christensen's subset): with the default 100 neighbours one
// photon in 3 to 6 in the first round, more as the rounds shrink k, every photon from 16.
// The precompute, whose searches and coverage probes were a third of a round, runs at the
// sites alone.
std::uint64_t IrradianceSites(std::uint64_t photons, int neighbours);

// How many photons the global estimate gathers at a site: its k, or fewer where its
// max_radius bounds the search (few photons for a small radius). Of the tree's first 63
// photons (its top six levels, spread over the surfaces as the photons are), the count
// one in eight of them finds or fewer, so that the sparse parts of the map have sites
// enough too. Deterministic: every precompute task of a round finds the same.
int GatheredNeighbours(const PhotonMap& global, const RadianceEstimateSettings& estimate);

// Part `part` of `parts` of the irradiance at the global map's sites (IrradianceSites of
// its photons and GatheredNeighbours of the round's global estimate: sites
// [S part / parts, S (part + 1) / parts)), in the snapshot's tree order (Christensen
// 1999), as irradiance-shard bytes (docs/photon-snapshot.md); the coordinator merges the
// parts into the snapshot so that final gathering reads one precomputed value per gather
// ray instead of a k-nearest estimate. radius_scale shrinks the search radius as in
// RoundSettings. Deterministic. progress advances as in ComputeIrradiance. Throws
// std::invalid_argument unless part < parts.
std::string ComputeIrradianceShard(const Scene& scene, const PhotonSnapshot& photons, std::uint32_t part,
                                   std::uint32_t parts, double radius_scale, std::stop_token stop = {},
                                   Progress progress = {});

// What ComputeIrradianceShard encodes, for any PhotonMap (tests use in-memory maps): for
// each photon i of the range, the irradiance on the side of its normal from the global
// map's k nearest photons, i itself among them (box filter, the scene's global estimate as
// ForRound(radius_scale) makes it: radius and k shrink with the rounds) plus, if there is
// a caustic map, its estimate (the scene's caustic estimate, likewise), each over the
// surface its disc covers (surface_estimate.h: no light lost at edges): all the light the global map's photon holds but direct light, which final
// gathering samples with shadow rays at the gather hit instead. Parallel (TBB) and
// deterministic: each value depends only on the maps and i. Throws std::invalid_argument
// for a range outside the map or a radius_scale that is not finite and > 0. progress
// advances by the photons of each batch once their values are computed: photon_count in
// all.
std::vector<Rgb> ComputeIrradiance(const SceneData& scene, const PhotonMap& global,
                                   const PhotonMap* caustic, std::uint64_t first_photon,
                                   std::uint64_t photon_count, double radius_scale,
                                   std::stop_token stop = {}, Progress progress = {});

}  // namespace farm
