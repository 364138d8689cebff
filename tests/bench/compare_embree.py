#!/usr/bin/env python3
"""Incoherent rays per second of Fredholm's extend stage against Embree 4 (PyPI embreex) on the same mesh and rays.

  /opt/refbench/mitsuba-venv/bin/python tests/bench/compare_embree.py SCENE.glb [--rays 1000000] [--repeats 3]
      [--order random|origin|direction-origin] [--sort-rays] [--opaque] [--any-hit] [--mitsuba]

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
render would; tests/bench/RESULTS.md "Ray order"), the sort's time counted in its rate; Embree traces them as given.
--any-hit traces shadow rays instead, as next-event estimation does: from a point uniform by area over the triangles
that do not emit, lifted off the surface towards the target, to a point uniform by area over the emitting triangles
(over all triangles in a scene without emission), ending 1e-4 of the distance short of it (the renderer's shadow
epsilon). Fredholm traces them through its connect stage (`bench --trace-rays FILE --any-hit`), Embree as occlusion
queries; both must agree on which rays are blocked.
--mitsuba also times Mitsuba 3's ray tracer on the same rays (`Scene.ray_intersect_preliminary`, or `Scene.ray_test`
with --any-hit; two threads, the median of --repeats after an untimed first call that compiles the kernel): the tracer
inside the renderer that `compare_efficiency.py` measures. Needs the Mitsuba venv.
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


def read_scene_triangles(path):
    """Every triangle of the scene's default scene graph in world space (every node's transform applied, as Fredholm
    loads it), as an (n, 3, 3) float32 array, and whether each one's material emits light."""
    try:
        meshes = load_gltf(path, need_camera=False)["meshes"]
    except (ValueError, KeyError, OSError) as e:
        raise SystemExit(f"compare_embree: {path}: {e}")
    triangles = np.concatenate([m["positions"][m["faces"]] for m in meshes]).astype(np.float32)
    emits = np.concatenate([np.full(len(m["faces"]), any(c > 0.0 for c in m["material"]["emission"])) for m in meshes])
    return triangles, emits


def read_triangles(path):
    return read_scene_triangles(path)[0]


def triangle_geometry(triangles):
    """Per triangle its two edges from vertex 0, its unit normal (winding order) and its area."""
    e1, e2 = triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]
    normals = np.cross(e1, e2).astype(np.float64)
    areas = 0.5 * np.linalg.norm(normals, axis=1)
    keep = areas > 0
    normals[keep] /= (2.0 * areas[keep])[:, None]
    return e1, e2, normals, areas


def sample_surface_points(triangles, geometry, candidates, count, rng):
    """Points uniform by area over the triangles whose indices are `candidates`, and their unit normals."""
    e1, e2, normals, areas = geometry
    weights = areas[candidates]
    pick = candidates[rng.choice(len(candidates), size=count, p=weights / weights.sum())]
    r1, r2 = np.sqrt(rng.random(count)), rng.random(count)
    b1, b2 = r1 * (1 - r2), r1 * r2
    points = triangles[pick, 0] + b1[:, None] * e1[pick] + b2[:, None] * e2[pick]
    return points, normals[pick]


def scene_size(triangles):
    return float(np.max(triangles.reshape(-1, 3).max(0) - triangles.reshape(-1, 3).min(0)))


def diffuse_rays(triangles, count, seed):
    rng = np.random.default_rng(seed)
    points, n = sample_surface_points(triangles, triangle_geometry(triangles), np.arange(len(triangles)), count, rng)
    origins = points + 1e-4 * scene_size(triangles) * n
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


def shadow_rays(triangles, emits, count, seed):
    """Next-event estimation's rays (see --any-hit): origins, unit directions and t_max."""
    rng = np.random.default_rng(seed)
    everything = np.arange(len(triangles))
    lights, others = (everything[emits], everything[~emits]) if emits.any() and not emits.all() else (everything, everything)
    geometry = triangle_geometry(triangles)
    points, n = sample_surface_points(triangles, geometry, others, count, rng)
    targets, _ = sample_surface_points(triangles, geometry, lights, count, rng)
    side = np.where(np.sum((targets - points) * n, axis=1) < 0.0, -1.0, 1.0)[:, None]
    origins = points + 1e-4 * scene_size(triangles) * side * n
    to_target = targets - origins
    length = np.linalg.norm(to_target, axis=1)
    keep = length > 1e-6 * scene_size(triangles)  # a target on the origin's own spot has no direction
    directions = to_target[keep] / length[keep, None]
    return (origins[keep].astype(np.float32), directions.astype(np.float32),
            (length[keep] * (1.0 - 1e-4)).astype(np.float32))


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


def time_embree(triangles, origins, directions, t_max, threads, repeats):
    """Median seconds of tracing every ray, and per ray its hit distance (inf: a miss), or with t_max (occlusion
    queries) 1 where it is blocked, 0 where not; and the build's seconds."""
    builds = [build_embree(triangles, origins, directions) for _ in range(repeats)]
    scene, build_seconds = builds[-1][0], float(np.median([b[1] for b in builds]))
    chunks = np.array_split(np.arange(len(origins)), threads)
    results = [None] * threads
    seconds = []
    for _ in range(repeats):
        def work(k):
            idx = chunks[k]
            if t_max is None:
                results[k] = scene.run(origins[idx], directions[idx], output=1)["tfar"]
            else:  # the id of the geometry that blocks the ray, -1 for none
                results[k] = (scene.run(origins[idx], directions[idx], dists=t_max[idx], query="OCCLUDED") != -1)
        start = time.perf_counter()
        workers = [threading.Thread(target=work, args=(k,)) for k in range(threads)]
        for w in workers:
            w.start()
        for w in workers:
            w.join()
        seconds.append(time.perf_counter() - start)
    out = np.concatenate(results)
    out = out.astype(np.float32) if t_max is not None else np.where(out > 1e30, np.inf, out)
    return float(np.median(seconds)), out, build_seconds


def time_mitsuba(triangles, origins, directions, t_max, threads, repeats):
    """Mitsuba 3's tracer (llvm_ad_rgb, as compare_efficiency.py renders with) over the same rays: median seconds and
    per ray what time_embree returns. The first call compiles the kernel and is not timed."""
    import drjit as dr
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    dr.set_thread_count(threads)
    mesh = mi.Mesh("mesh", 3 * len(triangles), len(triangles), has_vertex_normals=False)
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(triangles.reshape(-1).astype(np.float32))
    params["faces"] = mi.UInt32(np.arange(3 * len(triangles), dtype=np.uint32))
    params.update()
    scene = mi.load_dict({"type": "scene", "mesh": mesh})
    o, d = mi.Point3f(*(origins[:, k] for k in range(3))), mi.Vector3f(*(directions[:, k] for k in range(3)))
    ray = mi.Ray3f(o, d)
    if t_max is not None:
        ray.maxt = mi.Float(t_max)  # the constructor's third argument is the ray's time, not maxt
    dr.eval(ray)
    seconds, out = [], None
    for r in range(repeats + 1):
        dr.sync_thread()
        start = time.perf_counter()
        result = scene.ray_intersect_preliminary(ray).t if t_max is None else scene.ray_test(ray)
        dr.eval(result)
        dr.sync_thread()
        if r > 0:
            seconds.append(time.perf_counter() - start)
        out = np.array(result)
    if t_max is None:
        out = np.where(np.isfinite(out) & (out < 1e30), out, np.inf).astype(np.float32)
    else:
        out = out.astype(np.float32)
    return float(np.median(seconds)), out, mi.__version__


def agreement(kind, ours, theirs):
    """Where two tracers agree: the share of rays with the same answer (hit or miss; blocked or not), and for closest
    hits the relative difference of the hit distances where both hit (median, 99.9th percentile)."""
    if kind == "any-hit":
        return {"hit_agreement": float(np.mean(ours == theirs))}
    both = np.isfinite(ours) & np.isfinite(theirs)
    rel = np.abs(ours[both] - theirs[both]) / np.maximum(theirs[both], 1e-12)
    return {"hit_agreement": float(np.mean(np.isfinite(ours) == np.isfinite(theirs))),
            "relative_t_median": float(np.median(rel)), "relative_t_p999": float(np.quantile(rel, 0.999))}


def describe_agreement(kind, a):
    if kind == "any-hit":
        return f"blocked or not agree on {100 * a['hit_agreement']:.4f}% of rays"
    return (f"hit or miss agree on {100 * a['hit_agreement']:.4f}% of rays, hit distance relative difference median "
            f"{a['relative_t_median']:.2e}, 99.9th percentile {a['relative_t_p999']:.2e}")

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
    ap.add_argument("--any-hit", action="store_true",
                    help="shadow rays towards the emitting triangles, traced as occlusion queries (connect stage)")
    ap.add_argument("--mitsuba", action="store_true", help="also time Mitsuba 3's tracer on the same rays")
    ap.add_argument("--json", help="also write the figures here")
    args = ap.parse_args()
    if args.any_hit and args.sort_rays:
        ap.error("--sort-rays sorts extend's rays; the connect stage traces shadow rays in their order")
    kind = "any-hit" if args.any_hit else "closest-hit"
    triangles, emits = read_scene_triangles(args.scene)
    if args.any_hit:
        origins, directions, t_max = shadow_rays(triangles, emits, args.rays, args.seed)
    else:
        (origins, directions), t_max = diffuse_rays(triangles, args.rays, args.seed), None
    permutation = order_rays(origins, directions, args.order)
    origins, directions = origins[permutation], directions[permutation]
    columns = [origins, directions]
    if t_max is not None:
        t_max = t_max[permutation]
        columns.append(t_max[:, None])
    count = len(origins)
    with tempfile.TemporaryDirectory() as tmp:
        ray_file, hit_file, stats_file = (os.path.join(tmp, n) for n in ("rays.bin", "hits.bin", "stats.json"))
        np.concatenate(columns, axis=1).astype("<f4").tofile(ray_file)
        subprocess.run([args.fredholm, "bench", args.scene, "--trace-rays", ray_file, "--hits-out", hit_file,
                        "--repeats", str(args.repeats), "--json", stats_file, "--sort-rays", "on" if args.sort_rays else "off"]
                       + (["--disable-effect", "alpha"] if args.opaque else []) + (["--any-hit"] if args.any_hit else []),
                       check=True, stdout=subprocess.DEVNULL)
        fredholm_out = np.fromfile(hit_file, dtype="<f4")
        stats = json.load(open(stats_file))
    fredholm_rate = stats["rays_per_second"]
    embree_seconds, embree_out, embree_build = time_embree(triangles, origins, directions, t_max, args.threads,
                                                           args.repeats)
    embree_rate = count / embree_seconds
    rays_kind = "shadow rays (any hit)" if args.any_hit else "diffuse-bounce rays"
    print(f"scene {os.path.basename(args.scene)}: {len(triangles)} triangles, {count} {rays_kind}, order {args.order}")
    if args.any_hit:
        print(f"  {int(np.sum(fredholm_out))} of them blocked (Fredholm); mean t_max {float(np.mean(t_max)):.4g}")
    stage = "connect" if args.any_hit else "extend"
    print(f"fredholm {stage}: {fredholm_rate / 1e6:.3f} Mrays/s (median of {args.repeats}"
          f"{'; sorted on the device first, the sort timed too' if args.sort_rays else ''}"
          f"{'; alpha test compiled out, every triangle opaque' if args.opaque else ''})")
    print(f"embree {args.threads} thread(s): {embree_rate / 1e6:.3f} Mrays/s (median of {args.repeats})")
    embree_agreement = agreement(kind, fredholm_out, embree_out)
    print(f"fredholm / embree: {fredholm_rate / embree_rate:.3f}; {describe_agreement(kind, embree_agreement)}")
    figures = {"triangles": len(triangles), "rays": count, "kind": kind, "fredholm_rays_per_second": fredholm_rate,
               "embree_rays_per_second": embree_rate, "embree_threads": args.threads, "order": args.order,
               "fredholm_sorts_rays": args.sort_rays, "opaque": args.opaque, "ratio": fredholm_rate / embree_rate,
               **embree_agreement}
    if args.mitsuba:
        mitsuba_seconds, mitsuba_out, version = time_mitsuba(triangles, origins, directions, t_max, args.threads,
                                                             args.repeats)
        mitsuba_rate = count / mitsuba_seconds
        call = "ray_test" if args.any_hit else "ray_intersect_preliminary"
        print(f"mitsuba {version} llvm_ad_rgb {call}, {args.threads} thread(s): {mitsuba_rate / 1e6:.3f} Mrays/s "
              f"(median of {args.repeats})")
        mitsuba_agreement = agreement(kind, fredholm_out, mitsuba_out)
        print(f"fredholm / mitsuba: {fredholm_rate / mitsuba_rate:.3f}; {describe_agreement(kind, mitsuba_agreement)}")
        figures.update(mitsuba_rays_per_second=mitsuba_rate, mitsuba_version=version,
                       mitsuba_ratio=fredholm_rate / mitsuba_rate,
                       mitsuba_agreement=mitsuba_agreement)
    # Both builds timed alike: the median of --repeats builds in a warm process. Fredholm's first, cold build (the
    # one a render pays once) is printed beside it.
    fredholm_build, fredholm_cold = stats["bvh_build_seconds_median"], stats["bvh_build_seconds"]
    print(f"BVH build: fredholm {len(triangles) / fredholm_build / 1e6:.2f} M triangles/s ({fredholm_build:.4f} s, "
          f"median of {args.repeats}; the first build {fredholm_cold:.4f} s; two threads, binned SAH), embree "
          f"{len(triangles) / embree_build / 1e6:.2f} M triangles/s ({embree_build:.4f} s, median of {args.repeats}); "
          f"fredholm / embree {embree_build / fredholm_build:.3f}")
    if args.json:
        figures.update(fredholm_bvh_build_seconds=fredholm_build, fredholm_bvh_first_build_seconds=fredholm_cold,
                       embree_build_seconds=embree_build)
        with open(args.json, "w") as out:
            json.dump(figures, out, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
