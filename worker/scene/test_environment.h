#pragma once

// Helpers for tests (not linked into the worker): environment maps as Radiance HDR bytes,
// and scenes that use them.

#include <cmath>
#include <string>
#include <vector>

#include "math/rgb.h"
#include "scene/test_scenes.h"

namespace farm::testing {

// A Radiance HDR file (RGBE, flat scanlines) of width x height texels, row 0 at the top.
inline std::string EncodeRadianceHdr(int width, int height, const std::vector<Rgb>& texels) {
  std::string out = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(height) + " +X " +
                    std::to_string(width) + "\n";
  for (const Rgb& t : texels) {
    const float m = std::max({t.r, t.g, t.b});
    if (!(m > 1e-32f)) {
      out.append(4, '\0');
      continue;
    }
    int e = 0;
    const float scale = std::frexp(m, &e) * 256.0f / m;
    out += static_cast<char>(static_cast<unsigned char>(t.r * scale));
    out += static_cast<char>(static_cast<unsigned char>(t.g * scale));
    out += static_cast<char>(static_cast<unsigned char>(t.b * scale));
    out += static_cast<char>(static_cast<unsigned char>(e + 128));
  }
  return out;
}

// Gives the scene an environment mapping texture "sky" (blob `digest`), times radiance.
inline pb::Environment* AddEnvironmentMap(pb::Scene& s, const std::string& digest, const Rgb& radiance,
                                          double rotation_degrees = 0) {
  pb::Texture* t = s.add_textures();
  t->set_name("sky");
  t->set_path("sky.hdr");
  t->set_digest(digest);
  pb::Environment* env = s.mutable_environment();
  env->mutable_map()->set_texture("sky");
  Set(env->mutable_radiance(), radiance);
  env->set_rotation_degrees(rotation_degrees);
  return env;
}

inline pb::Environment* AddConstantEnvironment(pb::Scene& s, const Rgb& radiance) {
  pb::Environment* env = s.mutable_environment();
  Set(env->mutable_radiance(), radiance);
  return env;
}

}  // namespace farm::testing
