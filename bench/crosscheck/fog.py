"""Issue 15's acceptance 3: the fog Cornell box against Mitsuba 3's volumetric path tracer.

    bench/crosscheck/fog.py BUILD_DIR OUT_DIR [--size N] [--reference-spp N] [--rounds A,B]

scenes/cornell-fog.json (the Cornell box in a homogeneous medium of albedo 0.85, density
0.001 a unit and g 0.2 that fills the ball about its shapes: docs/media.md) at SIZE x SIZE:

  farm       `farm render` on two workers after A and after B progressive rounds (default
             2 and 8; converge.py's sized_scene and render_farm): a bias stays as the
             rounds grow, the farm's own noise shrinks
  reference  Mitsuba's `volpath` (to_mitsuba.py: the medium inside a null sphere that is the
             farm's ball, vacuum outside) at REFERENCE_SPP samples a pixel in two halves,
             cached in BUILD_DIR/bench-cache like converge.py's references (the same code)

For each farm image it prints

    relMSE = mean over pixels p and channels c of (farm - mitsuba)^2 / (mitsuba^2 + 0.01)

(run.py's measure) over every pixel, PASS at most 0.01 and MISSED above (a figure, not an
error: the exit status is 0 either way), then the same over the pixels converge.py
measures (the light and its neighbours left out: their jagged edge is the pixel filter's),
each channel's mean ratio farm / Mitsuba, and per region the relMSE and the relative
difference of the mean radiance (converge.py's regions, from the geometry without the
medium, and `fog`: pixels whose camera ray meets no surface, the farm's alpha 0, which see
nothing but the lit fog). Mitsuba's own noise is printed in the same measure (its halves'
relMSE over 4: that of their mean). OUT_DIR/cornell-fog-compare.png: farm after B rounds |
Mitsuba | |difference| x 4, tone-mapped alike."""

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.dont_write_bytecode = True  # nothing written beside the scripts
HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import converge  # noqa: E402  (sets Mitsuba's variant)
import models  # noqa: E402
from run import preview, rel_mse  # noqa: E402

NAME = "cornell-fog"
TARGET = 0.01


def without_media(path, out_dir):
    """The scene at path without its media, written into out_dir: what the region masks are
    found on (Mitsuba's AOVs stop at the ball's null surface, which is no region)."""
    scene = json.loads(path.read_text())
    scene.pop("medium", None)
    for shape in scene["shapes"]:
        shape.pop("interiorMedium", None)
    out_dir.mkdir(parents=True, exist_ok=True)
    out = out_dir / path.name
    out.write_text(json.dumps(scene, indent=1))
    return out


def alpha_of(exr):
    """The alpha of the farm's EXR (H x W): 0 where the camera ray met nothing."""
    for name, layer in converge.mi.Bitmap(str(exr)).split():
        if name == "<root>":
            return np.array(layer, dtype=np.float64)[..., 3]
    raise ValueError(f"{exr}: no root layer")


def figures(img, ref, masks, measured):
    """The lines printed for one farm image against the reference."""
    err = rel_mse(img, ref)
    ratio = img.reshape(-1, 3).mean(axis=0) / ref.reshape(-1, 3).mean(axis=0)
    lines = [f"relMSE {err:.4f} ({'PASS' if err <= TARGET else 'MISSED'} at <= {TARGET}); "
             f"without the light and its neighbours {rel_mse(img[measured], ref[measured]):.4f}; "
             f"mean farm/Mitsuba R {ratio[0]:.3f} G {ratio[1]:.3f} B {ratio[2]:.3f}"]
    for name, m in masks.items():
        if m.any():
            rel = img[m].mean(axis=0) / ref[m].mean(axis=0) - 1
            lines.append(f"  {name:8s} {int(m.sum()):5d} pixels: relMSE {rel_mse(img[m], ref[m]):.4f}, mean "
                         f"{100 * (img[m].sum() / ref[m].sum() - 1):+.1f}% (R {100 * rel[0]:+.1f} G {100 * rel[1]:+.1f} "
                         f"B {100 * rel[2]:+.1f})")
    return err, lines


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build", type=Path)
    ap.add_argument("out", type=Path)
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--reference-spp", type=int, default=4096)
    ap.add_argument("--rounds", default="2,8", help="the two round counts of the farm, the verdict on the second")
    args = ap.parse_args()
    build, out = args.build.resolve(), args.out.resolve()
    counts = [int(x) for x in args.rounds.split(",")]
    src = HERE.parent.parent / "scenes" / f"{NAME}.json"

    base = converge.sized_scene(src, out / NAME, args.size, 1)
    t0 = time.monotonic()
    (h1, h2), cached = converge.reference(build / "bench-cache", base, out / NAME / "mitsuba", args.reference_spp)
    ref = (h1 + h2) / 2
    ref_s = time.monotonic() - t0
    mi = converge.mi
    mi.Bitmap(ref.astype(np.float32)).write(str(out / NAME / "mitsuba.exr"))
    masks, measured = converge.region_masks(without_media(base, out / NAME / "masks"), out / NAME / "mitsuba")
    print(f"{NAME}: {args.size}x{args.size}; Mitsuba volpath {args.reference_spp} spp "
          f"({'cached' if cached else f'made in {ref_s:.0f} s'}), its own noise relMSE {rel_mse(h1, h2) / 4:.4f}")

    img = None
    for rounds in counts:
        path = converge.sized_scene(src, out / NAME / f"rounds-{rounds}", args.size, rounds)
        img, seconds = converge.render_farm(build, path, path.parent)
        # The pixels that see only fog, as the farm found them (alpha 0: no surface hit).
        masks["fog"] = alpha_of(path.parent / f"{NAME}.exr") < 0.5
        err, lines = figures(img, ref, masks, measured)
        print(f"  farm {rounds} rounds on 2 workers in {seconds:.0f} s: " + lines[0])
        for line in lines[1:]:
            print("  " + line)
    diff = np.abs(img - ref) * 4
    models.write_png(out / f"{NAME}-compare.png", np.concatenate([preview(img), preview(ref), preview(diff)], axis=1))
    print(f"  relMSE after {counts[-1]} rounds {err:.4f}: {'PASS' if err <= TARGET else 'MISSED'} (target <= {TARGET})")


if __name__ == "__main__":
    main()
