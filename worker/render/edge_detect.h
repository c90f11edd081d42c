#pragma once

// Edge detection for edge anti-aliasing: which pixels of a tile get supersampled.
//
// Supersampling fixes what varies inside a pixel faster than the base samples resolve:
// silhouettes, creases, boundaries between materials, shadow edges. It does nothing for
// texture detail (texture lookups already filter over the pixel's footprint) or for the
// noise of the light estimates (more samples of a pixel are not what removes it), so the
// test reads cues that neither moves (SurfaceCues): those of the pixel's eight neighbours'
// base samples, and those of the pixel's own pilot, a few camera rays (kEdgePilots) drawn
// apart from the samples it is estimated from and traced for their cues only (see
// "Unbiased" below); never those of the pixel's own base samples:
//
//   surface   an id of the surfaces the camera path's first branch met: the first hit
//             and those seen from it through specular bounces (shape, mesh part and
//             material; SampleResult::surface). A pixel is an edge where two of its
//             neighbours have different ids, or its pilot's rays have another or
//             disagree, or a neighbour's own base samples disagree on it: silhouettes,
//             and albedo edges between untextured shapes.
//   normal    the mean of the surfaces' own normals (SampleResult::surface_normal:
//             interpolated, not normal-mapped): an edge where two neighbours', or the
//             pilot's and a neighbour's, turn by more than acos(kEdgeNormalCos) from each
//             other (creases, facets).
//   depth     1/depth, which is linear in screen space across a plane, so that the sums
//             of opposite neighbours (along the row, the column and the two diagonals)
//             are equal on a plane, each twice the pixel's: an edge where two of those sums
//             differ by more than kEdgeDepthStep of half their mean, the pixel's 1/depth
//             on a plane, or one differs from twice the pilot's by more than kEdgeDepthStep
//             of the pilot's (one surface occluding another part of itself).
//   light     the log-luminance of the irradiance from the lights on the surfaces the path
//             shaded, direct and through the caustic map (SampleResult::light_irradiance:
//             shadowed, over the geometric normal, no BSDF, not the environment's soft and
//             noisy share), so that texture patterns and normal maps leave it and the edges
//             of shadows and caustics stay: an edge where its Sobel
//             gradient exceeds the scene's edge_threshold (the Sobel kernels weigh the
//             pixel itself zero). Indirect light, whose final-gathering noise is no edge,
//             is not read.
//
// Log-luminance makes the light test relative (a step from 0.1 to 0.2 counts as much as one
// from 10 to 20, which is what the eye sees after tone mapping); a floor of 1/256 keeps
// noise in the darkest displayable values from counting as edges. The Sobel kernels are
// divided by 8, their weight on each side, so the gradient is in log units per pixel: a
// linear ramp of slope k reads k, and a sharp step of height h reads h/2 on the pixels
// either side of it.
//
// Unbiased: an edge pixel's value is the mean of all its samples, its base samples among
// them. Were the decision to read the pixel's own base samples, the number of samples
// would depend on what they saw, and the mean would be biased, round after round: a
// light seen in a mirror over part of a pixel makes an edge when the base sample sees it
// and often none when it misses, so the pixel kept a dark single sample in some rounds
// and a supersampled mean in others, and converged 25% too dark. The neighbours' samples
// and the pilot are independent of the pixel's own, so the decision is, and the pixel's
// estimate is unbiased whatever it decides. The pilot restores, and betters, what the
// pixel's own base sample used to see: without it a feature smaller than a pixel that no
// neighbour saw (a small highlight) kept one sample a round, unbiased and very noisy.
//
// Bright edges: an edge pixel's error is the contrast across the edge times how well its
// samples place the edge, so in the linear image the edges of lights dominate: a light of
// radiance 13 against a ceiling of 0.2 is 65 times the contrast of a shadow's edge, and
// its outline, and its image in a mirror or in glass (a feature smaller than a pixel),
// held most of the Cornell boxes' squared error after many rounds. An edge pixel whose
// neighbourhood holds an emitter's light (what its neighbours' base samples or its pilot
// saw emitted, directly or through specular bounces, SampleResult::emitted) takes
// EdgeSampleFactor times edge_samples: the square root of the ratio of that light to the
// darkest neighbour over kBrightEdgeRatio, rounded, from 1 to kMaxEdgeSampleFactor. An
// edge that no light borders takes edge_samples. Samples spent in proportion to contrast
// would minimise the squared error (docs/adaptive-sampling.md's law, the error of a
// pixel's coverage falling as samples^-3/4 at a straight edge and samples^-1/2 at a
// feature smaller than a pixel); the square root stays below it and the cap bounds what
// a light's outline costs. The factor reads the same cues as the decision, never the
// pixel's own samples, so the pixel stays unbiased.
//
// The decision for a pixel depends only on the eight base-pass neighbours around it,
// mirrored at the image border (never at a tile border), and on its pilot (a pure function
// of the round's seed and the pixel), so it is the same whichever tile the pixel is
// rendered in.

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "image/image.h"
#include "math/vec3.h"

namespace farm {

inline constexpr float kEdgeLuminanceFloor = 1.0f / 256.0f;
// Neighbouring normals closer than about 25 degrees are one smooth surface.
inline constexpr double kEdgeNormalCos = 0.9;
// A tenth of the pixel's inverse depth.
inline constexpr double kEdgeDepthStep = 0.1;
// Bright edges (above): a light up to about 9 times its darkest neighbour's luminance
// takes edge_samples, as any other edge; 16 times takes 2 times edge_samples, 64 times 4.
inline constexpr double kBrightEdgeRatio = 4;
inline constexpr std::uint32_t kMaxEdgeSampleFactor = 8;

// log(luminance + floor) of a linear RGB value (Rec. 709 luminance).
double EdgeLogLuminance(float r, float g, float b);

// Values over `area`: a tile with its one-pixel apron, clipped to the image.
template <typename T>
class ApronGrid {
 public:
  explicit ApronGrid(const PixelRect& area)
      : area_(area), values_(static_cast<std::size_t>(std::max(0, area.width)) * std::max(0, area.height)) {
    if (area.width <= 0 || area.height <= 0) throw std::invalid_argument("ApronGrid: empty area");
  }

  const PixelRect& area() const { return area_; }
  void set(int x, int y, const T& value) { values_[Index(x, y)] = value; }
  // Coordinates outside the area are mirrored into it (x - 1 of the first column reads
  // x + 1). For a pixel of the tile the area holds every neighbour inside the image, so
  // this is mirroring at the image border: a border pixel's missing neighbours are
  // stand-ins from the image, never the pixel itself (see "Unbiased" above). Only an
  // image one pixel wide or tall has nothing to mirror, and clamps.
  const T& at(int x, int y) const { return values_[Index(Mirror(x, area_.x, area_.x_end()), Mirror(y, area_.y, area_.y_end()))]; }

 private:
  static int Mirror(int v, int begin, int end) {
    if (v < begin) v = 2 * begin - v;
    else if (v >= end) v = 2 * (end - 1) - v;
    return std::clamp(v, begin, end - 1);
  }
  std::size_t Index(int x, int y) const {
    return static_cast<std::size_t>(y - area_.y) * area_.width + (x - area_.x);
  }
  PixelRect area_;
  std::vector<T> values_;
};

using LogLuminanceGrid = ApronGrid<double>;

// A pixel's geometric cues from its base samples (see above).
struct SurfaceCues {
  std::uint32_t surface = 0;  // of its first base sample; 0 where it hit nothing
  bool mixed = false;         // its base samples met different surfaces
  Vec3 normal;                // sum of the surface normals of the samples that hit (not unit)
  double inverse_depth = 0;   // 1 / mean depth of the samples that hit; 0 for none
  float emitted = 0;          // the largest luminance of the light a sample saw emitted
  float luminance = 0;        // of the base samples' mean radiance (not set for a pilot)
};

using SurfaceCueGrid = ApronGrid<SurfaceCues>;

// The Sobel gradient magnitude at (x, y), in log units per pixel (see above).
double SobelGradient(const LogLuminanceGrid& grid, int x, int y);

// Whether the surface, normal or depth cues of (x, y)'s eight neighbours, and of its pilot
// if not null, make it an edge (see above).
bool SurfaceEdge(const SurfaceCueGrid& grid, int x, int y, const SurfaceCues* pilot = nullptr);

// How many times edge_samples edge pixel (x, y) takes (bright edges, above), from its
// eight neighbours' cues and its pilot's: 1 to kMaxEdgeSampleFactor.
std::uint32_t EdgeSampleFactor(const SurfaceCueGrid& grid, int x, int y, const SurfaceCues& pilot);

// One byte per pixel of `tile` (row-major): 1 where SobelGradient exceeds threshold. The grid
// must cover the tile with its apron clipped to the image (ApronArea).
std::vector<std::uint8_t> DetectEdges(const LogLuminanceGrid& grid, const PixelRect& tile,
                                      double threshold);

// As above, and also 1 where SurfaceEdge holds; both grids cover the same area. pilots, if
// not null, holds each tile pixel's pilot.
std::vector<std::uint8_t> DetectEdges(const SurfaceCueGrid& surfaces, const LogLuminanceGrid& light,
                                      const PixelRect& tile, double threshold,
                                      const SurfaceCueGrid* pilots = nullptr);

// `tile` grown by one pixel on each side and clipped to the image.
PixelRect ApronArea(const PixelRect& tile, ImageSize image);

}  // namespace farm
