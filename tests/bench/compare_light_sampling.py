#!/usr/bin/env python3
"""Time to an error with each light sampler, against Mitsuba 3 in the same run: 1 / (relMSE x render seconds).

Renders SCENE with Fredholm once per --light-sampler (tree, power, uniform) and with Mitsuba 3 (compare_renderers.py),
--repeats seeds each, alternating, all at the same size, samples per pixel and maximum depth, and scores every image
against one converged REFERENCE:

  relMSE = mean over pixels of (L - L_ref)^2 / (L_ref^2 + 0.01), L the luminance (pbrt's and Mitsuba's relMSE),

leaving out the pixels where the reference's luminance is above --emitter-luminance (the emitters seen directly and
the pixels their edges cross: a few pixels whose error would otherwise stand for the whole image). Prints per
renderer the median render seconds, the mean relMSE over the seeds, the efficiency, and the ratio to Mitsuba's.

  /opt/refbench/mitsuba-venv/bin/python tests/bench/compare_light_sampling.py --scene scenes/studio.gltf \\
      --reference REF.exr [--size 160] [--spp 64] [--repeats 3] [--json OUT.json]

The reference: a long Fredholm render of the same scene (`fredholm render SCENE --width 160 --height 160 --spp 8192
--max-depth 10 --seed 99`); the mean of Mitsuba's images agrees with it where the scene is within what
compare_renderers.py reads (Lambertian materials, flat shading), which the script prints (mean ratio).
--with-cycles adds Blender Cycles (compare_renderers.py: CPU, its default light tree). Needs the Mitsuba (and for
Cycles the Cycles) environment of tests/bench/README.md.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare_efficiency import REPO, read_rgb, run_fredholm, run_mitsuba  # noqa: E402

SAMPLERS = ["tree", "power", "uniform"]


def luminance(rgb):
    return rgb @ np.array([0.2126, 0.7152, 0.0722])


def score(image, reference, mask):
    lum, ref = luminance(image)[mask], luminance(reference)[mask]
    return float(np.mean((lum - ref) ** 2 / (ref ** 2 + 0.01))), float(lum.mean() / ref.mean())


def run_cycles(args, out_dir, seed):
    exr = os.path.join(out_dir, "cycles.exr")
    cmd = [args.cycles_python, os.path.join(REPO, "tests", "bench", "compare_renderers.py"), "--renderer", "cycles",
           "--scene", args.scene, "--size", str(args.size), "--spp", str(args.spp), "--max-depth", str(args.max_depth),
           "--repeats", "1", "--output", exr, "--seed", str(seed)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return exr, float(re.search(r"seconds_median ([0-9.]+)", out).group(1)), " ".join(cmd)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fredholm", default=os.path.join(REPO, "build", "fredholm"))
    ap.add_argument("--scene", required=True)
    ap.add_argument("--reference", required=True)
    ap.add_argument("--size", type=int, default=160)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--max-depth", type=int, default=10)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--emitter-luminance", type=float, default=10.0)
    ap.add_argument("--mitsuba-sampler", default="multijitter")
    ap.add_argument("--mitsuba-python", default="/opt/refbench/mitsuba-venv/bin/python")
    ap.add_argument("--without-mitsuba", action="store_true",
                    help="Fredholm's samplers alone (a scene compare_renderers.py cannot read: punctual lights)")
    ap.add_argument("--with-cycles", action="store_true", help="also Blender Cycles (bpy, CPU, its light tree on)")
    ap.add_argument("--cycles-python", default="/opt/refbench/cycles-venv/bin/python")
    ap.add_argument("--fredholm-extra", default="", help="more arguments for every Fredholm render (e.g. --env MAP)")
    ap.add_argument("--json", help="also write the results here")
    args = ap.parse_args()
    args.fredholm_sampler = "sobol"
    reference = read_rgb(args.reference)
    mask = luminance(reference) <= args.emitter_luminance
    names = [f"fredholm {s}" for s in SAMPLERS] + ([] if args.without_mitsuba else ["mitsuba"]) + \
        (["cycles"] if args.with_cycles else [])
    results = {n: {"seconds": [], "relmse": [], "mean_ratio": []} for n in names}
    with tempfile.TemporaryDirectory() as out_dir:
        for repeat in range(args.repeats):
            seed = args.seed + repeat
            for s in SAMPLERS:
                args.fredholm_args = f"--light-sampler {s} {args.fredholm_extra}"
                exr, seconds, cmd = run_fredholm(args, out_dir, repeat, seed)
                r = results[f"fredholm {s}"]
                r["command"] = cmd
                rel, ratio = score(read_rgb(exr), reference, mask)
                r["seconds"].append(seconds), r["relmse"].append(rel), r["mean_ratio"].append(ratio)
            if args.with_cycles:
                exr, seconds, cmd = run_cycles(args, out_dir, seed)
                rel, ratio = score(read_rgb(exr), reference, mask)
                r = results["cycles"]
                r.update(command=cmd)
                r["seconds"].append(seconds), r["relmse"].append(rel), r["mean_ratio"].append(ratio)
            if args.without_mitsuba:
                continue
            exr, seconds, cmd, version = run_mitsuba(args, out_dir, seed)
            rel, ratio = score(read_rgb(exr), reference, mask)
            r = results["mitsuba"]
            r.update(command=cmd, version=version)
            r["seconds"].append(seconds), r["relmse"].append(rel), r["mean_ratio"].append(ratio)
    m = results["mitsuba" if not args.without_mitsuba else "fredholm power"]
    for r in results.values():
        r["seconds_median"] = statistics.median(r["seconds"])
        r["relmse_mean"] = statistics.fmean(r["relmse"])
        r["efficiency"] = 1.0 / (r["relmse_mean"] * r["seconds_median"])
    print(f"{os.path.basename(args.scene)}, {args.size} x {args.size}, {args.spp} spp, max depth {args.max_depth}, "
          f"seeds {args.seed}..{args.seed + args.repeats - 1}; {int(mask.sum())} of {mask.size} pixels scored")
    for name, r in results.items():
        print(f"{name:17s} seconds {r['seconds_median']:.3f}  relMSE {r['relmse_mean']:.3e}  efficiency "
              f"{r['efficiency']:.4g}  x {'Mitsuba' if not args.without_mitsuba else 'power'} {r['efficiency'] / m['efficiency']:.2f}  mean / reference "
              f"{statistics.fmean(r['mean_ratio']):.4f}")
    if args.json:
        with open(args.json, "w") as out:
            json.dump({"results": results, "settings": vars(args)}, out, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
