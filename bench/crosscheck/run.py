"""Issue 13's acceptance 4: the farm against Mitsuba 3 on two scenes of this issue.

    bench/crosscheck/run.py BUILD_DIR OUT_DIR [--farm-spp N] [--farm-rounds N] [--mitsuba-spp N] [--only CASE]

For each model of models.py (a textured glTF under an environment map; metallic and rough
principled balls under the map and a sun): `farm import` it into a scene file, render
that scene on a local two-worker farm (`farm render`, progressive rounds), translate the
same scene file for Mitsuba 3 (to_mitsuba.py; variant scalar_rgb, path tracer, in two
halves of different seeds) and print

    relMSE = mean over pixels p and channels c of (farm - mitsuba)^2 / (mitsuba^2 + 0.01)

on the linear images (the EXR's premultiplied R, G, B against Mitsuba's), which should be
at most 0.01; and, to tell bias from noise, Mitsuba's own noise in the same measure
(the two halves' relMSE against each other over 4: the variance of their mean), each
channel's mean ratio farm / mitsuba, and relMSE over the pixels of each material. A third,
diagnostic case renders the metals with a Lambertian floor in both renderers, which
leaves out the one model the two principled materials do not share (bench/README.md).
OUT_DIR keeps both EXRs and OUT_DIR/NAME-compare.png: farm | Mitsuba | |difference| x 4,
tone-mapped alike."""

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.dont_write_bytecode = True  # nothing written beside the scripts
import mitsuba as mi  # noqa: E402

mi.set_variant("scalar_rgb")

sys.path.insert(0, str(Path(__file__).resolve().parent))
import models  # noqa: E402
import to_mitsuba  # noqa: E402

EPS = 0.01
SIZE = 256


def rel_mse(a, b):
    return float(np.mean((a - b) ** 2 / (b * b + EPS)))


def read_rgb(path):
    """The R, G, B channels of an OpenEXR file (the farm's root layer) as an HxWx3 array."""
    bmp = mi.Bitmap(str(path))
    for name, layer in bmp.split():
        if name == "<root>":
            return np.array(layer, dtype=np.float64)[..., :3]
    return np.array(bmp, dtype=np.float64)[..., :3]


def preview(img):
    """sRGB 8-bit of a linear image clipped to [0, 1], for the figures."""
    x = np.clip(img, 0, 1)
    x = np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)
    return (x * 255 + 0.5).astype(np.uint8)


# The cases: a name, the model, and the materials made Lambertian in both renderers (a
# diagnostic: with the floor Lambertian, what is left is the balls').
CASES = (("textured", "textured", ()), ("metals", "metals", ()), ("metals-lambert-floor", "metals", ("floor",)))


def farm_scene(build, models_dir, name, model, lambert, out, spp, rounds):
    """farm import of models_dir/MODEL.gltf under the sky, with the sampling of a converged
    render, the principled materials whose names contain a word of lambert made Lambertian
    of their base colour."""
    scene_path = out / name / "scene.json"
    subprocess.run([str(build / "bin" / "farm"), "import", str(models_dir / f"{model}.gltf"), "-o", str(scene_path),
                    "--environment", str(models_dir / "sky.hdr"), "--width", str(SIZE), "--height", str(SIZE)],
                   check=True, stdout=subprocess.DEVNULL)
    scene = json.loads(scene_path.read_text())
    scene["sampling"] = {"samplesPerPixel": spp, "seed": "1"}
    scene["progressive"] = {"maxRounds": rounds}
    for m in scene["materials"]:
        if any(word in m["name"] for word in lambert):
            m["lambert"] = {"reflectance": m.pop("principled")["baseColor"]}
    scene_path.write_text(json.dumps(scene, indent=1))
    return scene_path


def material_masks(scene_path, work_dir):
    """The pixels whose centre sees each material first: each shape made a diffuse BSDF
    whose reflectance numbers it, seen through Mitsuba's albedo AOV (0 where no shape is
    hit). Distinct BSDFs also keep Mitsuba from merging the shapes."""
    d, material_of = to_mitsuba.mitsuba_scene(mi, scene_path, work_dir, 1)
    keys = sorted(material_of)
    for i, key in enumerate(keys):
        d[key]["bsdf"] = {"type": "diffuse", "reflectance": {"type": "rgb", "value": (i + 1) / len(keys) / 2}}
    d["integrator"] = {"type": "aov", "aovs": "alb:albedo"}
    d["sensor"]["sampler"] = {"type": "stratified", "sample_count": 1, "jitter": False}
    index = np.rint(np.array(mi.render(mi.load_dict(d)))[..., 0] * len(keys) * 2).astype(int)
    masks = {}
    for i, key in enumerate(keys):
        m = masks.setdefault(material_of[key], np.zeros(index.shape, bool))
        m |= index == i + 1
    return masks


def render_mitsuba(scene_path, work_dir, spp):
    halves = []
    for seed in (1, 2):
        d, _ = to_mitsuba.mitsuba_scene(mi, scene_path, work_dir, spp // 2, seed=seed)
        halves.append(np.array(mi.render(mi.load_dict(d)), dtype=np.float64))
    return halves


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build", type=Path)
    ap.add_argument("out", type=Path)
    ap.add_argument("--farm-spp", type=int, default=2, help="farm camera samples per pixel per round")
    ap.add_argument("--farm-rounds", type=int, default=8, help="farm progressive rounds")
    ap.add_argument("--mitsuba-spp", type=int, default=1024, help="Mitsuba samples per pixel (two halves)")
    ap.add_argument("--only", help="one case: " + ", ".join(c[0] for c in CASES))
    args = ap.parse_args()
    build, out = args.build.resolve(), args.out.resolve()
    models_dir = out / "models"
    models_dir.mkdir(parents=True, exist_ok=True)
    models.write_hdr(models_dir / "sky.hdr", models.sky())
    models.textured(models_dir)
    models.metals(models_dir)
    worst = None
    for name, model, lambert in CASES:
        if args.only and name != args.only:
            continue
        scene_path = farm_scene(build, models_dir, name, model, lambert, out, args.farm_spp, args.farm_rounds)
        t0 = time.monotonic()
        # --name: farm render names its files after the scene's name field (the model's).
        subprocess.run([str(build / "bin" / "farm"), "render", str(scene_path), "-o", str(out / name), "--name", "scene",
                        "--workers", "2", "--no-dashboard"], check=True, stdout=subprocess.DEVNULL)
        farm_s = time.monotonic() - t0
        farm = read_rgb(out / name / "scene.exr")
        t0 = time.monotonic()
        h1, h2 = render_mitsuba(scene_path, out / name / "mitsuba", args.mitsuba_spp)
        mitsuba_s = time.monotonic() - t0
        ref = (h1 + h2) / 2
        mi.Bitmap(ref.astype(np.float32)).write(str(out / name / "mitsuba.exr"))
        err = rel_mse(farm, ref)
        noise = rel_mse(h1, h2) / 4
        ratio = farm.reshape(-1, 3).mean(axis=0) / ref.reshape(-1, 3).mean(axis=0)
        if not lambert:
            worst = max(worst or 0.0, err)
        print(f"{name}: {SIZE}x{SIZE}, farm {args.farm_spp} spp x {args.farm_rounds} rounds on 2 workers in {farm_s:.0f} s, "
              f"Mitsuba {args.mitsuba_spp} spp in {mitsuba_s:.0f} s")
        print(f"  relMSE {err:.4f} ({'PASS' if err <= 0.01 else 'FAIL'} at <= 0.01); Mitsuba's own noise {noise:.4f}; "
              f"mean farm/Mitsuba R {ratio[0]:.3f} G {ratio[1]:.3f} B {ratio[2]:.3f}")
        for material, mask in material_masks(scene_path, out / name / "mitsuba").items():
            if mask.any():
                print(f"    {material}: relMSE {rel_mse(farm[mask], ref[mask]):.4f} over {mask.sum()} pixels, "
                      f"mean farm/Mitsuba {farm[mask].mean() / ref[mask].mean():.3f}")
        diff = np.abs(farm - ref) * 4
        models.write_png(out / f"{name}-compare.png", np.concatenate([preview(farm), preview(ref), preview(diff)], axis=1))
    if worst is not None:
        print(f"worst relMSE {worst:.4f} (of the cases without Lambertian stand-ins)")


if __name__ == "__main__":
    main()
