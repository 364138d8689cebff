#!/usr/bin/env python3
"""How honest is the error estimate every render writes? Reported against true relative error over many seeds.

For each scene, renders --seeds images that differ only in their seed and compares the relative error each reports
(fredholm:relative_error, engine/render/error_estimate.h) with the true one, measured from the images themselves:

  true^2 = mean over pixels of var_seeds(Y) / (mean_seeds(Y)^2 + 0.01),  Y the pixel's luminance,

the variance over the seeds being each image's variance (they are independent, unbiased renders). Prints per scene the
root mean square of the reported errors, the true error, their ratio (above 1: the estimate is conservative) and the
spread of the ratio of single renders (a render's own estimate, against the truth). Needs numpy and OpenEXR (the
Mitsuba environment of tests/bench/README.md has both).

  /opt/refbench/mitsuba-venv/bin/python tests/bench/error_calibration.py [--size 64] [--spp 64] [--seeds 12] \\
      [--scene NAME=PATH[,extra args] ...] [--json OUT.json]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
import OpenEXR

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHARED = os.path.join(os.path.dirname(REPO), "shared")
ENV = os.path.join(REPO, "scenes", "environments", "courtyard.exr")
SCENES = [
    "cornell=scenes/cornell.gltf,--max-depth 10",
    "studio=scenes/studio.gltf",
    "lamp_hall=scenes/lamp_hall.gltf",
    "sign_bulb=scenes/sign_bulb.gltf",
    "door_gap=scenes/door_gap.gltf",
    "lamp_shade=scenes/lamp_shade.gltf",
    "glass_caustic=scenes/glass_caustic.gltf,--max-depth 12",
    f"damaged_helmet={SHARED}/scenes-thirdparty/DamagedHelmet/glTF/DamagedHelmet.gltf,--env {ENV}",
]


def luminance(path):
    with OpenEXR.File(path) as f:
        ch = f.channels()
        rgb = np.asarray(ch["RGB"].pixels, dtype=np.float64) if "RGB" in ch else \
            np.stack([np.asarray(ch[c].pixels, dtype=np.float64) for c in "RGB"], axis=-1)
    return rgb @ np.array([0.2126, 0.7152, 0.0722])


def calibrate(args, name, scene, extra, out):
    images, reported = [], []
    for seed in range(1, args.seeds + 1):
        exr, stats = os.path.join(out, f"{name}_{seed}.exr"), os.path.join(out, f"{name}_{seed}.json")
        cmd = [args.fredholm, "render", scene, "-o", exr, "--width", str(args.size), "--height", str(args.size),
               "--spp", str(args.spp), "--seed", str(seed), "--stats", stats, "-q"] + extra
        subprocess.run(cmd, check=True, cwd=REPO)
        with open(stats) as f:
            reported.append(json.load(f)["relative_error"])
        images.append(luminance(exr))
    y = np.stack(images)
    mean, var = y.mean(0), y.var(0, ddof=1)
    truth = float(np.sqrt(np.mean(var / (mean ** 2 + 0.01))))
    rms = float(np.sqrt(np.mean(np.square(reported))))
    ratios = np.array(reported) / truth
    return {"scene": name, "spp": args.spp, "size": args.size, "seeds": args.seeds, "reported": rms, "true": truth,
            "ratio": rms / truth, "single_min": float(ratios.min()), "single_max": float(ratios.max()),
            "command": " ".join(["fredholm", "render", scene] + extra)}


def scene_entries(entries):
    """(name, path, extra args) of each NAME=PATH[,extra args] entry whose file exists; the others are named as
    skipped."""
    for entry in entries:
        name, rest = entry.split("=", 1)
        path, _, extra = rest.partition(",")
        if not os.path.exists(os.path.join(REPO, path)):
            print(f"{name:16} skipped: {path} not found")
            continue
        yield name, path, extra.split()


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--fredholm", default=os.path.join(REPO, "build", "fredholm"))
    p.add_argument("--size", type=int, default=64)
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--seeds", type=int, default=12)
    p.add_argument("--scene", action="append", help="NAME=PATH[,extra args] (default: a fixed set)")
    p.add_argument("--json")
    args = p.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as out:
        print(f"{'scene':16} {'spp':>5} {'reported':>9} {'true':>9} {'ratio':>6}  single renders")
        for name, path, extra in scene_entries(args.scene or SCENES):
            r = calibrate(args, name, path, extra, out)
            rows.append(r)
            print(f"{name:16} {r['spp']:5d} {r['reported']:9.4f} {r['true']:9.4f} {r['ratio']:6.3f}  "
                  f"{r['single_min']:.2f} to {r['single_max']:.2f}", flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=2)


if __name__ == "__main__":
    sys.exit(main())
