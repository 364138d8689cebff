#!/usr/bin/env python3
"""What parity with Mitsuba 3 would take on one scene: Fredholm's render split into its tracing stages and the rest,
Mitsuba's render time, and both tracers on the same rays, measured back to back, with two projections from them.

  /opt/refbench/mitsuba-venv/bin/python tests/bench/project_parity.py [--scene scenes/cornell.gltf] [--spp 64]
      [--size 256] [--max-depth 10] [--renders 3] [--rays 1000000] [--repeats 5] [--fredholm build/fredholm]

Measures, in this order:
- `fredholm render SCENE --stats` --renders times (the median by render seconds is kept): the extend and connect
  stages' GPU seconds, the rest (shade, generate, advance, accumulate) and the rays each traced;
- Mitsuba 3's render of the same scene (compare_renderers.py, llvm_ad_rgb, multijitter, two threads, median of 3);
- `compare_embree.py --mitsuba`, closest hit and --any-hit: Fredholm's extend and connect stages against Mitsuba's own
  tracer (and Embree 4) on the same rays.
Then prints:
- Fredholm with its traversal at Mitsuba's rates: extend and connect scaled by the same-ray ratios, the rest as it is,
  against Mitsuba's render time;
- what Mitsuba's render has left besides tracing Fredholm's ray counts at its own rates (an upper bound if it traces
  at least as many rays per sample), against Fredholm's rest.
Both are estimates: the standalone rays are uniform diffuse bounces and shadow rays towards the lights, not the
render's own. tests/bench/RESULTS.md "Speed" ("Against Mitsuba's own tracer, and what parity with Mitsuba would take") has the figures.
Needs the Mitsuba venv with embreex (tests/bench/README.md).
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BENCH = os.path.join(REPO, "tests", "bench")


def render_fredholm(args, tmp):
    runs = []
    for k in range(args.renders):
        stats = os.path.join(tmp, f"stats_{k}.json")
        subprocess.run([args.fredholm, "render", args.scene, "-o", os.path.join(tmp, "fredholm.exr"), "--width",
                        str(args.size), "--height", str(args.size), "--spp", str(args.spp), "--max-depth",
                        str(args.max_depth), "--stats", stats, "--quiet"], check=True)
        with open(stats) as f:
            runs.append(json.load(f))
    runs.sort(key=lambda s: s["render_seconds"])
    return runs[len(runs) // 2]


def render_mitsuba(args):
    out = subprocess.run([sys.executable, os.path.join(BENCH, "compare_renderers.py"), "--renderer", "mitsuba",
                          "--scene", args.scene, "--size", str(args.size), "--spp", str(args.spp), "--max-depth",
                          str(args.max_depth), "--repeats", "3", "--threads", "2", "--mitsuba-sampler", "multijitter"],
                         check=True, capture_output=True, text=True).stdout
    return float(re.search(r"seconds_median ([0-9.]+)", out).group(1))


def trace_same_rays(args, tmp, any_hit):
    figures = os.path.join(tmp, f"rays_{int(any_hit)}.json")
    subprocess.run([sys.executable, os.path.join(BENCH, "compare_embree.py"), args.scene, "--fredholm", args.fredholm,
                    "--rays", str(args.rays), "--repeats", str(args.repeats), "--mitsuba", "--json", figures]
                   + (["--any-hit"] if any_hit else []), check=True, stdout=subprocess.DEVNULL)
    with open(figures) as f:
        return json.load(f)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default=os.path.join(REPO, "scenes", "cornell.gltf"))
    ap.add_argument("--fredholm", default=os.path.join(REPO, "build", "fredholm"))
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--max-depth", type=int, default=10)
    ap.add_argument("--renders", type=int, default=3, help="Fredholm renders; the median is kept")
    ap.add_argument("--rays", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=5, help="timed traces of the same rays per tracer")
    ap.add_argument("--json", help="also write the figures here")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        stats = render_fredholm(args, tmp)
        mitsuba_seconds = render_mitsuba(args)
        closest, shadow = trace_same_rays(args, tmp, False), trace_same_rays(args, tmp, True)
    stages = stats["stage_seconds"]
    extend, connect = stages.get("extend", 0.0), stages.get("connect", 0.0)
    total = stats["render_seconds"]
    rest = total - extend - connect
    closest_ratio = closest["fredholm_rays_per_second"] / closest["mitsuba_rays_per_second"]
    any_ratio = shadow["fredholm_rays_per_second"] / shadow["mitsuba_rays_per_second"]
    traced, shadow_rays = stats["traced_rays"], stats["traced_shadow_rays"]
    print(f"scene {os.path.basename(args.scene)}, {args.size} x {args.size}, {args.spp} spp, max depth {args.max_depth}")
    print(f"fredholm render {total:.3f} s (median of {args.renders}): extend {extend:.3f} s ({traced / 1e6:.2f} M rays), "
          f"connect {connect:.3f} s ({shadow_rays / 1e6:.2f} M shadow rays), the rest {rest:.3f} s")
    print(f"mitsuba render {mitsuba_seconds:.3f} s (median of 3): fredholm / mitsuba time {total / mitsuba_seconds:.2f}x")
    for name, f in (("closest hit", closest), ("any hit", shadow)):
        print(f"same rays, {name}: fredholm {f['fredholm_rays_per_second'] / 1e6:.2f}, embree 4 "
              f"{f['embree_rays_per_second'] / 1e6:.2f}, mitsuba {f['mitsuba_rays_per_second'] / 1e6:.2f} Mrays/s; "
              f"fredholm / mitsuba {f['fredholm_rays_per_second'] / f['mitsuba_rays_per_second']:.3f}")
    projected = rest + extend * closest_ratio + connect * any_ratio
    mitsuba_tracing = traced / closest["mitsuba_rays_per_second"] + shadow_rays / shadow["mitsuba_rays_per_second"]
    mitsuba_rest = mitsuba_seconds - mitsuba_tracing
    print(f"fredholm with its traversal at mitsuba's rates: {projected:.3f} s, {projected / mitsuba_seconds:.2f}x "
          f"mitsuba's time")
    print(f"fredholm's rays at mitsuba's rates: {mitsuba_tracing:.3f} s, leaving mitsuba {mitsuba_rest:.3f} s for the "
          f"rest, against fredholm's {rest:.3f} s ({rest / mitsuba_rest:.1f}x)" if mitsuba_rest > 0 else
          f"fredholm's rays at mitsuba's rates: {mitsuba_tracing:.3f} s, more than mitsuba's whole render")
    if args.json:
        with open(args.json, "w") as out:
            json.dump({"scene": args.scene, "size": args.size, "spp": args.spp, "max_depth": args.max_depth,
                       "fredholm_seconds": total, "extend_seconds": extend, "connect_seconds": connect,
                       "rest_seconds": rest, "traced_rays": traced, "traced_shadow_rays": shadow_rays,
                       "mitsuba_seconds": mitsuba_seconds, "closest": closest, "any": shadow,
                       "projected_seconds": projected, "mitsuba_tracing_seconds": mitsuba_tracing}, out, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
