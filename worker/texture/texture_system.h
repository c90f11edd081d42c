#pragma once

// Textures through OpenImageIO's TextureSystem: one per worker process, with a tile cache
// bounded by TextureSystemOptions::cache_mib (farm-worker --texture-cache-mib).
//
// A texture file (a blob: PNG, JPEG, OpenEXR, Radiance HDR) is first prepared, once per
// worker host: converted to linear values as its use says (below), given an RGBA layout
// (grey replicated into RGB; alpha 1 where there is none) and written as a tiled,
// MIP-mapped TIFF (.tx, 64x64 tiles, zip; levels by box-filtered halving) into the
// prepared folder, named by the blob's digest, the use and the decoding, through a temporary file
// renamed into place (workers sharing the folder are safe). Lookups then read tiles of
// the prepared file through the cache, filtered over the footprint a lookup gives
// (TextureFilter); a footprint of zero reads the finest level (bilinear), which photons
// and the alpha cut-out test use.
//
// Decoding, as assets.proto says: a colour (base colour, emission) is sRGB in 8- and
// 16-bit files, data (metallic-roughness, normals) is linear, float files are linear;
// Texture.encoding overrides the rule for integer files. sRGB files are converted to
// linear before their MIP levels are made (filtering sRGB values would darken every
// average: a black and white checkerboard's mean is 0.5 in linear light, 0.21 in sRGB),
// into half floats; linear integer files keep their type.
//
// OIIO headers stay in the .cpp: every shading file includes this one.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "math/rgb.h"
#include "math/vec3.h"

namespace farm {

// What a texture stands for, which decides how its stored values become linear ones.
enum class TextureUse { kColor, kData };

// Texture.encoding: unset follows the use.
enum class TextureEncoding { kByUse, kSrgb, kLinear };

// Texture.wrap: how coordinates outside [0, 1] read the image.
enum class TextureWrap { kRepeat, kClamp, kMirror };

struct Rgba {
  Rgb rgb;
  float alpha = 1;
};

// How a lookup filters over its footprint.
enum class TextureFilter {
  // OIIO's anisotropic MIP-map filter: bilinear probes along the footprint's major axis at
  // the level of its minor one, at most kMaxAnisotropy of them (a longer footprint is read
  // at a coarser level, a little blurred across). For what the camera sees sharply.
  kAnisotropic,
  // Trilinear over a square as wide as the footprint's major axis: two bilinear reads, at
  // the two levels about that width. For a ray whose cone is already wide (after a
  // diffuse bounce, footprint.h), whose footprint's shape is of no visible consequence.
  kIsotropic,
};

// The probes an anisotropic lookup takes at most (OIIO's own default is 32, which lets a
// grazing footprint cost 64 bilinear reads).
inline constexpr int kMaxAnisotropy = 8;

// Where on the texture a lookup reads: texture coordinates (glTF's: (0, 0) is the image's
// top-left corner, v grows downwards), the footprint's two axes in texture coordinates
// (the change of (u, v) across the pixel's footprint in two directions) and its filter.
// Zero axes read the finest level, bilinearly, whatever the filter.
struct TextureLookup {
  Vec2 uv;
  Vec2 axis1, axis2;
  TextureFilter filter = TextureFilter::kAnisotropic;
};

struct TextureSystemOptions {
  // Bound of the tile cache, MiB.
  std::size_t cache_mib = 512;
  // Where prepared textures are kept (created if missing).
  std::filesystem::path prepared_dir;
};

// Opaque: an OIIO texture handle of a prepared file.
struct PreparedTexture {
  void* handle = nullptr;
  bool srgb = false;  // converted from sRGB (for messages and tests)
};

class TextureSystem {
 public:
  explicit TextureSystem(TextureSystemOptions options);
  ~TextureSystem();
  TextureSystem(const TextureSystem&) = delete;
  TextureSystem& operator=(const TextureSystem&) = delete;

  // Where the source file of a texture is, called only when it must be prepared (the
  // daemon fetches the blob then).
  using SourceFile = std::function<std::filesystem::path()>;

  // The prepared form of the texture blob with `digest` for `use`; prepares it from
  // source() if the prepared folder does not have it yet. Throws BadInputError if the file
  // is not an image or has more than max_texture_pixels pixels, and what the source or the
  // disk throws (a blob that cannot be had, a full disk). Thread-safe.
  PreparedTexture Prepare(const std::string& digest, TextureUse use, TextureEncoding encoding,
                          const SourceFile& source);

  // A filtered lookup. Thread-safe; never throws (a failed read gives magenta, which a
  // prepared file, checked when it was prepared, does not do).
  Rgba Lookup(const PreparedTexture& texture, const TextureLookup& at, TextureWrap wrap) const;

  // The mean of the whole image (its coarsest MIP level, of one texel).
  Rgba Average(const PreparedTexture& texture) const;

  // Bytes of tiles the cache holds now (at most about cache_mib MiB).
  std::uint64_t CacheBytes() const;

  const TextureSystemOptions& options() const { return options_; }

 private:
  struct Impl;
  TextureSystemOptions options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace farm
