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
MISSED when below (not an error)."""

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

    (u_img, u_s, u_e), (a_img, a_s, a_e) = runs["uniform"], runs["adaptive"]
    raw = u_e / max(a_e, 1e-12)
    equal_time = u_e / max(a_e * np.sqrt(a_s / u_s), 1e-12)
    verdict = "" if equal_time >= TARGET else "  MISSED"
    print(f"  uniform / adaptive RMSE: {raw:.2f} as measured, {equal_time:.2f} at equal time "
          f"(times {u_s:.1f} s / {a_s:.1f} s; target >= {TARGET}){verdict}")


if __name__ == "__main__":
    main()
