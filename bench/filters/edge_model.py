"""A numerical model of bench/filters/light_edge.py's figure: how much lower a pixel
filter's error at a straight high-contrast edge is than the box's at equal samples, and
what the film sampler changes in it (docs/pixel-filters.md, "What a filter gains at equal
samples").

    bench/filters/edge_model.py [--edges N] [--trials T] [--samplers a,b,...]
                                [--edge ANGLE,OFFSET ...]

A straight edge of contrast 1 crosses a 64x64 image; the pixels it crosses and their 8
neighbours take 12 samples, the others 1 (edge anti-aliasing's 1 and 12, its detector
idealised). Each filter is reconstructed as the farm does (worker/render/filter_splats.h):
a supersampled pixel's samples weigh f(s - c) at their positions, a 1-sample pixel counts
by its mean at the filter's exact weight over its area, and the sum is divided by the
summed weight; the box of radius 1/2 is the mean of the pixel's samples. Each is compared
with the exact filtered edge (the box: the covered fraction) over the pixels within 2.5 px
of the edge, away from the image border. Samplers of the film position, all uniform over
the pixel:

  per-pixel   each pixel its own Owen-scrambled 2D Sobol points 0..n-1 (the farm before the
              film sampler: pixel_sampler.h's first pair)
  global      one 2D Sobol sequence over the image, sample j of a pixel the point of block j
              in it, the bits below the pixel Owen-scrambled per column (x) and row (y): the
              farm's film sampler (worker/sampling/film_sampler.h)
  shift       the same sequence randomised by one random digital shift (XOR) of the bits
              below the pixel for the whole image: structured, as pbrt-v4's SobolSampler
              leaves its pixel dimensions
  zsobol      pbrt-v4's ZSobolSampler ordering: Morton index of the pixel and sample, its
              base-4 digits permuted by hashes of the digits above, one Owen scramble for all
  iid         independent uniform points, the reference case of the bound 1 / integral f^2

The edges are the Cornell light's two long ones (as the pixel grid cuts them) and N at
random angles and offsets, or those given by --edge (the normal's angle in degrees from
the x axis, the offset in pixels from the image centre). It prints, per edge and over all,
the RMSE of the box and the ratios box / Gaussian (radius 2, sigma 1/2) and box / Mitchell
(radius 2, B = C = 1/3). Pure numpy; a few minutes. The model is not the renderer: the
farm's own figures are light_edge.py's and PixelFilterEdge's (worker/render)."""

import argparse
import itertools
import math

import numpy as np

K = 6
S = 1 << K  # the image is S x S
N = 12  # samples of a supersampled pixel
U32 = np.uint64(0xFFFFFFFF)


def reverse32(v):
    v = v.astype(np.uint64) & U32
    out = np.zeros_like(v)
    for b in range(32):
        out |= ((v >> np.uint64(b)) & np.uint64(1)) << np.uint64(31 - b)
    return out


DIM1 = [0x80000000]
for _ in range(31):
    DIM1.append(DIM1[-1] ^ (DIM1[-1] >> 1))


def sobol(index, dim):
    """32-bit fractions of Sobol dimension 0 or 1 (worker/sampling/sobol.cpp)."""
    index = index.astype(np.uint64)
    if dim == 0:
        return reverse32(index)
    v = np.zeros_like(index)
    for b in range(32):
        v ^= np.where((index >> np.uint64(b)) & np.uint64(1), np.uint64(DIM1[b]), np.uint64(0))
    return v


def owen(v, seed):
    """sobol.cpp's OwenScramble."""
    seed = np.asarray(seed, dtype=np.uint64) & U32
    mul = lambda a, c: (a * np.uint64(c)) & U32  # noqa: E731
    v = reverse32(v)
    v = v ^ mul(v, 0x3D20ADEA)
    v = (v + seed) & U32
    v = (v * ((seed >> np.uint64(16)) | np.uint64(1))) & U32
    v = v ^ mul(v, 0x05526C56)
    v = v ^ mul(v, 0x53A22864)
    return reverse32(v)


def mix(v):
    v = v.astype(np.uint64)
    v ^= v >> np.uint64(31)
    v = v * np.uint64(0x7FB5D329728EA185)
    v ^= v >> np.uint64(27)
    v = v * np.uint64(0x81DADEF4BC2DD44D)
    v ^= v >> np.uint64(33)
    return v


class Samplers:
    """Each returns the film offsets (ux, uy), arrays [y, x, j] in [0, 1)."""

    def __init__(self, rng):
        self.rng = rng

    def seeds(self, shape):
        return self.rng.integers(0, 2**32, size=shape, dtype=np.uint64)

    def per_pixel(self):
        first = np.arange(N, dtype=np.uint64)
        return tuple(owen(np.broadcast_to(sobol(first, d), (S, S, N)), self.seeds((S, S, 1))) / 2**32 for d in (0, 1))

    def _global(self, randomise):
        index = np.arange(N * S * S, dtype=np.uint64)
        x, y = sobol(index, 0), sobol(index, 1)
        px, py = (x >> np.uint64(32 - K)).astype(np.int64), (y >> np.uint64(32 - K)).astype(np.int64)
        fx, fy = randomise((x << np.uint64(K)) & U32, px, (y << np.uint64(K)) & U32, py)
        j = (index // np.uint64(S * S)).astype(np.int64)
        ux, uy = np.zeros((S, S, N)), np.zeros((S, S, N))
        ux[py, px, j], uy[py, px, j] = fx / 2**32, fy / 2**32
        return ux, uy

    def global_owen(self):
        cols, rows = self.seeds(S), self.seeds(S)
        return self._global(lambda fx, px, fy, py: (owen(fx, cols[px]), owen(fy, rows[py])))

    def shift(self):
        a, b = self.seeds(2)
        return self._global(lambda fx, px, fy, py: (fx ^ a, fy ^ b))

    def zsobol(self):
        # A pixel has 16 slots (a power of 4 at least N) and takes the first N.
        yy, xx, jj = np.meshgrid(*(np.arange(n, dtype=np.uint64) for n in (S, S, N)), indexing="ij")
        morton = np.zeros_like(xx)
        for b in range(K):
            morton |= ((xx >> np.uint64(b)) & np.uint64(1)) << np.uint64(2 * b)
            morton |= ((yy >> np.uint64(b)) & np.uint64(1)) << np.uint64(2 * b + 1)
        index = (morton << np.uint64(4)) | jj
        perms = np.array(list(itertools.permutations(range(4))), dtype=np.uint64)
        salt = self.seeds(1)[0]
        out = np.zeros_like(index)
        for i in range((2 * K + 4) // 2 - 1, -1, -1):
            shift = np.uint64(2 * i)
            digit = (index >> shift) & np.uint64(3)
            p = (mix((index >> (shift + np.uint64(2))) ^ salt) >> np.uint64(24)) % np.uint64(24)
            out |= perms[p.astype(np.int64), digit.astype(np.int64)] << shift
        a, b = self.seeds(2)
        return owen(sobol(out, 0), a) / 2**32, owen(sobol(out, 1), b) / 2**32

    def iid(self):
        return self.rng.random((S, S, N)), self.rng.random((S, S, N))


SAMPLERS = {"per-pixel": "per_pixel", "global": "global_owen", "shift": "shift", "zsobol": "zsobol", "iid": "iid"}


def gaussian(x, r=2.0, s=0.5):
    return np.where(np.abs(x) < r, np.exp(-x * x / (2 * s * s)) - math.exp(-r * r / (2 * s * s)), 0.0)


def mitchell(x, r=2.0):
    b = c = 1 / 3
    x = np.abs(2 * x / r)
    near = ((12 - 9 * b - 6 * c) * x**3 + (-18 + 12 * b + 6 * c) * x**2 + (6 - 2 * b)) / 6
    far = ((-b - 6 * c) * x**3 + (6 * b + 30 * c) * x**2 + (-12 * b - 48 * c) * x + (8 * b + 24 * c)) / 6
    return np.where(x < 1, near, np.where(x < 2, far, 0.0))


def box(x):
    return np.where(np.abs(x) < 0.5, 1.0, 0.0)


FILTERS = {"gaussian": (gaussian, 2.0), "mitchell": (mitchell, 2.0)}
QUAD = (np.arange(64) + 0.5) / 64


def exact(f, r, nx, ny, off):
    """The filtered edge at every pixel centre: lit where nx (x - S/2) + ny (y - S/2) > off.
    The filter is separable: the axis with the larger normal component is integrated
    exactly through f's cumulative integral, the other by quadrature."""
    t = (np.arange(-int(r * 2000), int(r * 2000)) + 0.5) / 2000
    cdf = np.concatenate([[0], np.cumsum(f(t))])
    ends = np.concatenate([t - 0.00025, [t[-1] + 0.00025]])
    upper = lambda a: (cdf[-1] - np.interp(a, ends, cdf)) / cdf[-1]  # noqa: E731
    c = np.arange(S) + 0.5
    swap = abs(nx) > abs(ny)
    a, b = (ny, nx) if swap else (nx, ny)
    ca, cb = (c[:, None], c[None, :]) if swap else (c[None, :], c[:, None])
    ts = t[::20]
    ws = f(ts) / f(ts).sum()
    value = np.zeros((S, S))
    for tv, wv in zip(ts, ws):
        threshold = (off - a * (ca + tv - S / 2)) / b - (cb - S / 2)
        value += wv * (upper(threshold) if b > 0 else 1 - upper(threshold))
    return value


def reconstruct(f, r, xs, ys, lit, taken, smooth):
    """filter_splats.h's estimate at every pixel (np.roll wraps at the border, which the
    band stays away from)."""
    margin = int(math.ceil(r - 0.5))
    count = taken.sum(-1)
    mean = (lit * taken).sum(-1) / count
    cx, cy = np.arange(S)[None, :, None] + 0.5, np.arange(S)[:, None, None] + 0.5
    num, den = np.zeros((S, S)), np.zeros((S, S))
    for dy in range(-margin, margin + 1):
        for dx in range(-margin, margin + 1):
            at = lambda a: np.roll(np.roll(a, -dy, 0), -dx, 1)  # noqa: E731  (pixel p + (dx, dy) at p)
            w = f(at(xs) - cx) * f(at(ys) - cy) * at(taken)
            area = f(dx + QUAD - 0.5).mean() * f(dy + QUAD - 0.5).mean()
            by_mean = at(smooth)
            num += np.where(by_mean, area * at(mean), (w * at(lit)).sum(-1) / at(count))
            den += np.where(by_mean, area, w.sum(-1) / at(count))
    return num / den


def edge_errors(draw, samplers, angle, off, trials):
    nx, ny = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    yy, xx = np.mgrid[0:S, 0:S] + 0.5
    dist = np.abs(nx * (xx - S / 2) + ny * (yy - S / 2) - off)
    inside = (xx > 6) & (xx < S - 6) & (yy > 6) & (yy < S - 6)
    band = (dist <= 2.5) & inside
    crossed = dist <= (abs(nx) + abs(ny)) / 2
    supersampled = np.zeros_like(crossed)
    for a, b in itertools.product((-1, 0, 1), repeat=2):
        supersampled |= np.roll(np.roll(crossed, a, 0), b, 1)
    taken = np.arange(N)[None, None, :] < np.where(supersampled, N, 1)[:, :, None]
    truth = {"box": exact(box, 0.5, nx, ny, off)} | {k: exact(f, r, nx, ny, off) for k, (f, r) in FILTERS.items()}
    squares = {}
    for name in samplers:
        for _ in range(trials):
            ux, uy = getattr(draw, SAMPLERS[name])()
            xs, ys = np.arange(S)[None, :, None] + ux, np.arange(S)[:, None, None] + uy
            lit = (nx * (xs - S / 2) + ny * (ys - S / 2) > off).astype(float)
            estimate = {"box": (lit * taken).sum(-1) / taken.sum(-1)}
            for k, (f, r) in FILTERS.items():
                estimate[k] = reconstruct(f, r, xs, ys, lit, taken, ~supersampled)
            for k, v in estimate.items():
                squares.setdefault(name, {}).setdefault(k, []).append((v - truth[k])[band] ** 2)
    return {s: {k: float(np.mean(np.concatenate(v))) for k, v in d.items()} for s, d in squares.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--edges", type=int, default=16, help="random edges (angle, offset), besides the light's two")
    ap.add_argument("--trials", type=int, default=6, help="sample sets per edge and sampler")
    ap.add_argument("--samplers", default="per-pixel,global,shift,zsobol,iid")
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--edge", action="append", default=[], help="ANGLE,OFFSET: this edge instead (repeatable)")
    args = ap.parse_args()
    samplers = args.samplers.split(",")
    rng = np.random.default_rng(args.seed)
    draw = Samplers(rng)
    # The Cornell light's long edges are horizontal and cross their rows 0.57 and 0.42 of a
    # pixel down (bench/README.md): a normal at 90 degrees, offsets of those fractions.
    edges = [(90.0, 0.57), (90.0, 0.42)] + [(float(rng.uniform(0, 90)), float(rng.uniform(0, 1)))
                                            for _ in range(args.edges)]
    if args.edge:
        edges = [tuple(float(v) for v in e.split(",")) for e in args.edge]
    total = {}
    for angle, off in edges:
        result = edge_errors(draw, samplers, angle, off, args.trials)
        cells = []
        for s, r in result.items():
            for k, v in r.items():
                total.setdefault(s, {}).setdefault(k, []).append(v)
            cells.append(f"{s} {math.sqrt(r['box']):.4f} {math.sqrt(r['box'] / r['gaussian']):.2f} "
                         f"{math.sqrt(r['box'] / r['mitchell']):.2f}")
        print(f"normal {angle:5.1f} deg, offset {off:.2f}: " + " | ".join(cells), flush=True)
    print("sampler: box RMSE, box / Gaussian, box / Mitchell over all edges")
    for s, r in total.items():
        b, g, m = (np.mean(r[k]) for k in ("box", "gaussian", "mitchell"))
        print(f"  {s:9s} {math.sqrt(b):.4f}  {math.sqrt(b / g):.2f}  {math.sqrt(b / m):.2f}")


if __name__ == "__main__":
    main()
