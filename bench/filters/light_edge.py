"""Issue 14's acceptance 6, its figure: the Cornell box light's edge with the box, the
Gaussian and the Mitchell pixel filter at equal samples, each against a Mitsuba 3
reference rendered with the matching filter.

    bench/filters/light_edge.py BUILD_DIR OUT_DIR [--mitsuba-spp N]

scenes/cornell-box.json is rendered by `farm render` on a local two-worker farm three
times, with the scene's sampling (1 camera sample a pixel, edge_samples on edge pixels, one round):
as it is (the box of radius 1/2, the default), with film.filter the Gaussian of radius 2
and sigma 1/2, and with Mitchell's of radius 2 (B = C = 1/3). Mitsuba (variant scalar_rgb,
path tracer, stratified sampler) renders the same scene, as bench/crosscheck/to_mitsuba.py
translates it (the light reflects as the farm's), in a window about the light with rfilter
`box`, `gaussian` (stddev 0.5, whose radius is Mitsuba's 4 stddev = 2: the farm's profile
exactly) and `mitchell` (B = C = 1/3, radius 2), each in two halves of different seeds.
Over the pixels whose centre lies within 2.5 pixels of the light's outline (its corners
projected by the scene's camera) it prints each filter's RMSE of the linear R, G, B
against its reference, the reference's own noise (the RMSE of its halves against each
other over 2: the error of their mean), the farm's RMSE over the window's pixels more
than 3 px from the outline (out of every filter's reach of the edge: the noise floor),
and the ratios box / Gaussian and box / Mitchell, each marked PASS at 2 or more and
MISSED below (never a failing exit: the figure is what is asked for). OUT_DIR keeps the EXRs and the references as .npy."""

import argparse
import copy
import json
import math
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.dont_write_bytecode = True  # nothing written beside the scripts
import mitsuba as mi  # noqa: E402

mi.set_variant("scalar_rgb")

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "crosscheck"))
import to_mitsuba  # noqa: E402  (the scene for Mitsuba, vec)
from run import read_rgb  # noqa: E402  (the farm EXR's beauty)

ROOT = Path(__file__).resolve().parent.parent.parent
SCENE = ROOT / "scenes" / "cornell-box.json"
BAND = 2.5  # pixels from the light's outline
MARGIN = 6  # pixels of the Mitsuba window beyond the light's outline
GAUSSIAN = {"gaussian": {"radius": 2, "sigma": 0.5}}
# Mitsuba's mitchell is B = C = 1/3 over radius 2, the farm's default.
MITCHELL = {"mitchell": {"radius": 2}}
FILTERS = (("box", None, {"type": "box"}), ("gaussian", GAUSSIAN, {"type": "gaussian", "stddev": 0.5}),
           ("mitchell", MITCHELL, {"type": "mitchell", "B": 1 / 3, "C": 1 / 3}))
TARGET = 2.0


def project(cam, film, p):
    """Image coordinates (pixels, y down) of world point p through the scene's pinhole:
    the image's right is cross(forward, up) (scene.proto), film x = (1 + right / (depth
    tan(fov / 2) aspect)) width / 2 (worker/scene/camera.cpp)."""
    pos, look, up = (np.array(to_mitsuba.vec(cam[k], "x", "y", "z")) for k in ("position", "lookAt", "up"))
    fwd = (look - pos) / np.linalg.norm(look - pos)
    right = np.cross(fwd, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, fwd)
    d = np.asarray(p) - pos
    t = math.tan(math.radians(cam["verticalFovDegrees"]) / 2)
    w, h = film["width"], film["height"]
    sx = d @ right / (d @ fwd * t * w / h)
    sy = d @ true_up / (d @ fwd * t)
    return np.array([(sx + 1) * w / 2, (1 - sy) * h / 2])


def light_outline(scene):
    """The light quad's corners in image coordinates, in order round the quad."""
    q = next(s["quad"] for s in scene["shapes"] if "quad" in s)
    o, u, v = (np.array(to_mitsuba.vec(q[k], "x", "y", "z")) for k in ("origin", "edgeU", "edgeV"))
    return [project(scene["camera"], scene["film"], c) for c in (o, o + u, o + u + v, o + v)]


def outline_distance(corners, x0, y0, w, h):
    """Each pixel's (rows, cols of the window at x0, y0) centre's distance to the outline."""
    ys, xs = np.mgrid[y0:y0 + h, x0:x0 + w] + 0.5
    dist = np.full(xs.shape, np.inf)
    for a, b in zip(corners, corners[1:] + corners[:1]):
        ab = b - a
        t = np.clip(((xs - a[0]) * ab[0] + (ys - a[1]) * ab[1]) / (ab @ ab), 0, 1)
        dist = np.minimum(dist, np.hypot(xs - a[0] - t * ab[0], ys - a[1] - t * ab[1]))
    return dist


def mitsuba_scene(work, rfilter, window, spp, seed):
    """The Cornell box as to_mitsuba translates it (the light's reflectance included),
    rendering `window` with a stratified sampler and `rfilter`."""
    d, _ = to_mitsuba.mitsuba_scene(mi, SCENE, work, spp, seed)
    x0, y0, w, h = window
    d["sensor"]["sampler"] = {"type": "stratified", "sample_count": spp, "seed": seed}
    d["sensor"]["film"].update({"crop_offset_x": x0, "crop_offset_y": y0, "crop_width": w, "crop_height": h,
                                "sample_border": True, "rfilter": rfilter})
    return d


def rmse(a, b, mask):
    return float(np.sqrt(np.mean((a - b)[mask] ** 2)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build", type=Path)
    ap.add_argument("out", type=Path)
    ap.add_argument("--mitsuba-spp", type=int, default=2048, help="Mitsuba samples per pixel (two halves)")
    args = ap.parse_args()
    build, out = args.build.resolve(), args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    scene = json.loads(SCENE.read_text())
    corners = light_outline(scene)
    xs, ys = [c[0] for c in corners], [c[1] for c in corners]
    x0, y0 = int(math.floor(min(xs))) - MARGIN, int(math.floor(min(ys))) - MARGIN
    window = (x0, y0, int(math.ceil(max(xs))) + MARGIN - x0, int(math.ceil(max(ys))) + MARGIN - y0)
    dist = outline_distance(corners, *window)
    band = dist <= BAND
    # Beyond every filter's reach of the edge (radius 2 about a pixel's centre, and the
    # pixel's own half width): what is left there is each render's noise.
    away = dist > 3
    print(f"light outline at x {min(xs):.1f}..{max(xs):.1f}, y {min(ys):.1f}..{max(ys):.1f}; "
          f"{int(band.sum())} pixels within {BAND} px of it; farm: {scene['film']['width']}x{scene['film']['height']}, "
          f"scene sampling (1 sample a pixel, edge anti-aliasing), two workers; Mitsuba: {args.mitsuba_spp} spp")
    errors = {}
    for name, farm_filter, rfilter in FILTERS:
        variant = copy.deepcopy(scene)
        if farm_filter:
            variant["film"]["filter"] = farm_filter
        path = out / f"cornell-{name}.json"
        path.write_text(json.dumps(variant, indent=1))
        start = time.time()
        # --name: farm render names its files after the scene's name field, the same for
        # every variant.
        subprocess.run([str(build / "bin" / "farm"), "render", str(path), "-o", str(out), "--name", f"cornell-{name}",
                        "--workers", "2", "--no-dashboard"], check=True, stdout=subprocess.DEVNULL)
        farm_seconds = time.time() - start
        farm = read_rgb(out / f"cornell-{name}.exr")[y0:y0 + window[3], x0:x0 + window[2]]
        start = time.time()
        halves = [np.array(mi.render(mi.load_dict(mitsuba_scene(out, rfilter, window, args.mitsuba_spp // 2, seed))),
                           dtype=np.float64)[..., :3] for seed in (1, 2)]
        mitsuba_seconds = time.time() - start
        ref = (halves[0] + halves[1]) / 2
        np.save(out / f"reference-{name}.npy", ref)
        errors[name] = rmse(farm, ref, band)
        print(f"{name:9s} farm RMSE {errors[name]:.4f} against Mitsuba with rfilter {rfilter['type']} "
              f"(its own noise {rmse(halves[0], halves[1], band) / 2:.4f}); "
              f"mean over the band farm {farm[band].mean():.4f} / Mitsuba {ref[band].mean():.4f}; "
              f"farm {farm_seconds:.0f} s, Mitsuba {mitsuba_seconds:.0f} s; "
              f"away from the edge ({int(away.sum())} pixels over 3 px from it) farm RMSE {rmse(farm, ref, away):.4f}")
    for name in ("gaussian", "mitchell"):
        ratio = errors["box"] / errors[name]
        verdict = "PASS" if ratio >= TARGET else "MISSED"
        print(f"light edge RMSE box / {name} at equal samples: {ratio:.2f} (target at least {TARGET:.0f}): {verdict}")


if __name__ == "__main__":
    main()
