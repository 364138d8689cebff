#!/usr/bin/env python3
"""The error of a region of the image against render time, from a `fredholm converge --keep-images` report.

converge measures the whole image, where a few bright pixels that every integrator finds hard can hide what one of
them does better elsewhere (a caustic seen through the glass that casts it, shaders/lib/integrator/README.md "Vertex
connection and merging"). This takes the report's kept images and its times (convergence.csv) and prints, per
configuration, the relMSE of a pixel rectangle at each step (converge's definition: mean (x - r)^2 / (r^2 + 0.01)
over the rectangle's pixels and channels) and the time to each target, interpolated in log-log between steps as
converge does (extrapolated along 1 / seconds past the last step, marked ~).

Needs PyPI OpenEXR and numpy (the Mitsuba venv of tests/bench/README.md has both):

  fredholm converge scenes/water_glass.gltf -o report --keep-images --max-depth 12 --vary integrator=path,bdpt,vcm \\
      --reference ref.exr --width 128 --height 96
  /opt/refbench/mitsuba-venv/bin/python tests/bench/region_error.py report ref.exr --rect 52,30,76,62
"""
import argparse
import csv
import math
from pathlib import Path

import numpy as np
import OpenEXR


def read_rgb(path):
    with OpenEXR.File(str(path)) as f:
        channels = f.channels()
        rgb = channels["RGB"].pixels if "RGB" in channels else channels["RGBA"].pixels[..., :3]
        return np.array(rgb, dtype=np.float64)


def slug(name):
    return name.replace("=", "-").replace(":", "-")


def time_to(target, steps):
    """Seconds at which the relMSE reaches target: log-log between the steps around it, or ~ past the last."""
    for (s0, e0), (s1, e1) in zip(steps, steps[1:]):
        if e0 > target >= e1 and e1 > 0:
            t = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return f"{math.exp(math.log(s0) + t * (math.log(s1) - math.log(s0))):.3g} s"
    if steps and steps[-1][1] <= target:
        return f"{steps[0][0]:.3g} s (at the first step)"
    seconds, error = steps[-1]
    return f"~{seconds * error / target:.3g} s"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("report", type=Path, help="converge's report directory (run with --keep-images)")
    parser.add_argument("reference", type=Path, help="the reference EXR converge was given")
    parser.add_argument("--rect", required=True, help="x0,y0,x1,y1: pixel columns [x0, x1) and rows [y0, y1)")
    parser.add_argument("--targets", default="0.01,0.005", help="relMSE targets (default 0.01,0.005)")
    args = parser.parse_args()
    x0, y0, x1, y1 = (int(v) for v in args.rect.split(","))
    targets = [float(v) for v in args.targets.split(",")]
    reference = read_rgb(args.reference)[y0:y1, x0:x1]
    rows = list(csv.DictReader(open(args.report / "convergence.csv")))
    print(f"region columns [{x0}, {x1}) rows [{y0}, {y1}) of {args.reference.name}")
    for config in dict.fromkeys(r["config"] for r in rows):
        steps = []
        for r in (r for r in rows if r["config"] == config):
            image = args.report / "images" / f"{slug(config)}_spp{int(r['spp']):05d}.exr"
            if not image.exists():
                raise SystemExit(f"region_error: {image}: missing (run converge with --keep-images)")
            x = read_rgb(image)[y0:y1, x0:x1]
            steps.append((float(r["seconds"]), float(np.mean((x - reference) ** 2 / (reference ** 2 + 0.01)))))
        last_seconds, last_error = steps[-1]
        times = ", ".join(f"t({100 * t:g}%) {time_to(t, steps)}" for t in targets)
        print(f"{config:24s} {len(steps)} steps, last {last_seconds:.3g} s: region relMSE {last_error:.4g}; {times}")


if __name__ == "__main__":
    main()
