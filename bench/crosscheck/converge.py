"""Issue 14's acceptance 1: the farm against a long Mitsuba 3 reference on our own Cornell
scenes, region by region, round by round and at equal wall time.

    bench/crosscheck/converge.py BUILD_DIR OUT_DIR [--size N] [--reference-spp N] [--only NAME]
                                 [--rounds A,B] [--seconds 3,10,60]

For scenes/cornell-box.json and scenes/cornell-caustics.json, each at SIZE x SIZE:

  reference   Mitsuba's path tracer (to_mitsuba.py; scalar_rgb, box pixel filter like the
              farm's) at REFERENCE_SPP samples per pixel in two halves of different seeds,
              cached in BUILD_DIR/bench-cache/ under a digest of the scene file, the
              translation and the settings (a reference is minutes; it is made once)
  regions     from the geometry, through one Mitsuba pass of AOVs (the shape and the
              point each pixel's centre sees): floor, ceiling, walls (back, left, right),
              objects (every other shape but the light), and corners: pixels whose point
              lies within 1/40 of the scene's diagonal of another face (the room's edges
              and corners, and where the objects meet the floor or each other). Pixels
              that see the light, or touch one that does, are in no region and left out of
              every RMSE: the light's jagged edge is the pixel filter's, not the estimate's
  rounds      the farm (`farm render`, two workers) after A and after B progressive rounds
              (default 9 and 50): RMSE against the reference, the ratio of the two, and the
              relative difference of the mean radiance in each region, per channel
  equal time  the farm and Mitsuba at about 3, 10 and 60 s of wall time (the farm's whole
              `farm render` command; Mitsuba's render call): the farm runs the number of
              rounds whose wall time its A- and B-round runs put nearest the budget (wall =
              start-up + rounds x round time), Mitsuba the samples that fit in the wall
              time the farm actually took (its cost per sample calibrated on this machine
              just before); both print the time they took

The reference's own noise (the RMSE of its two halves' difference, halved: that of their
mean) is printed beside it, and every RMSE is printed less that noise (the reference's
noise is independent of the image, so it adds its variance to the mean square), then as
measured in brackets."""

import argparse
import hashlib
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.dont_write_bytecode = True  # nothing written beside the scripts
import mitsuba as mi  # noqa: E402

mi.set_variant("scalar_rgb")

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import to_mitsuba  # noqa: E402
from run import preview, read_rgb  # noqa: E402
import models  # noqa: E402

SCENES = ("cornell-box", "cornell-caustics")
REGIONS = ("walls", "floor", "ceiling", "objects", "corners")


def sized_scene(src, out_dir, size, rounds):
    """The scene file at src with a SIZE x SIZE film and `rounds` progressive rounds, written
    into out_dir under the same file name (farm render names its output after the scene's name
    field, which for the project's scenes is the file's name)."""
    scene = json.loads(Path(src).read_text())
    scene["film"] = dict(scene.get("film", {}), width=size, height=size)
    scene["progressive"] = dict(scene.get("progressive", {}), maxRounds=rounds)
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / Path(src).name
    path.write_text(json.dumps(scene, indent=1))
    return path


def render_farm(build, scene_path, out_dir):
    """The farm's image of scene_path and the wall time of the whole `farm render`."""
    t0 = time.monotonic()
    subprocess.run([str(build / "bin" / "farm"), "render", str(scene_path), "-o", str(out_dir), "--workers", "2",
                    "--no-dashboard"], check=True, stdout=subprocess.DEVNULL)
    seconds = time.monotonic() - t0
    return read_rgb(out_dir / (scene_path.stem + ".exr")), seconds


def render_mitsuba(scene_path, work_dir, spp, seed):
    """Mitsuba's image at spp samples per pixel and the seconds of its render call."""
    d, _ = to_mitsuba.mitsuba_scene(mi, scene_path, work_dir, spp, seed=seed)
    scene = mi.load_dict(d)
    t0 = time.monotonic()
    img = np.array(mi.render(scene), dtype=np.float64)
    return img, time.monotonic() - t0


def cache_key(scene_path, settings, extra=b""):
    """A cache entry's key: a digest of the scene file, the translation, Mitsuba's version
    and the settings (a string) it was made with, and of extra bytes."""
    return hashlib.sha256(scene_path.read_bytes() + (HERE / "to_mitsuba.py").read_bytes() +
                          f"{settings} {mi.__version__}".encode() + extra).hexdigest()[:16]


def reference(cache, scene_path, work_dir, spp):
    """The two halves of the reference, from the cache when the scene, the translation and
    spp are those it was made with."""
    key = cache_key(scene_path, spp)
    paths = [cache / f"{scene_path.stem}-{key}-{half}.exr" for half in (1, 2)]
    meta = cache / f"{scene_path.stem}-{key}.json"
    if all(p.exists() for p in paths) and meta.exists():
        halves = [np.array(mi.Bitmap(str(p)), dtype=np.float64)[..., :3] for p in paths]
        return halves, True
    cache.mkdir(parents=True, exist_ok=True)
    halves, seconds = [], 0.0
    for half, path in zip((1, 2), paths):
        img, s = render_mitsuba(scene_path, work_dir, spp // 2, seed=100 + half)
        halves.append(img)
        seconds += s
        mi.Bitmap(img.astype(np.float32)).write(str(path))
    meta.write_text(json.dumps({"spp": spp, "seconds": seconds}))
    return halves, False


# refine_reference: the reference's noisiest pixels, those holding REFINE_SHARE of its
# noise (at most REFINE_MOST), are rendered again at REFINE_FACTOR times the samples.
REFINE_SHARE, REFINE_MOST, REFINE_FACTOR = 0.95, 128, 32


def clusters(mask):
    """Bounding boxes (x0, y0, width, height) of mask's groups of pixels, pixels within two
    of each other grouped."""
    h, w = mask.shape
    seen = np.zeros_like(mask)
    boxes = []
    for y, x in zip(*np.nonzero(mask)):
        if seen[y, x]:
            continue
        seen[y, x] = True
        stack, members = [(y, x)], []
        while stack:
            cy, cx = stack.pop()
            members.append((cy, cx))
            for ny in range(max(0, cy - 2), min(h, cy + 3)):
                for nx in range(max(0, cx - 2), min(w, cx + 3)):
                    if mask[ny, nx] and not seen[ny, nx]:
                        seen[ny, nx] = True
                        stack.append((ny, nx))
        ys, xs = zip(*members)
        boxes.append((int(min(xs)), int(min(ys)), int(max(xs) - min(xs) + 1), int(max(ys) - min(ys) + 1)))
    return boxes


def refine_reference(cache, scene_path, work_dir, halves, spp, within=None):
    """The reference's halves with the pixels that hold most of its own noise rendered again
    at REFINE_FACTOR times spp (in windows about them, two halves of other seeds), cached
    beside the reference, and the windows. A reference's noise sits in a few pixels (a
    light's rim, its image in a mirror: 90% of a 64x64 Cornell box's in 11 pixels), the same
    pixels where a farm image's error sits; once that error falls to the reference's noise,
    subtracting the noise (it is independent of the image) no longer measures it: the two
    meet in so few pixels that their cross term does not average out. within, a mask,
    limits the choice to the pixels an error is measured over."""
    h1, h2 = halves
    noise = (((h1 - h2) / 2) ** 2).mean(axis=2)
    if within is not None:
        noise = np.where(within, noise, 0.0)
    order = np.argsort(noise.ravel())[::-1]
    held = np.cumsum(noise.ravel()[order]) / max(noise.sum(), 1e-300)
    count = min(REFINE_MOST, int(np.searchsorted(held, REFINE_SHARE)) + 1)
    chosen = np.zeros(noise.shape, dtype=bool)
    chosen.ravel()[order[:count]] = True
    windows = clusters(chosen)
    key = cache_key(scene_path, f"{spp} refined {REFINE_SHARE} {REFINE_MOST} {REFINE_FACTOR}",
                    b"" if within is None else np.packbits(within).tobytes())
    paths = [cache / f"{scene_path.stem}-{key}-refined-{half}.exr" for half in (1, 2)]
    if all(p.exists() for p in paths):
        return [np.array(mi.Bitmap(str(p)), dtype=np.float64)[..., :3] for p in paths], windows
    refined = [h1.copy(), h2.copy()]
    for x0, y0, w, h in windows:
        for half, img in zip((1, 2), refined):
            d, _ = to_mitsuba.mitsuba_scene(mi, scene_path, work_dir, spp * REFINE_FACTOR // 2, seed=200 + half)
            d["sensor"]["film"].update({"crop_offset_x": int(x0), "crop_offset_y": int(y0),
                                        "crop_width": int(w), "crop_height": int(h)})
            img[y0:y0 + h, x0:x0 + w] = np.array(mi.render(mi.load_dict(d)), dtype=np.float64)[..., :3]
    for img, path in zip(refined, paths):
        mi.Bitmap(img.astype(np.float32)).write(str(path))
    return refined, windows


def point_triangle_distance(p, a, b, c):
    """Distance from each point of p (N x 3) to the triangle abc."""
    ab, ac, n = b - a, c - a, np.cross(b - a, c - a)
    n = n / np.linalg.norm(n)
    d_plane = (p - a) @ n
    q = p - np.outer(d_plane, n)  # projection onto the plane
    # Barycentric coordinates of the projection; inside the triangle, the plane distance.
    v0, v1, v2 = ab, ac, q - a
    d00, d01, d11 = v0 @ v0, v0 @ v1, v1 @ v1
    d20, d21 = v2 @ v0, v2 @ v1
    den = d00 * d11 - d01 * d01
    v = (d11 * d20 - d01 * d21) / den
    w = (d00 * d21 - d01 * d20) / den
    inside = (v >= 0) & (w >= 0) & (v + w <= 1)

    def segment(x, y):
        t = np.clip(((p - x) @ (y - x)) / ((y - x) @ (y - x)), 0, 1)
        return np.linalg.norm(p - (x + np.outer(t, y - x)), axis=1)

    edges = np.minimum(np.minimum(segment(a, b), segment(b, c)), segment(c, a))
    return np.where(inside, np.abs(d_plane), edges)


def faces_of(scene):
    """Each flat face (a shape's triangles that share a plane) or sphere of a farm scene, as
    (shape index, distance function of N x 3 points)."""
    faces = []
    for i, shape in enumerate(scene["shapes"]):
        if "sphere" in shape:
            c = np.array(to_mitsuba.vec(shape["sphere"]["center"], "x", "y", "z"))
            r = float(shape["sphere"]["radius"])
            faces.append((i, lambda p, c=c, r=r: np.abs(np.linalg.norm(p - c, axis=1) - r)))
            continue
        if "quad" in shape:
            q = shape["quad"]
            o, u, v = (np.array(to_mitsuba.vec(q[k], "x", "y", "z")) for k in ("origin", "edgeU", "edgeV"))
            tris = [(o, o + u, o + u + v), (o, o + u + v, o + v)]
        else:
            t = shape["triangles"]
            pos = np.array([to_mitsuba.vec(p, "x", "y", "z") for p in t["positions"]])
            idx = np.array(t["indices"]).reshape(-1, 3)
            tris = [tuple(pos[k]) for k in idx]
        # Triangles of a shape facing within 8 degrees of each other are one face (the
        # Cornell box's left wall is not quite planar: its crease is no edge).
        groups = []
        for a, b, c in tris:
            n = np.cross(b - a, c - a)
            n /= np.linalg.norm(n)
            group = next((g for g in groups if g[0] @ n > 0.99), None)
            if group is None:
                groups.append(group := (n, []))
            group[1].append((a, b, c))
        for _, group in groups:
            faces.append((i, lambda p, g=group: np.min([point_triangle_distance(p, *t) for t in g], axis=0)))
    return faces


def region_masks(scene_path, work_dir):
    """Boolean masks of REGIONS and of the pixels every measure leaves out (the light and its
    neighbours, and pixels that see nothing), from the geometry (see the top)."""
    scene = json.loads(scene_path.read_text())
    d, _ = to_mitsuba.mitsuba_scene(mi, scene_path, work_dir, 1)
    keys = [f"shape{i}" for i in range(len(scene["shapes"]))]
    for i, key in enumerate(keys):  # each shape a diffuse reflectance that numbers it
        d[key]["bsdf"] = {"type": "diffuse", "reflectance": {"type": "rgb", "value": (i + 1) / len(keys) / 2}}
        d[key].pop("emitter", None)
    d["integrator"] = {"type": "aov", "aovs": "alb:albedo,pos:position"}
    d["sensor"]["sampler"] = {"type": "stratified", "sample_count": 1, "jitter": False}
    aov = np.array(mi.render(mi.load_dict(d)), dtype=np.float64)
    shape = np.rint(aov[..., 0] * len(keys) * 2).astype(int) - 1  # -1: nothing
    pos = aov[..., 3:6]
    names = [s.get("name", "") for s in scene["shapes"]]
    emits = {m["name"] for m in scene["materials"] if "emissive" in m}
    light = np.isin(shape, [i for i, s in enumerate(scene["shapes"]) if s.get("material") in emits])
    padded = np.pad(light, 1)
    h, w = light.shape
    near_light = np.any([padded[1 + dy:1 + dy + h, 1 + dx:1 + dx + w] for dy in (-1, 0, 1) for dx in (-1, 0, 1)], axis=0)
    excluded = near_light | (shape < 0)
    lo = np.min([np.min(np.array([to_mitsuba.vec(p, "x", "y", "z") for p in s["triangles"]["positions"]]), 0)
                 for s in scene["shapes"] if "triangles" in s], 0)
    hi = np.max([np.max(np.array([to_mitsuba.vec(p, "x", "y", "z") for p in s["triangles"]["positions"]]), 0)
                 for s in scene["shapes"] if "triangles" in s], 0)
    band = np.linalg.norm(hi - lo) / 40
    flat = pos.reshape(-1, 3)
    dist = np.stack([f(flat) for _, f in faces_of(scene)])  # faces x pixels
    own = np.argmin(dist, axis=0)
    dist[own, np.arange(dist.shape[1])] = np.inf
    corner = (dist.min(axis=0) < band).reshape(shape.shape) & ~excluded
    by_name = {"floor": names.index("floor"), "ceiling": names.index("ceiling")}
    walls = [names.index(n) for n in ("back-wall", "left-wall", "right-wall")]
    masks = {
        "floor": (shape == by_name["floor"]),
        "ceiling": (shape == by_name["ceiling"]),
        "walls": np.isin(shape, walls),
    }
    masks["objects"] = (shape >= 0) & ~light & ~masks["floor"] & ~masks["ceiling"] & ~masks["walls"]
    masks = {k: m & ~excluded & ~corner for k, m in masks.items()}
    masks["corners"] = corner
    return masks, ~excluded


def rmse(a, b, mask):
    return float(np.sqrt(np.mean((a[mask] - b[mask]) ** 2)))


def error(img, ref, mask, ref_noise):
    """RMSE against the reference less the reference's own noise (independent of img, it adds
    its variance to the mean square): the image's own error."""
    return float(np.sqrt(max(0.0, rmse(img, ref, mask) ** 2 - ref_noise ** 2)))


def region_line(img, ref, masks):
    """Relative difference of the mean radiance per region: all channels, then R, G, B."""
    parts = []
    for name in REGIONS:
        m = masks[name]
        rel = img[m].mean(axis=0) / ref[m].mean(axis=0) - 1
        total = img[m].sum() / ref[m].sum() - 1
        parts.append(f"{name} {100 * total:+.2f}% (R {100 * rel[0]:+.1f} G {100 * rel[1]:+.1f} B {100 * rel[2]:+.1f})")
    return "; ".join(parts)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build", type=Path)
    ap.add_argument("out", type=Path)
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--reference-spp", type=int, default=16384)
    ap.add_argument("--rounds", default="9,50", help="the two round counts compared")
    ap.add_argument("--seconds", default="3,10,60", help="the equal-time budgets; empty for none")
    ap.add_argument("--only", choices=SCENES)
    args = ap.parse_args()
    build, out = args.build.resolve(), args.out.resolve()
    cache = build / "bench-cache"
    few, many = (int(x) for x in args.rounds.split(","))
    root = HERE.parent.parent
    for name in SCENES:
        if args.only and name != args.only:
            continue
        src = root / "scenes" / f"{name}.json"
        base = sized_scene(src, out / name, args.size, 1)
        t0 = time.monotonic()
        (h1, h2), cached = reference(cache, base, out / name / "mitsuba", args.reference_spp)
        ref = (h1 + h2) / 2
        masks, measured = region_masks(base, out / name / "mitsuba")
        noise = rmse(h1, h2, measured) / 2
        print(f"{name}: {args.size}x{args.size}; reference {args.reference_spp} spp "
              f"({'cached' if cached else f'made in {time.monotonic() - t0:.0f} s'}), its own noise "
              f"RMSE {noise:.5f}; pixels: " +
              ", ".join(f"{k} {int(m.sum())}" for k, m in masks.items()) + f", left out {int((~measured).sum())}")
        runs = {}
        for rounds in (few, many):
            path = sized_scene(src, out / name / f"rounds-{rounds}", args.size, rounds)
            img, seconds = render_farm(build, path, out / name / f"rounds-{rounds}")
            runs[rounds] = (img, seconds)
            print(f"  farm {rounds:3d} rounds in {seconds:6.1f} s: RMSE {error(img, ref, measured, noise):.5f} "
                  f"({rmse(img, ref, measured):.5f}); {region_line(img, ref, masks)}")
        e_few, e_many = (error(runs[r][0], ref, measured, noise) for r in (few, many))
        print(f"  RMSE after {few} / after {many} rounds: {e_few / e_many:.2f} (target >= 2)")
        worst = max(abs(runs[many][0][m].sum() / ref[m].sum() - 1) for m in masks.values())
        print(f"  worst region after {many} rounds: {100 * worst:.2f}% (target <= 0.5%)")
        diff = np.abs(runs[many][0] - ref) * 8
        models.write_png(out / f"{name}-converge.png",
                         np.concatenate([preview(runs[many][0]), preview(ref), preview(diff)], axis=1))
        timings = {r: runs[r][1] for r in (few, many)}
        mitsuba_cost = calibrate_mitsuba(base, out / name / "mitsuba")
        for budget in sorted(float(s) for s in args.seconds.split(",") if s):
            rounds = rounds_for(budget, timings)
            path = sized_scene(src, out / name / f"time-{budget:g}", args.size, rounds)
            img, seconds = render_farm(build, path, out / name / f"time-{budget:g}")
            timings[rounds] = seconds
            # Mitsuba gets the wall time the farm took, whatever the budget said.
            mimg, mseconds, spp = render_mitsuba_for(path, out / name / "mitsuba", seconds, mitsuba_cost)
            e_farm, e_mitsuba = error(img, ref, measured, noise), error(mimg, ref, measured, noise)
            print(f"  ~{budget:g} s: farm {rounds} rounds in {seconds:.1f} s RMSE {e_farm:.5f} "
                  f"({rmse(img, ref, measured):.5f}); Mitsuba {spp} spp in {mseconds:.1f} s RMSE {e_mitsuba:.5f} "
                  f"({rmse(mimg, ref, measured):.5f}); farm / Mitsuba {e_farm / max(e_mitsuba, 1e-12):.2f}")


def rounds_for(budget, timings):
    """The rounds whose wall time is nearest `budget` seconds, by linear interpolation
    between the {rounds: seconds} the farm has taken so far (beyond them, the nearest two's
    line): a round is the farm's step. A line through the 9- and 50-round runs alone puts
    the start-up too high (later rounds are cheaper), and flooring it ran the ~10 s row in
    6 s."""
    points = sorted(timings.items())
    segments = list(zip(points, points[1:]))
    (r0, t0), (r1, t1) = next((seg for seg in segments if budget <= seg[1][1]), segments[-1])
    return max(1, round(r0 + (budget - t0) * (r1 - r0) / max(t1 - t0, 1e-9)))


def calibrate_mitsuba(scene_path, work_dir):
    """Mitsuba's render call on this machine now, as (fixed seconds, seconds per sample per
    pixel), from two short renders; the reference's rate was measured when it was made, on a
    machine that may have been busier or quieter."""
    (t1, t2), (n1, n2) = [render_mitsuba(scene_path, work_dir, n, seed=3)[1] for n in (16, 128)], (16, 128)
    per_spp = max((t2 - t1) / (n2 - n1), 1e-9)
    return max(0.0, t1 - n1 * per_spp), per_spp


def render_mitsuba_for(scene_path, work_dir, seconds, cost):
    """Mitsuba's image after about `seconds` of its render call: the samples the calibration
    says fit, corrected once by the time the first try took when it is more than 10% off."""
    fixed, per_spp = cost
    spp = max(1, int((seconds - fixed) / per_spp))
    img, took = render_mitsuba(scene_path, work_dir, spp, seed=7)
    if abs(took - seconds) > 0.1 * seconds:
        spp = max(1, int(spp * (seconds - fixed) / max(took - fixed, 1e-3)))
        img, took = render_mitsuba(scene_path, work_dir, spp, seed=7)
    return img, took, spp

if __name__ == "__main__":
    main()
