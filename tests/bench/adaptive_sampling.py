#!/usr/bin/env python3
"""What adaptive sampling (`fredholm render --adaptive`) buys: error, time and efficiency against uniform sampling.

For each scene, renders --seeds images per mode that differ only in their seed, uniform (`--spp S`) and adaptive
(`--adaptive --spp S`: the same samples on average, its pilot included), and measures from the images themselves
(as tests/bench/error_calibration.py does, no reference needed):

  true error^2 = mean over pixels of var_seeds(Y) / (mean_seeds(Y)^2 + 0.01),  Y the pixel's luminance;
  time = median render_seconds (--stats: the whole sampling, the pilot's included);
  efficiency = 1 / (true error^2 x time), and adaptive's against uniform's;
  bias: the two modes' per-pixel means over the seeds, |z| above 4 counted, and the images' mean luminance ratio;
  honesty: adaptive's reported error (fredholm:relative_error) over its true error.

With --target E it also renders each mode to the target (`--target-error E`) and prints the median time each took
and the true error each reached. Needs numpy and OpenEXR (the Mitsuba environment of tests/bench/README.md has both).

  /opt/refbench/mitsuba-venv/bin/python tests/bench/adaptive_sampling.py [--size 96] [--spp 64] [--seeds 8] \\
      [--target 0.05] [--scene NAME=PATH[,extra args] ...] [--json OUT.json]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

from error_calibration import REPO, SCENES, luminance, scene_entries

MODES = {"uniform": [], "adaptive": ["--adaptive"]}


def render_set(args, name, scene, extra, out, mode, budget):
    images, reported, seconds = [], [], []
    for seed in range(1, args.seeds + 1):
        exr, stats = os.path.join(out, f"{name}_{mode}_{seed}.exr"), os.path.join(out, f"{name}_{mode}_{seed}.json")
        cmd = [args.fredholm, "render", scene, "-o", exr, "--width", str(args.size), "--height", str(args.size),
               "--seed", str(seed), "--stats", stats, "-q"] + budget + MODES[mode] + extra
        subprocess.run(cmd, check=True, cwd=REPO)
        with open(stats) as f:
            j = json.load(f)
        reported.append(j["relative_error"])
        seconds.append(j["render_seconds"])
        images.append(luminance(exr))
    y = np.stack(images)
    mean, var = y.mean(0), y.var(0, ddof=1)
    truth = float(np.sqrt(np.mean(var / (mean ** 2 + 0.01))))
    return {"mean": mean, "var": var, "true": truth, "reported": float(np.sqrt(np.mean(np.square(reported)))),
            "seconds": float(np.median(seconds))}


def compare(args, name, scene, extra, out):
    row = {"scene": name, "size": args.size, "spp": args.spp, "seeds": args.seeds,
           "command": " ".join(["fredholm", "render", scene] + extra)}
    sets = {m: render_set(args, name, scene, extra, out, m, ["--spp", str(args.spp)]) for m in MODES}
    u, a = sets["uniform"], sets["adaptive"]
    for m, s in sets.items():
        row[m] = {"true": s["true"], "reported": s["reported"], "seconds": s["seconds"],
                  "efficiency": 1.0 / (s["true"] ** 2 * s["seconds"])}
    row["efficiency_ratio"] = row["adaptive"]["efficiency"] / row["uniform"]["efficiency"]
    row["error_ratio"] = a["true"] / u["true"]
    z = (a["mean"] - u["mean"]) / np.sqrt((a["var"] + u["var"]) / args.seeds + 1e-30)
    row["bias_pixels_z_above_4"] = float(np.mean(np.abs(z) > 4))
    row["mean_luminance_ratio"] = float(a["mean"].mean() / u["mean"].mean())
    if args.target:
        for m in MODES:
            t = render_set(args, name, scene, extra, out, m, ["--target-error", str(args.target)])
            row[m]["to_target_seconds"] = t["seconds"]
            row[m]["to_target_true"] = t["true"]
        row["time_to_target_ratio"] = row["adaptive"]["to_target_seconds"] / row["uniform"]["to_target_seconds"]
    return row


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--fredholm", default=os.path.join(REPO, "build", "fredholm"))
    p.add_argument("--size", type=int, default=96)
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--seeds", type=int, default=8)
    p.add_argument("--target", type=float, default=0.0, help="also render to this relative error")
    p.add_argument("--scene", action="append", help="NAME=PATH[,extra args] (default: error_calibration's set)")
    p.add_argument("--json")
    args = p.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as out:
        print(f"{'scene':16} {'true u':>8} {'true a':>8} {'s u':>6} {'s a':>6} {'eff a/u':>7} {'rep/true a':>10} "
              f"{'|z|>4':>6} {'mean a/u':>8}" + ("  to target: s u, s a (true u, true a)" if args.target else ""))
        for name, path, extra in scene_entries(args.scene or SCENES):
            r = compare(args, name, path, extra, out)
            rows.append(r)
            u, a = r["uniform"], r["adaptive"]
            line = (f"{name:16} {u['true']:8.4f} {a['true']:8.4f} {u['seconds']:6.2f} {a['seconds']:6.2f} "
                    f"{r['efficiency_ratio']:7.2f} {a['reported'] / a['true']:10.2f} "
                    f"{r['bias_pixels_z_above_4']:6.4f} {r['mean_luminance_ratio']:8.4f}")
            if args.target:
                line += (f"  {u['to_target_seconds']:.2f}, {a['to_target_seconds']:.2f} "
                         f"({u['to_target_true']:.4f}, {a['to_target_true']:.4f})")
            print(line, flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=2)


if __name__ == "__main__":
    sys.exit(main())
