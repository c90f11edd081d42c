// The image a job would deliver if it stopped now, kept in the browser from what the farm
// stores: the newest round composite's accumulation.exr (per pixel, the weighted sums of
// R, G, B over the rounds so far and the sum of their weights; worker/image/
// accumulation_exr.h) plus every render tile finished since, each added with weight 1 (a
// round of samples_per_pixel samples). Under adaptive sampling a newer tile's true weight
// is its allocated samples over samples_per_pixel, so between composites the mean is
// approximate; the next composite replaces it with the exact one.

import type { ExrImage } from "./exr.js";

export interface Rect {
  x: number;
  y: number;
  width: number;
  height: number;
}

/** A finished render tile's beauty: R, G, B of its rectangle, row-major. */
export interface TileValues {
  round: number;
  rect: Rect;
  rgb: [Float32Array, Float32Array, Float32Array];
}

const RGB = ["R", "G", "B"] as const;

function channel(img: ExrImage, name: string, what: string): Float32Array {
  const values = img.channels.get(name);
  if (!values) throw new Error(`${what} has no channel ${name}`);
  return values;
}

/** The R, G, B channels of a decoded tile.exr at rect, or an Error naming what is missing. */
export function tileValues(img: ExrImage, round: number, rect: Rect): TileValues {
  if (img.width !== rect.width || img.height !== rect.height) {
    throw new Error(`tile.exr is ${img.width}x${img.height}, its task's rectangle ${rect.width}x${rect.height}`);
  }
  const [r, g, b] = RGB.map((c) => channel(img, c, "tile.exr"));
  return { round, rect, rgb: [r!, g!, b!] };
}

export class RunningImage {
  /** The round of the accumulation the sums hold (0: none yet). */
  baseRound = 0;
  private readonly sums: Float32Array; // R, G, B interleaved: the composite's
  private readonly weights: Float32Array;
  // The tiles of rounds after baseRound, by task id, and their sums and counts per pixel.
  private readonly newer = new Map<string, TileValues>();
  private readonly newerSums: Float32Array;
  private readonly newerCounts: Uint16Array;

  constructor(
    readonly width: number,
    readonly height: number,
  ) {
    this.sums = new Float32Array(3 * width * height);
    this.weights = new Float32Array(width * height);
    this.newerSums = new Float32Array(3 * width * height);
    this.newerCounts = new Uint16Array(width * height);
  }

  /** Whether the tile of this task is counted (in the sums or as a newer tile). */
  has(taskId: string, round: number): boolean {
    return round <= this.baseRound || this.newer.has(taskId);
  }

  /**
   * Replaces the sums with round's accumulation.exr (decoded) and drops the tiles it
   * already holds. An older round than the one held changes nothing (returns false).
   */
  setBase(round: number, acc: ExrImage): boolean {
    if (round <= this.baseRound) return false;
    if (acc.width !== this.width || acc.height !== this.height) {
      throw new Error(`accumulation.exr is ${acc.width}x${acc.height}, the job's image ${this.width}x${this.height}`);
    }
    const sums = RGB.map((c) => channel(acc, `sum.${c}`, "accumulation.exr"));
    const weight = channel(acc, "weight", "accumulation.exr");
    for (let p = 0; p < this.weights.length; p++) {
      for (let c = 0; c < 3; c++) this.sums[3 * p + c] = sums[c]![p]!;
      this.weights[p] = weight[p]!;
    }
    this.baseRound = round;
    for (const [id, tile] of this.newer) {
      if (tile.round > round) continue;
      this.fold(tile, -1);
      this.newer.delete(id);
    }
    return true;
  }

  /** Adds a finished tile of a round after baseRound (returns false if already counted). */
  addTile(taskId: string, tile: TileValues): boolean {
    if (this.has(taskId, tile.round)) return false;
    this.newer.set(taskId, tile);
    this.fold(tile, 1);
    return true;
  }

  /** Adds (sign 1) or takes away (-1) a tile's values in the newer sums. */
  private fold({ rect, rgb }: TileValues, sign: 1 | -1): void {
    for (let y = 0; y < rect.height; y++) {
      for (let x = 0; x < rect.width; x++) {
        const p = (rect.y + y) * this.width + rect.x + x;
        const t = y * rect.width + x;
        this.newerCounts[p] += sign;
        for (let c = 0; c < 3; c++) {
          const v = rgb[c]![t]!;
          // Exactly 0 once no tile is left, whatever rounding the sums took.
          this.newerSums[3 * p + c] = this.newerCounts[p] === 0 ? 0 : this.newerSums[3 * p + c]! + sign * (Number.isFinite(v) ? v : 0);
        }
      }
    }
  }

  /** The mean so far of pixel p, linear R, G, B into out (NaN where nothing has arrived yet). */
  meanAt(p: number, out: Float32Array): void {
    const w = this.weights[p]! + this.newerCounts[p]!;
    for (let c = 0; c < 3; c++) out[c] = w > 0 ? (this.sums[3 * p + c]! + this.newerSums[3 * p + c]!) / w : NaN;
  }
}
