#!/usr/bin/env python3
"""Incoherent rays per second of Fredholm's extend stage against Embree 4 (PyPI embreex) on the same mesh and rays.

  /opt/refbench/mitsuba-venv/bin/python tests/bench/compare_embree.py SCENE.glb [--rays 1000000] [--repeats 3]
      [--order random|origin|direction-origin] [--sort-rays] [--opaque]

The rays are diffuse bounces: origins uniform by area over every triangle of the scene, lifted off the surface by
1e-4 of the scene's size, directions cosine-distributed about the triangle's normal (the side its winding faces); no
two rays are alike and neighbours in the list are unrelated, as a path tracer's second bounce is. Both tracers get
exactly these rays (Fredholm: `fredholm bench SCENE --trace-rays FILE`, which times the extend stage alone on the
device; Embree: `EmbreeScene.run` of the whole array, one call per thread, wall clock), and their hit distances are
compared ray by ray (they must agree: the same mesh, the same rays). Reads .gltf and .glb files (node transforms applied;
not Draco, meshopt or quantised meshes), such as tests/bench/make_displaced_sphere.py's spheres and the Khronos sample
models. Alpha-tested materials make Fredholm pass through cut-out texels, which Embree does not: those rays disagree.
--opaque has Fredholm compile its alpha test out (`--disable-effect alpha`): both tracers then see every triangle as
opaque, do the same work and agree on every ray.
--order sorts the rays on the host before either tracer sees them (the sort is not timed), to measure what a coherent
ray order would buy: by the Morton code of the origin, or by a direction cell (16 x 16 x 16 over the unit cube) and
then the origin's Morton code. --sort-rays has Fredholm sort the rays on the device first (`--sort-rays on`, as a
render would; README "Ray order"), the sort's time counted in its rate; Embree traces them as given.
Needs numpy and embreex (tests/bench/README.md).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np
from embreex import rtcore_scene
from embreex.mesh_construction import TriangleMesh

from compare_renderers import load_gltf

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def read_triangles(path):
    """Every triangle of the scene's default scene graph in world space (every node's transform applied, as Fredholm
    loads it), as an (n, 3, 3) float32 array."""
    try:
        meshes = load_gltf(path, need_camera=False)["meshes"]
    except (ValueError, KeyError, OSError) as e:
        raise SystemExit(f"compare_embree: {path}: {e}")
    return np.concatenate([m["positions"][m["faces"]] for m in meshes]).astype(np.float32)


def diffuse_rays(triangles, count, seed):
    rng = np.random.default_rng(seed)
    e1, e2 = triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]
    normals = np.cross(e1, e2).astype(np.float64)
    areas = 0.5 * np.linalg.norm(normals, axis=1)
    keep = areas > 0
    normals[keep] /= (2.0 * areas[keep])[:, None]
    pick = rng.choice(len(triangles), size=count, p=areas / areas.sum())
    r1, r2 = np.sqrt(rng.random(count)), rng.random(count)
    b1, b2 = r1 * (1 - r2), r1 * r2
    points = triangles[pick, 0] + b1[:, None] * e1[pick] + b2[:, None] * e2[pick]
    n = normals[pick]
    size = float(np.max(triangles.reshape(-1, 3).max(0) - triangles.reshape(-1, 3).min(0)))
    origins = points + 1e-4 * size * n
    # Cosine-weighted directions about n (Malley's method in a frame built around n).
    u1, u2 = rng.random(count), rng.random(count)
    radius, phi = np.sqrt(u1), 2.0 * np.pi * u2
    local = np.stack([radius * np.cos(phi), radius * np.sin(phi), np.sqrt(np.maximum(0.0, 1.0 - u1))], axis=1)
    helper = np.where(np.abs(n[:, :1]) > 0.9, np.array([[0.0, 1.0, 0.0]]), np.array([[1.0, 0.0, 0.0]]))
    t = np.cross(helper, n)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    b = np.cross(n, t)
    directions = local[:, :1] * t + local[:, 1:2] * b + local[:, 2:3] * n
    return origins.astype(np.float32), directions.astype(np.float32)


def morton_code(cells, bits):
    """Interleaves the bits of three integer coordinates (each below 2^bits) into one key per row."""
    code = np.zeros(len(cells), dtype=np.uint64)
    for bit in range(bits):
        for axis in range(3):
            code |= ((cells[:, axis].astype(np.uint64) >> np.uint64(bit)) & np.uint64(1)) << np.uint64(3 * bit + axis)
    return code


def order_rays(origins, directions, order):
    """The permutation that puts the rays in the given order ("random": as generated)."""
    if order == "random":
        return np.arange(len(origins))
    lo, hi = origins.min(0), origins.max(0)
    key = morton_code(((origins - lo) / np.maximum(hi - lo, 1e-30) * 1023).astype(np.int64), 10)
    if order == "direction-origin":
        key |= morton_code(((directions * 0.5 + 0.5) * 15.999).astype(np.int64), 4) << np.uint64(30)
    return np.argsort(key, kind="stable")


def build_embree(triangles, origins, directions):
    """Embree's scene with its BVH built, and the seconds of the build alone: the first run commits the scene
    (Embree's default build quality, all threads). Handing the mesh over is left out: embreex copies it in Python,
    which takes longer than the build."""
    scene = rtcore_scene.EmbreeScene()
    vertices = triangles.reshape(-1, 3)
    TriangleMesh(scene, vertices, np.arange(len(vertices), dtype=np.int32).reshape(-1, 3))
    start = time.perf_counter()
    scene.run(origins[:1], directions[:1], output=1)
    return scene, time.perf_counter() - start


def time_embree(triangles, origins, directions, threads, repeats):
    builds = [build_embree(triangles, origins, directions) for _ in range(repeats)]
    scene, build_seconds = builds[-1][0], float(np.median([b[1] for b in builds]))
    chunks = np.array_split(np.arange(len(origins)), threads)
    results = [None] * threads
    seconds = []
    for _ in range(repeats):
        def work(k):
            idx = chunks[k]
            results[k] = scene.run(origins[idx], directions[idx], output=1)["tfar"]
        start = time.perf_counter()
        workers = [threading.Thread(target=work, args=(k,)) for k in range(threads)]
        for w in workers:
            w.start()
        for w in workers:
            w.join()
        seconds.append(time.perf_counter() - start)
    tfar = np.concatenate(results)
    return float(np.median(seconds)), np.where(tfar > 1e30, np.inf, tfar), build_seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--fredholm", default=os.path.join(REPO, "build", "fredholm"))
    ap.add_argument("--rays", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2, help="Embree threads (default: the machine's 2 cores)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--order", choices=["random", "origin", "direction-origin"], default="random",
                    help="ray order both tracers get (default: as generated, unrelated neighbours)")
    ap.add_argument("--sort-rays", action="store_true",
                    help="Fredholm sorts the rays on the device before tracing them, the sort timed with the trace")
    ap.add_argument("--opaque", action="store_true",
                    help="Fredholm without its alpha test (--disable-effect alpha), every triangle opaque as for Embree")
    ap.add_argument("--json", help="also write the figures here")
    args = ap.parse_args()
    triangles = read_triangles(args.scene)
    origins, directions = diffuse_rays(triangles, args.rays, args.seed)
    permutation = order_rays(origins, directions, args.order)
    origins, directions = origins[permutation], directions[permutation]
    with tempfile.TemporaryDirectory() as tmp:
        ray_file, hit_file, stats_file = (os.path.join(tmp, n) for n in ("rays.bin", "hits.bin", "stats.json"))
        np.concatenate([origins, directions], axis=1).astype("<f4").tofile(ray_file)
        subprocess.run([args.fredholm, "bench", args.scene, "--trace-rays", ray_file, "--hits-out", hit_file,
                        "--repeats", str(args.repeats), "--json", stats_file, "--sort-rays", "on" if args.sort_rays else "off"]
                       + (["--disable-effect", "alpha"] if args.opaque else []),
                       check=True, stdout=subprocess.DEVNULL)
        fredholm_t = np.fromfile(hit_file, dtype="<f4")
        stats = json.load(open(stats_file))
    fredholm_rate = stats["rays_per_second"]
    embree_seconds, embree_t, embree_build = time_embree(triangles, origins, directions, args.threads, args.repeats)
    embree_rate = args.rays / embree_seconds
    both = np.isfinite(fredholm_t) & np.isfinite(embree_t)
    agree_hit = float(np.mean(np.isfinite(fredholm_t) == np.isfinite(embree_t)))
    rel = np.abs(fredholm_t[both] - embree_t[both]) / np.maximum(embree_t[both], 1e-12)
    print(f"scene {os.path.basename(args.scene)}: {len(triangles)} triangles, {args.rays} diffuse-bounce rays, "
          f"order {args.order}")
    print(f"fredholm extend: {fredholm_rate / 1e6:.3f} Mrays/s (median of {args.repeats}"
          f"{'; sorted on the device first, the sort timed too' if args.sort_rays else ''}"
          f"{'; alpha test compiled out, every triangle opaque' if args.opaque else ''})")
    print(f"embree {args.threads} thread(s): {embree_rate / 1e6:.3f} Mrays/s (median of {args.repeats})")
    print(f"fredholm / embree: {fredholm_rate / embree_rate:.3f}; hit or miss agree on {100 * agree_hit:.4f}% of rays, "
          f"hit distance relative difference median {np.median(rel):.2e}, 99.9th percentile {np.quantile(rel, 0.999):.2e}")
    # Both builds timed alike: the median of --repeats builds in a warm process. Fredholm's first, cold build (the
    # one a render pays once) is printed beside it.
    fredholm_build, fredholm_cold = stats["bvh_build_seconds_median"], stats["bvh_build_seconds"]
    print(f"BVH build: fredholm {len(triangles) / fredholm_build / 1e6:.2f} M triangles/s ({fredholm_build:.4f} s, "
          f"median of {args.repeats}; the first build {fredholm_cold:.4f} s; two threads, binned SAH), embree "
          f"{len(triangles) / embree_build / 1e6:.2f} M triangles/s ({embree_build:.4f} s, median of {args.repeats}); "
          f"fredholm / embree {embree_build / fredholm_build:.3f}")
    if args.json:
        with open(args.json, "w") as out:
            json.dump({"triangles": len(triangles), "rays": args.rays, "fredholm_rays_per_second": fredholm_rate,
                       "embree_rays_per_second": embree_rate, "embree_threads": args.threads, "order": args.order,
                       "fredholm_sorts_rays": args.sort_rays, "opaque": args.opaque, "ratio": fredholm_rate / embree_rate,
                       "hit_agreement": agree_hit, "relative_t_median": float(np.median(rel)),
                       "fredholm_bvh_build_seconds": fredholm_build,
                       "fredholm_bvh_first_build_seconds": fredholm_cold, "embree_build_seconds": embree_build}, out, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
