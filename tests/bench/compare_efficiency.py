#!/usr/bin/env python3
"""Efficiency of Fredholm against Mitsuba 3 on the same scene, measured back to back: 1 / (MSE x render seconds).

Both render the scene at the same size, samples per pixel and maximum depth; both images are scored against the same
converged reference (default: ../shared/references/cornell_mitsuba_16384spp.exr for scenes/cornell.gltf). Render
seconds are the render call alone for both: Fredholm's `render_seconds` (the wave loop: no loading, BVH build or
pipeline creation) and Mitsuba's timed render after an untimed warm-up that JIT-compiles its kernels
(compare_renderers.py). Each renderer is timed --repeats times, alternating, and the medians are reported. Repeat k
renders with seed --seed + k on both sides, and the MSE is the mean over the repeats: one image's MSE varies by about
10% from seed to seed (Mitsuba's seed 0 on the Cornell box, 8.9e-5, is the lowest of seeds 0 to 3; their mean is
9.8e-5), so a single seed can tilt the ratio.

  python3 tests/bench/compare_efficiency.py [--fredholm build/fredholm] [--spp 64] [--repeats 3]
      [--mitsuba-sampler multijitter] [--fredholm-sampler sobol]

Needs the Mitsuba environment of tests/bench/README.md (/opt/refbench/mitsuba-venv) and PyPI OpenEXR and numpy in
the Python that runs this script (the Mitsuba venv has both: run it with /opt/refbench/mitsuba-venv/bin/python).
Prints one line per renderer and one line of ratios; --json writes them.
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
import OpenEXR

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHARED = os.path.join(os.path.dirname(REPO), "shared")


def read_rgb(path):
    with OpenEXR.File(path) as f:
        channels = f.channels()
        if "RGB" in channels:
            return np.asarray(channels["RGB"].pixels, dtype=np.float64)
        return np.stack([np.asarray(channels[c].pixels, dtype=np.float64) for c in "RGB"], axis=-1)


def mse(image, reference):
    if image.shape != reference.shape:
        raise SystemExit(f"compare_efficiency: image {image.shape} and reference {reference.shape} differ in size")
    return float(np.mean((image - reference) ** 2))


def run_fredholm(args, out_dir, repeat, seed):
    exr, stats = os.path.join(out_dir, f"fredholm_{repeat}.exr"), os.path.join(out_dir, f"fredholm_{repeat}.json")
    cmd = [args.fredholm, "render", args.scene, "-o", exr, "--width", str(args.size), "--height", str(args.size),
           "--spp", str(args.spp), "--max-depth", str(args.max_depth), "--seed", str(seed), "--sampler",
           args.fredholm_sampler, "--stats", stats, "--quiet"] + args.fredholm_args.split()
    subprocess.run(cmd, check=True)
    with open(stats) as f:
        return exr, json.load(f)["render_seconds"], " ".join(cmd)


def run_mitsuba(args, out_dir, seed):
    exr = os.path.join(out_dir, "mitsuba.exr")
    cmd = [args.mitsuba_python, os.path.join(REPO, "tests", "bench", "compare_renderers.py"), "--renderer", "mitsuba",
           "--scene", args.scene, "--size", str(args.size), "--spp", str(args.spp), "--max-depth", str(args.max_depth),
           "--repeats", "1", "--mitsuba-sampler", args.mitsuba_sampler, "--output", exr, "--seed", str(seed)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    seconds = float(re.search(r"seconds_median ([0-9.]+)", out).group(1))
    version = re.search(r"version (\S+)", out)
    return exr, seconds, " ".join(cmd), version.group(1) if version else "?"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fredholm", default=os.path.join(REPO, "build", "fredholm"))
    ap.add_argument("--scene", default=os.path.join(REPO, "scenes", "cornell.gltf"))
    ap.add_argument("--reference", default=os.path.join(SHARED, "references", "cornell_mitsuba_16384spp.exr"))
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--max-depth", type=int, default=10)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--fredholm-sampler", default="sobol", choices=["sobol", "independent"])
    ap.add_argument("--fredholm-args", default="",
                    help="more options for fredholm render, e.g. \"--light-pick separate\" or \"--rr-start-depth 5\"")
    ap.add_argument("--mitsuba-sampler", default="multijitter",
                    help="independent, stratified, multijitter, orthogonal or ldsampler (default: its best here)")
    ap.add_argument("--mitsuba-python", default="/opt/refbench/mitsuba-venv/bin/python")
    ap.add_argument("--json", help="also write the results here")
    args = ap.parse_args()
    reference = read_rgb(args.reference)
    results = {"fredholm": {"seconds": [], "mses": []}, "mitsuba": {"seconds": [], "mses": []}}
    with tempfile.TemporaryDirectory() as out_dir:
        for repeat in range(args.repeats):
            seed = args.seed + repeat
            exr, seconds, cmd = run_fredholm(args, out_dir, repeat, seed)
            results["fredholm"]["seconds"].append(seconds)
            results["fredholm"]["mses"].append(mse(read_rgb(exr), reference))
            results["fredholm"].update(command=cmd, sampler=args.fredholm_sampler)
            exr, seconds, cmd, version = run_mitsuba(args, out_dir, seed)
            results["mitsuba"]["seconds"].append(seconds)
            results["mitsuba"]["mses"].append(mse(read_rgb(exr), reference))
            results["mitsuba"].update(command=cmd, sampler=args.mitsuba_sampler, version=version)
    for name, r in results.items():
        r["seconds_median"] = statistics.median(r["seconds"])
        r["mse"] = statistics.fmean(r["mses"])
        r["efficiency"] = 1.0 / (r["mse"] * r["seconds_median"])
        print(f"{name:9s} sampler {r['sampler']:12s} seconds {r['seconds_median']:.3f} (runs "
              f"{', '.join('%.3f' % s for s in r['seconds'])}) MSE {r['mse']:.4e} (mean of seeds {args.seed} to "
              f"{args.seed + args.repeats - 1}: {', '.join('%.3e' % m for m in r['mses'])}) efficiency "
              f"{r['efficiency']:.4e}")
    f, m = results["fredholm"], results["mitsuba"]
    ratios = {"time": f["seconds_median"] / m["seconds_median"], "mse": f["mse"] / m["mse"],
              "efficiency": f["efficiency"] / m["efficiency"]}
    print(f"fredholm / mitsuba: time {ratios['time']:.2f}x, MSE {ratios['mse']:.2f}x, efficiency {ratios['efficiency']:.3f}"
          f" ({os.path.basename(args.scene)}, {args.size} x {args.size}, {args.spp} spp, max depth {args.max_depth})")
    if args.json:
        with open(args.json, "w") as out:
            json.dump({"results": results, "ratios": ratios, "settings": vars(args)}, out, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
