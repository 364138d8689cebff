#!/usr/bin/env python3
"""What fredholm-ray costs and gains: one image rendered by a single `fredholm render` and by fredholm-ray on a Ray
cluster of 1 and 2 worker nodes (started here, on this machine, and warm before anything is timed).

Model, with K chunks on N worker nodes of one task slot each:

  T(N) = t_start_up + ceil(K / N) * (t_task + t_chunk)

  t_chunk    = single-process render time / K (that time includes fredholm's own start-up: device, scene, pipelines)
  t_task     = time of a 1-sample chunk run right after another on the same worker (Ray scheduling, scene
               unpacking, fredholm start-up and one sample, the part back): the gap between the two progress lines
               of an --spp 2 --chunks 2 run on one worker node
  t_start_up = wall time of that run minus 2 t_task (Python and Ray start, connect, ship the scene, start the
               run's worker processes (Ray starts them per run), merge)

fredholm's start-up is counted in t_task and again, divided by K, in t_chunk; with large K that is small. Every time
is the median of --repeats runs, after one untimed run. Nodes on one machine share its CPUs and GPU: with
--lavapipe-threads 1 (LP_NUM_THREADS for the single process and every node) each node renders on one core, so on a
2-core machine N = 1 and N = 2 stand for one and two 1-core machines and the speed-up can be checked; without it
both nodes share all cores and N = 2 measures the overheads only. Each measured line also prints the t_task that
would make the model exact for it.

  /opt/ray-venv/bin/python tests/bench/ray_overhead.py --fredholm build/fredholm [--scene scenes/cornell.gltf]
      [--width 256 --height 256 --spp 256 --chunks 8] [--render-args "--max-depth 8"] [--repeats 3]
"""
import argparse
import math
import os
import re
import shlex
import statistics
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "tests", "cluster"))
from local_cluster import LocalCluster, make_client_env  # noqa: E402

PACKAGE_DIR = os.path.join(REPO, "engine", "cluster")


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--fredholm", required=True)
    p.add_argument("--scene", default=os.path.join(REPO, "scenes", "cornell.gltf"))
    p.add_argument("--width", type=int, default=256)
    p.add_argument("--height", type=int, default=256)
    p.add_argument("--spp", type=int, default=256)
    p.add_argument("--chunks", type=int, default=8)
    p.add_argument("--render-args", default="", help="more render options, e.g. '--max-depth 8'")
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--ray", help="ray command (default: the one beside this Python)")
    p.add_argument("--lavapipe-threads", type=int, help="LP_NUM_THREADS for every render (one core per node: 1)")
    return p.parse_args()


def run_timed(command, env=None):
    began = time.monotonic()
    result = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env)
    seconds = time.monotonic() - began
    if result.returncode != 0:
        sys.exit(f"ray_overhead: failed: {shlex.join(command)}: {result.stderr.strip()}")
    return seconds, result.stderr


def time_single(args, workdir):
    command = [args.fredholm, "render", args.scene, "-o", os.path.join(workdir, "single.exr"), "--spp",
               str(args.spp), "-q", "--width", str(args.width), "--height", str(args.height)]
    command += shlex.split(args.render_args)
    run_timed(command, render_env(args))  # warm-up: driver caches, files
    return statistics.median(run_timed(command, render_env(args))[0] for _ in range(args.repeats))


def render_env(args, base=None):
    env = dict(base if base is not None else os.environ)
    if args.lavapipe_threads:
        env["LP_NUM_THREADS"] = str(args.lavapipe_threads)
    return env


def fredholm_ray_command(args, address, spp, chunks, output):
    return [sys.executable, "-m", "fredholm_ray", "render", args.scene, "-o", output, "--spp", str(spp),
            "--chunks", str(chunks), "--address", address, "--fredholm", args.fredholm, "--width", str(args.width),
            "--height", str(args.height)] + shlex.split(args.render_args)


def time_fredholm_ray(args, cluster, spp, chunks, workdir):
    """Median wall time of fredholm-ray runs, and (for a 2-chunk run) the median time between the two chunks."""
    env = make_client_env(cluster)
    env["PYTHONPATH"] = PACKAGE_DIR + os.pathsep + os.environ.get("PYTHONPATH", "")
    command = fredholm_ray_command(args, cluster.address, spp, chunks, os.path.join(workdir, "ray.exr"))
    run_timed(command, env)  # warm-up: Ray starts its worker processes
    walls, tasks = [], []
    for _ in range(args.repeats):
        wall, log = run_timed(command, env)
        walls.append(wall)
        first = re.search(r"1/2 chunks done, ([\d.]+) s", log)
        second = re.search(r"2/2 chunks done, ([\d.]+) s", log)
        if first and second:
            tasks.append(float(second.group(1)) - float(first.group(1)))
    return statistics.median(walls), (statistics.median(tasks) if tasks else None)


def main():
    args = parse_args()
    args.fredholm = os.path.abspath(args.fredholm)
    args.scene = os.path.abspath(args.scene)
    ray_cli = args.ray or os.path.join(os.path.dirname(sys.executable), "ray")
    with tempfile.TemporaryDirectory(prefix="fh-ray-bench-", dir="/tmp") as workdir:
        t_single = time_single(args, workdir)
        k = args.chunks
        print(f"image {args.width}x{args.height}, {args.spp} spp, {k} chunks, {args.scene}; median of "
              f"{args.repeats}; LP_NUM_THREADS {args.lavapipe_threads or 'unset'}")
        print(f"single-process fredholm render: {t_single:.2f} s")
        cluster = LocalCluster(ray_cli, os.path.join(workdir, "ray"), workdir, workers=1,
                               env=render_env(args, dict(os.environ, TMPDIR=workdir)))
        with cluster:
            wall_two, t_task = time_fredholm_ray(args, cluster, 2, 2, workdir)
            if t_task is None:
                sys.exit("ray_overhead: no progress lines in fredholm-ray's output to time a task by")
            t_start_up = wall_two - 2 * t_task
            t_chunk = t_single / k
            print(f"t_start_up {t_start_up:.2f} s, t_task {t_task:.2f} s (1-sample chunk), "
                  f"t_chunk {t_chunk:.2f} s (single / K)")
            for nodes in (1, 2):
                if nodes == 2:
                    cluster.add_worker()
                measured, _ = time_fredholm_ray(args, cluster, args.spp, k, workdir)
                predicted = t_start_up + math.ceil(k / nodes) * (t_task + t_chunk)
                print(f"N={nodes} worker node(s): predicted {predicted:.2f} s, measured {measured:.2f} s "
                      f"({measured / predicted - 1:+.0%}), speed-up over single process {t_single / measured:.2f}x")
                implied = (measured - t_start_up) / math.ceil(k / nodes) - t_chunk
                print(f"    t_task that would make the model exact: {implied:.2f} s")


if __name__ == "__main__":
    main()
