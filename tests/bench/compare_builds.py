#!/usr/bin/env python3
"""Paired timing of two Fredholm commands (two builds, or one build with two option sets), for changes of a few percent.

This machine's speed drifts by up to 1.5x within minutes, more than such a change, so medians of separate runs cannot
resolve it. Here each pair runs A and B back to back, in alternating order, and the figure is the median over the
pairs of B's time over A's (below 1: B faster), with how many pairs B won. A stage the change does not touch is the
control: its ratio shows the pairs' own noise.

Each command is a `fredholm bench ... --repeats 1` (its one size row is parsed) or a `fredholm render ...` (run with
--stats; its render_seconds and stage_seconds are read). Standard library only. Example (tests/bench/RESULTS.md "Speed"):

  python3 tests/bench/compare_builds.py --pairs 12 \\
      "/tmp/old/fredholm bench scenes/cornell.gltf --sizes 256 --spp 32 --max-depth 10 --repeats 1" \\
      "build/fredholm bench scenes/cornell.gltf --sizes 256 --spp 32 --max-depth 10 --repeats 1"
"""
import argparse
import json
import os
import re
import shlex
import statistics
import subprocess
import sys
import tempfile


def run(command, stats_path):
    """Total seconds and seconds per stage of one run."""
    words = shlex.split(command)
    if "render" in words:
        subprocess.run(words + ["--stats", stats_path, "--quiet"], check=True)
        with open(stats_path) as f:
            stats = json.load(f)
        return {"total": stats["render_seconds"], **stats["stage_seconds"]}
    out = subprocess.run(words, check=True, capture_output=True, text=True).stdout
    rows = [line.split() for line in out.splitlines() if re.match(r"\s*\d+x\d+\s", line)]
    if len(rows) != 1:
        sys.exit(f"compare_builds: expected one size row from: {command}")
    row = rows[0]  # size, disabled, seconds, Msamples/s, Mrays/s, then stage / seconds pairs
    return {"total": float(row[2]), **dict(zip(row[5::2], map(float, row[6::2])))}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=10)
    parser.add_argument("a", help="command A (the reference)")
    parser.add_argument("b", help="command B")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        stats_path = os.path.join(tmp, "stats.json")
        pairs = []
        for k in range(args.pairs):
            if k % 2 == 0:
                a = run(args.a, stats_path)
                b = run(args.b, stats_path)
            else:
                b = run(args.b, stats_path)
                a = run(args.a, stats_path)
            pairs.append((a, b))
    keys = [key for key in pairs[0][0] if all(key in a and key in b for a, b in pairs)]
    for key in keys:
        ratios = [b[key] / a[key] for a, b in pairs if a[key] > 0]
        if not ratios:
            continue
        print(f"{key:12} A median {statistics.median(a[key] for a, _ in pairs):8.3f} s   "
              f"B median {statistics.median(b[key] for _, b in pairs):8.3f} s   "
              f"B/A paired median {statistics.median(ratios):.3f} (min {min(ratios):.3f}, max {max(ratios):.3f}); "
              f"B faster in {sum(r < 1 for r in ratios)} of {len(ratios)}")


if __name__ == "__main__":
    main()
