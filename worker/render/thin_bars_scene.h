#pragma once

// A test and benchmark scene for edge anti-aliasing (not linked into the worker): thin dark
// bars at many angles lying on a white floor, seen obliquely and lit by one point light
// with direct light only. Nothing in it is random but the position of a sample inside its
// pixel, so every difference between renders is aliasing: the scene of issue 4's
// acceptance 2.

#include <cmath>
#include <numbers>

#include "scene/test_scenes.h"

namespace farm::testing {

// bar_width scales the bars' widths: at 1 they are 0.08 to 0.2 units, about 2 to 6 pixels
// at 320x240 (1.5 to 4 along the foreshortened direction): thin, but wide enough that one
// sample per pixel sees each of them somewhere along its length. Much thinner bars fall
// between samples for pixels on end, and no detector working on a 1-sample base pass can
// find them there.
inline pb::Scene ThinBarsScene(int width, int height, pb::AntialiasingMode mode,
                               uint32_t edge_samples, double bar_width = 1, uint64_t seed = 7) {
  pb::Scene s = MakeScene(width, height, {0, 9, 7}, {0, 0, 0.5}, {0, 1, 0}, 40, 1, seed);
  s.mutable_antialiasing()->set_mode(mode);
  s.mutable_antialiasing()->set_edge_samples(edge_samples);
  // Direct light only: no photon maps are given to the renderer, and the global map is not
  // gathered from. A point light needs one shadow ray: more would repeat the same one.
  s.mutable_indirect()->set_mode(pb::INDIRECT_MODE_PHOTON_MAP);
  s.mutable_sampling()->set_light_samples(1);
  AddLambert(s, "floor", Rgb(0.8f));
  AddLambert(s, "bar", Rgb(0.02f));
  AddQuad(s, "floor", {-6, 0, -6}, {0, 0, 12}, {12, 0, 0});  // y = 0, facing +y
  // Bars 0.3 or 0.6 above the floor, so that their shadows are edges too. A bar along d with
  // width w along p, where p x d = +y.
  constexpr int kBars = 14;
  for (int i = 0; i < kBars; ++i) {
    const double angle = std::numbers::pi * (0.03 + 0.97 * i / kBars);
    const double c = std::cos(angle), sn = std::sin(angle);
    const double w = bar_width * (0.08 + 0.12 * (i % 4) / 3.0);
    const double length = 5;
    const Vec3d centre(-3.2 + 6.4 * (i % 7) / 6.0, 0.3 + 0.3 * (i / 7), -1.5 + 3.0 * (i / 7));
    const Vec3d d(c * length, 0, sn * length);
    const Vec3d p(-sn * w, 0, c * w);
    AddQuad(s, "bar", centre - d * 0.5 - p * 0.5, p, d);
  }
  auto* light = s.add_lights()->mutable_point();
  Set(light->mutable_position(), {1.5, 6, 2});
  Set(light->mutable_intensity(), Rgb(40.0f));
  return s;
}

}  // namespace farm::testing
