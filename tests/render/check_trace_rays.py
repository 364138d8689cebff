#!/usr/bin/env python3
"""`fredholm bench --trace-rays` with and without the alpha test (`--disable-effect alpha`), closest and any hit.

  check_trace_rays.py FREDHOLM env_plane_cutouts.gltf OUT_DIR

The scene (make_asset_scenes.py) is a floor at z = 0 under three planes at z = 0.4, 0.8 and 1.2 that MASK cuts out
entirely. Rays cast straight down from z = 2 must pass the three planes and hit the floor at t = 2 with the alpha
test, and hit the top plane at t = 0.8 without it (every triangle opaque, as Embree sees them in
tests/bench/compare_embree.py --opaque). Both runs must count no escaped ray.
The same rays as shadow rays (`--any-hit`, the connect stage): ending at t = 1.9, above the floor, none is blocked with
the alpha test and every one without it; ending at t = 2.5, below the floor, every one is blocked.
"""
import os
import re
import struct
import subprocess
import sys


def trace(fredholm, scene, rays_file, hits_file, extra):
    out = subprocess.run([fredholm, "bench", scene, "--trace-rays", rays_file, "--hits-out", hits_file,
                          "--repeats", "1", "--sort-rays", "off"] + extra,
                         check=True, capture_output=True, text=True).stdout
    escaped = int(re.search(r"(\d+) escaped", out).group(1))
    with open(hits_file, "rb") as f:
        data = f.read()
    return list(struct.unpack(f"<{len(data) // 4}f", data)), escaped


def trace_shadows(fredholm, scene, rays_file, hits_file, extra):
    out = subprocess.run([fredholm, "bench", scene, "--trace-rays", rays_file, "--any-hit", "--hits-out", hits_file,
                          "--repeats", "1"] + extra, check=True, capture_output=True, text=True).stdout
    occluded = int(re.search(r"(\d+) occluded", out).group(1))
    with open(hits_file, "rb") as f:
        data = f.read()
    return list(struct.unpack(f"<{len(data) // 4}f", data)), occluded


def main():
    fredholm, scene, out_dir = sys.argv[1:4]
    os.makedirs(out_dir, exist_ok=True)
    rays_file = os.path.join(out_dir, "trace_rays_cutouts.bin")
    n = 16
    rays = []
    for j in range(n):
        for i in range(n):
            x, y = -5.0 + 10.0 * (i + 0.5) / n, -5.0 + 10.0 * (j + 0.37) / n
            rays += [x, y, 2.0, 0.0, 0.0, -1.0]
    with open(rays_file, "wb") as f:
        f.write(struct.pack(f"<{len(rays)}f", *rays))
    failures = 0
    for name, extra, expected in (("alpha test", [], 2.0), ("--disable-effect alpha", ["--disable-effect", "alpha"], 0.8)):
        t, escaped = trace(fredholm, scene, rays_file, os.path.join(out_dir, "trace_rays_hits.bin"), extra)
        worst = max(abs(v - expected) for v in t)
        ok = len(t) == n * n and worst < 1e-5 and escaped == 0
        print(f"{name}: {len(t)} rays, expected t = {expected}, largest difference {worst:.3g}, {escaped} escaped: "
              f"{'PASS' if ok else 'FAIL'}")
        failures += 0 if ok else 1
    shadow_file = os.path.join(out_dir, "trace_rays_cutouts_shadow.bin")
    for name, extra, t_max, expected in (("alpha test", [], 1.9, 0.0),
                                         ("--disable-effect alpha", ["--disable-effect", "alpha"], 1.9, 1.0),
                                         ("alpha test, through the floor", [], 2.5, 1.0)):
        shadows = []
        for k in range(n * n):
            shadows += rays[6 * k:6 * k + 6] + [t_max]
        with open(shadow_file, "wb") as f:
            f.write(struct.pack(f"<{len(shadows)}f", *shadows))
        blocked, occluded = trace_shadows(fredholm, scene, shadow_file, os.path.join(out_dir, "trace_rays_blocked.bin"),
                                          extra)
        ok = len(blocked) == n * n and all(b == expected for b in blocked) and occluded == int(expected) * n * n
        print(f"any hit, {name}, t_max {t_max}: {len(blocked)} rays, {occluded} blocked, expected "
              f"{int(expected) * n * n}: {'PASS' if ok else 'FAIL'}")
        failures += 0 if ok else 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
