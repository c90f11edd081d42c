// Linear light to the 8-bit sRGB the canvas shows: what the final-image viewer and the live
// mosaic share.

/** Linear to 8-bit sRGB, clipped to [0, 1] (NaN and negative values are black). */
export function srgb8(v: number): number {
  if (!(v > 0)) return 0;
  if (v >= 1) return 255;
  const s = v <= 0.0031308 ? 12.92 * v : 1.055 * v ** (1 / 2.4) - 0.055;
  return Math.round(s * 255);
}
