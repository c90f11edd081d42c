"""Issue 14's acceptance 5: the farm's error estimate against the error it actually has,
measured against a long Mitsuba 3 reference, round by round, on three scenes and several
seeds.

    bench/crosscheck/estimate.py BUILD_DIR OUT_DIR [--size N] [--rounds N] [--seeds 1,2,3]
                                 [--reference-spp N] [--only NAME]

For scenes/cornell-box.json (final gathering, a light whose jagged rim holds most of the
error), scenes/cornell-caustics.json (the caustic map seen directly, glass and a mirror)
and scenes/cornell-fog.json (the volume photon map) at SIZE x SIZE:

  reference  converge.py's Mitsuba reference at REFERENCE_SPP samples per pixel, in two
             halves of different seeds, cached in BUILD_DIR/bench-cache (the same cache
             entries as converge.py's and fog.py's at this size), its noisiest pixels (95%
             of its noise, at most 128) rendered again at 32 times the samples
             (converge.refine_reference; cached too): the farm's error came to fall below
             the reference's noise, in the same pixels (a light's rim), where subtracting
             the noise no longer measured it; written as an OpenEXR
             that the scene names as progressive.reference, so that the farm measures its
             own RMSE against it every round
  farm       `farm render --report` (two workers) of ROUNDS progressive rounds for each
             seed (sampling.seed): per round the estimated error (its 95% interval and its
             bias part) and the reference RMSE, from the job's own report

Per scene, seed and round it prints the estimate, its interval and bias part, the actual
error (the farm's reference RMSE less the reference's own noise, which is independent of
the image and adds its variance to the mean square: the RMSE of the halves' difference,
halved), their ratio and PASS when the estimate is within 25% of the actual error, MISSED
otherwise (from round 3: the target is "every round after the second"), and whether the
interval holds the actual error. Then per scene: the rounds that passed, the interval's
coverage, and the expectation over seeds round by round (the mean estimate, the RMS actual
error, their ratio within 25% or not from round 3) with whether the mean estimate fell at
every round. With 8 seeds or more (`--seeds 1,...,24 --rounds 4 --only cornell-box`), at
the last round: the mean of the estimate's squares over the actual errors', its noise part
over the variance of the seeds' images about their mean (both 1 for an estimate right in
expectation), and the spread of one job's ratio with the actual error's and the estimate's
own (docs/error-estimate.md, "How far one job's ratio strays"). A missed target is a figure, not an error: the exit status is 0 unless a
render fails. About 15 minutes at the defaults with the references cached (each took 4 to
8 minutes to make here, and their refinement 12 minutes for the three). docs/error-estimate.md has the figures of a run and what they
mean."""

import argparse
import functools
import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np

sys.dont_write_bytecode = True  # nothing written beside the scripts
print = functools.partial(print, flush=True)  # noqa: A001  (a long run shows where it is)
HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import converge  # noqa: E402  (sets Mitsuba's variant)
from run import read_rgb  # noqa: E402

SCENES = ("cornell-box", "cornell-caustics", "cornell-fog")
TOLERANCE = 0.25
SPREAD_SEEDS = 8  # from this many seeds, spread() says how far one job's ratio strays and why
FIRST_JUDGED = 3  # "every round after the second"

# A row of `farm report`'s table: round, seconds, photons, samples/px, estimated error,
# 95% interval ("low-high"), its bias part, reference RMSE, then layer RMSEs.
ROW = re.compile(r"^\s*(\d+)\s+[\d.]+\s+[\d,]+\s+\d+\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)")


def number(s):
    return None if s == "-" else float(s)


def actual_error(rmse, noise):
    """The image's own error: its RMSE against the reference less the reference's noise."""
    return float(np.sqrt(max(rmse * rmse - noise * noise, 0.0)))


def within(estimate, actual):
    return actual > 0 and abs(estimate / actual - 1) <= TOLERANCE


def rounds_of(report):
    """{round: (estimate, (low, high), bias, reference RMSE)} from `farm render --report`."""
    rows = {}
    for line in report.splitlines():
        m = ROW.match(line)
        if not m:
            continue
        # "low-high", either end possibly in exponent form ("4.1e-05-0.0012").
        low_high = None if m.group(3) == "-" else tuple(float(v) for v in re.split(r"(?<!e)-", m.group(3)))
        rows[int(m.group(1))] = (number(m.group(2)), low_high, number(m.group(4)), number(m.group(5)))
    return rows


def farm_rounds(build, src, out_dir, size, rounds, seed, reference):
    """The report rows of ROUNDS rounds of src at SIZE with sampling.seed SEED, measured
    against the reference EXR."""
    path = converge.sized_scene(src, out_dir, size, rounds)
    scene = json.loads(path.read_text())
    scene["sampling"] = dict(scene.get("sampling", {}), seed=str(seed))
    scene["progressive"] = dict(scene["progressive"], reference={"path": reference.name})
    path.write_text(json.dumps(scene, indent=1))
    (out_dir / reference.name).write_bytes(reference.read_bytes())
    r = subprocess.run([str(build / "bin" / "farm"), "render", str(path), "-o", str(out_dir), "--workers", "2",
                        "--no-dashboard", "--report"], check=True, capture_output=True, text=True)
    return rounds_of(r.stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build", type=Path)
    ap.add_argument("out", type=Path)
    ap.add_argument("--size", type=int, default=64)
    ap.add_argument("--rounds", type=int, default=12)
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--reference-spp", type=int, default=16384)
    ap.add_argument("--only", choices=SCENES)
    args = ap.parse_args()
    build, out = args.build.resolve(), args.out.resolve()
    seeds = [int(s) for s in args.seeds.split(",")]
    root = HERE.parent.parent
    for name in SCENES:
        if args.only and name != args.only:
            continue
        src = root / "scenes" / f"{name}.json"
        base = converge.sized_scene(src, out / name, args.size, 1)
        (h1, h2), cached = converge.reference(build / "bench-cache", base, out / name / "mitsuba", args.reference_spp)
        before = float(np.sqrt(np.mean((h1 - h2) ** 2)) / 2)
        (h1, h2), windows = converge.refine_reference(build / "bench-cache", base, out / name / "mitsuba", (h1, h2),
                                                      args.reference_spp)
        noise = float(np.sqrt(np.mean((h1 - h2) ** 2)) / 2)
        reference = out / name / "reference.exr"
        converge.mi.Bitmap(((h1 + h2) / 2).astype(np.float32)).write(str(reference))
        print(f"{name}: {args.size}x{args.size}, {args.rounds} rounds, seeds {args.seeds}; reference "
              f"{args.reference_spp} spp ({'cached' if cached else 'made now'}), its own noise RMSE {before:.5f}, "
              f"{noise:.5f} with its noisiest pixels at {converge.REFINE_FACTOR} times the samples (windows x, y, "
              f"w, h: {', '.join(' '.join(str(v) for v in w) for w in windows)})")
        runs = {}
        for seed in seeds:
            rows = farm_rounds(build, src, out / name / f"seed-{seed}", args.size, args.rounds, seed, reference)
            runs[seed] = rows
            print(f"  seed {seed}:  round  estimate  95% interval      bias     actual   ratio")
            for r in sorted(rows):
                est, interval, bias, rmse = rows[r]
                if est is None or rmse is None:
                    continue
                actual = actual_error(rmse, noise)
                ratio = est / actual if actual > 0 else float("inf")
                verdict = ("PASS" if within(est, actual) else "MISSED") if r >= FIRST_JUDGED else "(not judged)"
                held = "holds" if interval and interval[0] <= actual <= interval[1] else "misses"
                span = f"{interval[0]:.5f}-{interval[1]:.5f}" if interval else "-"
                print(f"          {r:5d}  {est:.5f}  {span}  {bias or 0:.5f}  {actual:.5f}  {ratio:5.2f}  {verdict}, "
                      f"interval {held}")
        summarize(runs, noise)
        if len(seeds) >= SPREAD_SEEDS:
            spread(runs, noise, [read_rgb(out / name / f"seed-{s}" / f"{name}.exr") for s in seeds])


def summarize(runs, noise):
    """The rounds that passed, the interval's coverage, and the expectation over seeds: per
    round the mean estimate against the RMS actual error, and whether it fell."""
    judged = passed = covered = measured = 0
    by_round = {}
    for rows in runs.values():
        for r, (est, interval, _, rmse) in rows.items():
            if est is None or rmse is None:
                continue
            actual = actual_error(rmse, noise)
            by_round.setdefault(r, []).append((est, actual))
            measured += 1
            covered += bool(interval and interval[0] <= actual <= interval[1])
            if r >= FIRST_JUDGED:
                judged += 1
                passed += within(est, actual)
    print(f"  within {100 * TOLERANCE:.0f}% from round {FIRST_JUDGED}: {passed} of {judged} rounds"
          f"{'' if passed == judged else '  MISSED'}; the 95% interval held the actual error in "
          f"{covered} of {measured}")
    means, expected_judged, expected_passed = [], 0, 0
    print("  over the seeds: round  mean estimate  RMS actual  ratio")
    for r in sorted(by_round):
        est = float(np.mean([e for e, _ in by_round[r]]))
        actual = float(np.sqrt(np.mean([a * a for _, a in by_round[r]])))
        means.append(est)
        verdict = ""
        if r >= FIRST_JUDGED:
            expected_judged += 1
            expected_passed += within(est, actual)
            verdict = "PASS" if within(est, actual) else "MISSED"
        print(f"                 {r:5d}  {est:.5f}        {actual:.5f}     {est / actual:.2f}  {verdict}")
    print(f"  over the seeds, within {100 * TOLERANCE:.0f}% from round {FIRST_JUDGED}: {expected_passed} of "
          f"{expected_judged} rounds{'' if expected_passed == expected_judged else '  MISSED'}")
    falls = all(b < a for a, b in zip(means, means[1:]))
    print(f"  the mean estimate {'fell at every round' if falls else 'did not fall at every round  MISSED'}")


def spread(runs, noise, images):
    """With many seeds, at the last round: whether the estimate is right in expectation (the
    mean of its squares against the actual errors'; its noise part against the variance of
    the seeds' images about their mean) and how far one job's ratio strays, split into the
    actual error's own spread and the estimate's."""
    last = min(max(rows) for rows in runs.values())
    est, bias, actual = (np.array(v) for v in zip(*[(rows[last][0], rows[last][2] or 0.0,
                                                     actual_error(rows[last][3], noise)) for rows in runs.values()]))
    variance = float(np.var(np.array(images, dtype=np.float64), axis=0, ddof=1).mean())
    logs = {"ratio": np.log(est / actual), "actual": np.log(actual), "estimate": np.log(est)}
    print(f"  {len(images)} seeds at round {last}: mean estimate^2 / mean actual^2 "
          f"{np.mean(est ** 2) / np.mean(actual ** 2):.3f}; noise part^2 / the images' variance across seeds "
          f"{np.mean(est ** 2 - bias ** 2) / variance:.3f}; standard deviation of the log of the ratio "
          f"{logs['ratio'].std():.3f}, of the actual error {logs['actual'].std():.3f}, of the estimate "
          f"{logs['estimate'].std():.3f}; within {100 * TOLERANCE:.0f}%: "
          f"{int(np.sum(np.abs(est / actual - 1) <= TOLERANCE))} of {len(images)}")


if __name__ == "__main__":
    main()
