"""Issue 14's acceptance 7: adaptive sampling against uniform sampling on the caustics scene
at equal time, both against the long Mitsuba 3 reference of converge.py.

    bench/crosscheck/adaptive.py BUILD_DIR OUT_DIR [--size N] [--rounds N] [--reference-spp N]

scenes/cornell-caustics.json at SIZE x SIZE is rendered twice by `farm render` (two
workers), ROUNDS progressive rounds each: once as it is (sampling.adaptive OFF), once with
sampling.adaptive ON, nothing else changed. Adaptive sampling draws as many camera samples a
round as round 2 did, so the two take about the same time; the wall time of each is
printed, and the ratio of their RMSEs both as measured and at equal time (the adaptive
RMSE scaled by sqrt(its time / the uniform time): an unbiased estimate's RMSE falls as one
over the square root of the work). The RMSE is against the cached reference of converge.py
(the same scene, size and samples, so the same cache entry; made if missing), its
noisiest measured pixels rendered again at 32 times the samples (converge.refine_reference,
cached too), less the reference's own noise, over the pixels converge.py measures (the light and its neighbours
left out). Also printed: where the adaptive run's samples went, from the image's samples
layer (samples.Y): the range a pixel, and the share the tenth of the pixels with the
largest error against the reference drew; OUT_DIR/adaptive-samples.png shows the adaptive
image beside its samples layer (log scale, black the fewest: docs/images/adaptive-samples.png
is one), OUT_DIR/uniform-samples.png the same of the uniform run, where edge anti-aliasing and
the bright edges put the samples (docs/images/edge-samples.png). Target: uniform / adaptive at
equal time >= 1.3;
MISSED when below (not an error).

With --bound SEEDS it also prints what any per-pixel allocation of camera samples could gain
on the scene (about SEEDS x 110 s more): SEEDS jobs like the uniform run but for their
seeds (1..SEEDS) give each measured pixel's variance v across jobs, and with its samples n
(the samples layer) a sample's variance v n. Drawing the same total in proportion to the
square root of that (the allocation that minimises the summed variance) would leave the
noise ((sum sqrt(v n))^2 / sum n) / (pixels); the ratio of the uniform noise to that, the
allocation's gain at equal samples (printed as RMSE, its square root), is an upper bound for
camera samples as costly as uniform's and whose variance falls as 1 / n (it does not where a
round's photon maps make the noise, which no camera sample of the round averages out). It is
printed twice: "known", the gain with every job's variance (an overestimate: the variances'
own noise looks like variation the allocation could exploit), and "estimated", the
allocation taken from half the jobs (smoothed over 3x3 pixels as the allocator does) judged
by the other half, both ways. The farm's bias against the reference (the jobs' mean less it,
less both's noise) is no sampling's to reduce: the RMSE ratio is at most sqrt((noise +
bias^2) / (noise / gain + bias^2))."""

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.dont_write_bytecode = True  # nothing written beside the scripts
HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import converge  # noqa: E402  (sets Mitsuba's variant)
import models  # noqa: E402
from run import preview  # noqa: E402

TARGET = 1.3


def adaptive_scene(path):
    """path's scene with sampling.adaptive ON, written beside it as <stem>.json in a folder
    of its own (farm render names its output after the file)."""
    scene = json.loads(path.read_text())
    scene["sampling"] = dict(scene.get("sampling", {}), adaptive="ADAPTIVE_SAMPLING_ON")
    out = path.parent / "adaptive" / path.name
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(scene, indent=1))
    return out


def samples_layer(exr):
    """The samples.Y channel of the farm's EXR (H x W)."""
    layers = dict(converge.mi.Bitmap(str(exr)).split())
    a = np.array(layers["samples"], dtype=np.float64)
    return a if a.ndim == 2 else a[..., 0]


def log_grey(samples):
    """A samples layer as an 8-bit grey RGB image on a log scale, black its fewest."""
    shade = np.log(samples / samples.min()) / max(np.log(samples.max() / samples.min()), 1e-12)
    return (np.repeat(shade[..., None], 3, axis=2) * 255 + 0.5).astype(np.uint8)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build", type=Path)
    ap.add_argument("out", type=Path)
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--rounds", type=int, default=16)
    ap.add_argument("--reference-spp", type=int, default=16384)
    ap.add_argument("--bound", type=int, default=0, metavar="SEEDS",
                    help="also print the gain bound of any per-pixel allocation, from SEEDS uniform jobs")
    args = ap.parse_args()
    build, out = args.build.resolve(), args.out.resolve()
    src = HERE.parent.parent / "scenes" / "cornell-caustics.json"
    base = converge.sized_scene(src, out / "reference", args.size, 1)
    (h1, h2), cached = converge.reference(build / "bench-cache", base, out / "mitsuba", args.reference_spp)
    _, measured = converge.region_masks(base, out / "mitsuba")
    before = converge.rmse(h1, h2, measured) / 2
    # The farm's error came to fall below the reference's noise, which sits in a few pixels
    # (the spheres' images of the light) where the farm's does (converge.refine_reference).
    (h1, h2), windows = converge.refine_reference(build / "bench-cache", base, out / "mitsuba", (h1, h2),
                                                  args.reference_spp, within=measured)
    ref = (h1 + h2) / 2
    noise = converge.rmse(h1, h2, measured) / 2
    print(f"cornell-caustics {args.size}x{args.size}, {args.rounds} rounds a run; reference {args.reference_spp} spp "
          f"({'cached' if cached else 'made now'}), its own noise RMSE {before:.5f}, {noise:.5f} with its noisiest "
          f"pixels at {converge.REFINE_FACTOR} times the samples ({len(windows)} windows)")

    uniform_path = converge.sized_scene(src, out / "uniform", args.size, args.rounds)
    adaptive_path = adaptive_scene(uniform_path)
    runs = {}
    for name, path in (("uniform", uniform_path), ("adaptive", adaptive_path)):
        img, seconds = converge.render_farm(build, path, path.parent)
        runs[name] = (img, seconds, converge.error(img, ref, measured, noise))
        print(f"  {name:8s} {seconds:6.1f} s: RMSE {runs[name][2]:.5f} ({converge.rmse(img, ref, measured):.5f} measured)")

    layers = {name: samples_layer(path.parent / (path.stem + ".exr"))
              for name, path in (("uniform", uniform_path), ("adaptive", adaptive_path))}
    for name, layer in layers.items():
        models.write_png(out / f"{name}-samples.png", np.concatenate([preview(runs[name][0]), log_grey(layer)], axis=1))
    samples = layers["adaptive"]
    err = np.where(measured, np.abs(runs["uniform"][0] - ref).mean(axis=2), -1).ravel()
    top = np.argsort(-err, kind="stable")[: max(1, int(measured.sum()) // 10)]
    print(f"  adaptive samples (layer samples.Y): {samples.min():.0f} to {samples.max():.0f} a pixel, mean "
          f"{samples.mean():.2f}; the 10% of pixels with the largest uniform-run error drew "
          f"{100 * samples.ravel()[top].sum() / samples.sum():.1f}% of them")

    if args.bound:
        allocation_bound(build, src, out / "bound", args, (h1, h2), measured)

    (u_img, u_s, u_e), (a_img, a_s, a_e) = runs["uniform"], runs["adaptive"]
    raw = u_e / max(a_e, 1e-12)
    equal_time = u_e / max(a_e * np.sqrt(a_s / u_s), 1e-12)
    verdict = "" if equal_time >= TARGET else "  MISSED"
    print(f"  uniform / adaptive RMSE: {raw:.2f} as measured, {equal_time:.2f} at equal time "
          f"(times {u_s:.1f} s / {a_s:.1f} s; target >= {TARGET}){verdict}")


def smoothed(a):
    """a's mean over each pixel's 3x3 neighbourhood (edge pixels repeated)."""
    return np.lib.stride_tricks.sliding_window_view(np.pad(a, 1, mode="edge"), (3, 3)).mean(axis=(2, 3))


def noise_gain(sample_variance, pixel_variance, samples, mask):
    """Uniform noise / the noise left when the same samples are drawn in proportion to the
    square root of sample_variance, the pixels' variance being pixel_variance at samples."""
    share = np.sqrt(np.maximum(sample_variance, 0.0))[mask]
    allocated = share / max(share.sum(), 1e-300) * samples[mask].sum()
    left = pixel_variance[mask] * samples[mask] / np.maximum(allocated, 1e-300)
    return pixel_variance[mask].mean() / left.mean()


def allocation_bound(build, src, out, args, halves, measured):
    """Print the most any per-pixel allocation of camera samples could gain (--bound)."""
    images, samples = [], []
    for seed in range(1, args.bound + 1):
        path = converge.sized_scene(src, out / f"seed-{seed}", args.size, args.rounds)
        scene = json.loads(path.read_text())
        scene["sampling"] = dict(scene.get("sampling", {}), seed=str(seed))
        path.write_text(json.dumps(scene, indent=1))
        images.append(converge.render_farm(build, path, path.parent)[0])
        samples.append(samples_layer(path.parent / (path.stem + ".exr")))
    images, n = np.array(images), np.mean(samples, axis=0)
    variance = lambda imgs: imgs.var(axis=0, ddof=1).mean(axis=2)  # noqa: E731
    v = variance(images)
    known = noise_gain(v * n, v, n, measured)
    a, b = variance(images[0::2]), variance(images[1::2])
    estimated = 2 / (1 / noise_gain(smoothed(a) * n, b, n, measured) + 1 / noise_gain(smoothed(b) * n, a, n, measured))
    ref_noise = ((halves[0] - halves[1]) ** 2 / 4).mean(axis=2)
    ref = (halves[0] + halves[1]) / 2
    bias2 = float(np.mean((((images.mean(axis=0) - ref) ** 2).mean(axis=2) - v / len(images) - ref_noise)[measured]))
    noise = float(v[measured].mean())
    ratio = lambda gain: np.sqrt((noise + max(bias2, 0)) / (noise / gain + max(bias2, 0)))  # noqa: E731
    print(f"  what any per-pixel allocation of camera samples could gain ({args.bound} uniform jobs "
          f"of {args.rounds} rounds): noise RMSE at equal samples {np.sqrt(known):.2f} times lower with the pixels' variance known, "
          f"{np.sqrt(estimated):.2f} with it estimated from half the jobs; with the farm's bias (RMSE "
          f"{np.sqrt(max(bias2, 0)):.5f}), uniform / adaptive RMSE is at most "
          f"{ratio(known):.2f} known, {ratio(estimated):.2f} estimated (target {TARGET})")

if __name__ == "__main__":
    main()
