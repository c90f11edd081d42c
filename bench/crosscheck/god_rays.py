"""Issue 15's acceptance 4: error against time on the god-rays scene, the farm against
Mitsuba 3's volumetric path tracer on the same machine.

    bench/crosscheck/god_rays.py BUILD_DIR OUT_DIR [--width N] [--reference-spp N]
                                 [--spp-per-round N] [--rounds 1,2,4,...] [--target 0.01]

scenes/god-rays.json (sunlight through three windows into a dusty room: a homogeneous
medium of albedo 0.8, density 0.2 a metre, g 0.75, filling the ball about the room) at
WIDTH x WIDTH * 9 / 16, with two changes for both renderers: the sun's disc is made a point
(angular diameter 0), since Mitsuba's `directional` emitter is a delta light and
to_mitsuba.py refuses a disc it cannot translate; and the glass ball is made of the
room's plaster, since a path tracer cannot find light from a point sun through glass (the
sun's one direction is never hit by a path leaving the glass, and a shadow ray cannot pass
through it): the farm's caustic photons light the fog and the floor behind the ball, a
focus that Mitsuba's image lacks, and the two would not converge to one image (measured
with the glass: the farm's mean 10% above Mitsuba's, most of it that focus). Without
--keep-glass, what is compared is what both renderers can render. What it prints:

  reference  Mitsuba's `volpath` at REFERENCE_SPP samples a pixel in two halves (cached in
             BUILD_DIR/bench-cache like converge.py's), and its own noise in relMSE (that of
             the two halves' mean, a quarter of theirs against each other)
  Mitsuba    renders at 1, 2, 4, ... samples a pixel (seeds apart from the reference's),
             each with the seconds of its render call and its relMSE against the reference,
             until it is below half the target; the time at which its error crosses the
             target, interpolated on log-log axes between the two renders about it
  farm       `farm render --report` on two local workers at each round count of --rounds
             (SPP_PER_ROUND camera samples a round; the reference is the scene's
             progressive.reference, so the job measures every round against it), each with
             the wall time of the whole command and its relMSE; the time to the target
             likewise; and the error-against-time table `farm render --report` printed for
             the longest run (the job's reference RMSE falling round after round)

relMSE = mean over pixels and channels of (image - reference)^2 / (reference^2 + 0.01)
(run.py's measure), less the reference's own noise in the same measure (independent of the
image, it adds to what is measured; converge.py does the same with RMSE), and as measured in
brackets. The verdict line prints both times to TARGET and their ratio; a
renderer that never reaches it within its runs says so (a figure, never an error exit).
OUT_DIR/god-rays-compare.png: the farm's longest run | Mitsuba's reference | |difference|
x 4, tone-mapped alike."""

import argparse
import json
import math
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.dont_write_bytecode = True  # nothing written beside the scripts
HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import converge  # noqa: E402  (sets Mitsuba's variant)
import models  # noqa: E402
from run import preview, read_rgb, rel_mse  # noqa: E402

NAME = "god-rays"
# The first line of `farm render --report`'s table: "job ID (NAME): STATE, N rounds".
REPORT = re.compile(r"^job \S+ \(.*\): .*rounds$", re.MULTILINE)


def bench_scene(src, out_dir, width, spp, rounds, reference=None, keep_glass=False):
    """The god-rays scene at width x width * 9 / 16 with a point sun and, unless keep_glass,
    its dielectric shapes in the first Lambert material, spp samples a round and `rounds`
    rounds, measured against `reference` (an EXR path relative to out_dir) when given."""
    scene = json.loads(Path(src).read_text())
    if not keep_glass:
        plaster = next(m["name"] for m in scene["materials"] if "lambert" in m)
        glass = {m["name"] for m in scene["materials"] if "dielectric" in m}
        for shape in scene["shapes"]:
            if shape.get("material") in glass:
                shape["material"] = plaster
    scene["film"] = dict(scene.get("film", {}), width=width, height=max(1, round(width * 9 / 16)))
    scene["sampling"] = dict(scene.get("sampling", {}), samplesPerPixel=spp)
    for light in scene.get("lights", []):
        light.get("sun", {}).pop("angularDiameterDegrees", None)
    progressive = dict(scene.get("progressive", {}), maxRounds=rounds)
    if reference is not None:
        progressive["reference"] = {"path": reference}
    scene["progressive"] = progressive
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / Path(src).name
    path.write_text(json.dumps(scene, indent=1))
    return path


def time_to(target, runs):
    """The seconds at which the error of runs [(seconds, error), ...] (in increasing seconds)
    first crosses target, interpolated on log-log axes; None if it never does."""
    for (t0, e0), (t1, e1) in zip(runs, runs[1:]):
        if e1 <= target < e0 and e1 > 0:
            f = math.log(e0 / target) / math.log(e0 / e1)
            return math.exp(math.log(t0) + f * math.log(t1 / t0))
    if runs and runs[0][1] <= target:
        return runs[0][0]
    return None


def own_error(img, ref, noise):
    """relMSE against the reference less the reference's own noise."""
    return max(0.0, rel_mse(img, ref) - noise)


def mitsuba_runs(base, work_dir, ref, noise, target, reference_spp):
    """Mitsuba at doubling sample counts until its error is below half the target, or its
    samples are an eighth of the reference's (past that the reference's own noise is most of
    what is measured)."""
    runs, spp = [], 1
    while True:
        img, seconds = converge.render_mitsuba(base, work_dir, spp, seed=7)
        err = own_error(img, ref, noise)
        runs.append((seconds, err))
        print(f"  Mitsuba {spp:5d} spp in {seconds:7.1f} s: relMSE {err:.5f} ({rel_mse(img, ref):.5f})", flush=True)
        if err < target / 2 or 8 * spp > reference_spp:
            return runs
        spp *= 2


def farm_runs(build, src, out, args, reference, ref, noise):
    """The farm at each round count, with the report of the last run."""
    runs, report, img = [], "", None
    for rounds in [int(x) for x in args.rounds.split(",")]:
        path = bench_scene(src, out / f"rounds-{rounds}", args.width, args.spp_per_round, rounds,
                           "../" + reference.name, args.keep_glass)
        t0 = time.monotonic()
        done = subprocess.run([str(build / "bin" / "farm"), "render", str(path), "-o", str(path.parent),
                               "--workers", "2", "--no-dashboard", "--report", "--asset-root", str(out)],
                              check=True, capture_output=True, text=True)
        seconds = time.monotonic() - t0
        img = read_rgb(path.parent / f"{NAME}.exr")
        err = own_error(img, ref, noise)
        runs.append((seconds, err))
        report = REPORT.search(done.stdout)
        report = done.stdout[report.start():] if report else "(no report printed)"
        print(f"  farm {rounds:3d} rounds of {args.spp_per_round} spp in {seconds:7.1f} s: relMSE {err:.5f} ({rel_mse(img, ref):.5f})", flush=True)
        if err < args.target / 2:
            break
    return runs, report, img


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build", type=Path)
    ap.add_argument("out", type=Path)
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--reference-spp", type=int, default=32768)
    ap.add_argument("--spp-per-round", type=int, default=4)
    ap.add_argument("--rounds", default="1,2,4,8,16,32", help="the farm's round counts, one run each")
    ap.add_argument("--target", type=float, default=0.01)
    ap.add_argument("--keep-glass", action="store_true", help="leave the glass ball glass (see above)")
    args = ap.parse_args()
    build, out = args.build.resolve(), args.out.resolve() / NAME
    src = HERE.parent.parent / "scenes" / f"{NAME}.json"

    base = bench_scene(src, out / "mitsuba-scene", args.width, 1, 1, keep_glass=args.keep_glass)
    t0 = time.monotonic()
    (h1, h2), cached = converge.reference(build / "bench-cache", base, out / "mitsuba", args.reference_spp)
    ref = (h1 + h2) / 2
    noise = rel_mse(h1, h2) / 4
    reference = out / "mitsuba.exr"
    converge.mi.Bitmap(ref.astype(np.float32)).write(str(reference))
    made = "cached" if cached else f"made in {time.monotonic() - t0:.0f} s"
    print(f"{NAME}: {args.width}x{ref.shape[0]}, the sun a point for both, "
          f"{'the glass ball glass' if args.keep_glass else 'the glass ball plaster'}; Mitsuba volpath "
          f"{args.reference_spp} spp ({made}), its own noise relMSE {noise:.5f}", flush=True)

    m_runs = mitsuba_runs(base, out / "mitsuba", ref, noise, args.target, args.reference_spp)
    f_runs, report, img = farm_runs(build, src, out, args, reference, ref, noise)
    print("  the farm's own report of its longest run (`farm render --report`):")
    for line in report.rstrip().splitlines():
        print("    " + line)

    t_farm, t_mitsuba = time_to(args.target, f_runs), time_to(args.target, m_runs)
    said = {k: (f"{t:.1f} s" if t is not None else "not reached") for k, t in (("farm", t_farm), ("mitsuba", t_mitsuba))}
    ratio = f"; farm / Mitsuba {t_farm / t_mitsuba:.2f}" if t_farm and t_mitsuba else ""
    print(f"  time to relMSE {args.target}: farm {said['farm']}, Mitsuba {said['mitsuba']}{ratio}")
    diff = np.abs(img - ref) * 4
    models.write_png(args.out.resolve() / f"{NAME}-compare.png",
                     np.concatenate([preview(img), preview(ref), preview(diff)], axis=1))


if __name__ == "__main__":
    main()
