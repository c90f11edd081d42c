#pragma once

// The 8-bit sRGB PNG preview of a render: what a browser or file viewer shows at a glance,
// exposed and tone-mapped as the scene's Output says (tone_map.h).

#include <cstdint>
#include <span>
#include <string>

#include "image/image.h"
#include "image/tone_map.h"

namespace farm {

// Linear value -> 8-bit sRGB code value: clamped to [0, 1] (NaN counts as 0), the sRGB
// transfer function (IEC 61966-2-1), rounded to nearest.
std::uint8_t LinearToSrgb8(float linear);

// Alpha in [0, 1] -> 8 bits, rounded to nearest; no transfer function.
std::uint8_t AlphaTo8(float alpha);

// Writes the R, G, B, A channels of `tile` into `rgba8`, the whole image's interleaved
// 8-bit RGBA buffer (row-major, width * height * 4 bytes). The tile's colour is
// premultiplied by alpha, as in OpenEXR; PNG stores straight alpha, so colour is divided by
// alpha first (where alpha > 0), then exposed and tone-mapped by `settings`. Throws
// ImageError if the tile lacks one of R, G, B, A or lies outside the image.
void WritePreviewPixels(const Image& tile, ImageSize image_size, std::span<std::uint8_t> rgba8,
                        const PreviewSettings& settings = {});

// Encodes the tile alone as a PNG of its rectangle's size, converted exactly as
// WritePreviewPixels converts it into the whole image's preview: the browser shows a
// finished tile (a render task's tile.png) with the tone mapping of the job's preview.png.
// Throws ImageError if the tile is empty or lacks one of R, G, B, A.
std::string EncodeTilePreviewPng(const Image& tile, const PreviewSettings& settings = {});

// Encodes a straight-alpha sRGB RGBA8 buffer as PNG bytes. Deterministic.
std::string EncodePngRgba8(ImageSize size, std::span<const std::uint8_t> rgba8);

}  // namespace farm
