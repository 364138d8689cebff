#!/usr/bin/env python3
"""Soak tests (README.md here): long runs whose memory must stay flat, outside CI.

  soak.py frames --fredholm build/fredholm [--frames 1000]     a --frames sequence, memory per frame from --stats
  soak.py viewer --fredholm build/fredholm [--frames 5000]     the viewer under Xvfb, camera moving all the time

Each prints its memory curve (host resident set, device memory and allocations), writes it as CSV beside its images,
and exits 1 when memory grows: host by more than --host-growth MiB over the run by the trend of its resident set
after the first tenth, or device memory by anything at all (first frame against last).
"""
import argparse
import csv
import glob
import json
import os
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
MIB = 1 << 20


def make_animated_scene(folder):
    """The square the render tests animate (tests/render/scenes/make_camera_scenes.py anim_square.gltf)."""
    subprocess.run([sys.executable, os.path.join(ROOT, "tests", "render", "scenes", "make_camera_scenes.py"), folder],
                   check=True, stdout=subprocess.DEVNULL)
    return os.path.join(folder, "anim_square.gltf")


def print_curve(rows, columns, marks):
    print("  " + "  ".join(f"{c:>16}" for c in columns))
    for row in rows:
        if row[0] in marks:
            print("  " + "  ".join(f"{row[i]:>16}" for i in range(len(columns))))


def judge(label, points, device_first, device_last, host_growth_mib):
    """points: (x, host resident bytes) after warm-up. The resident set swings by tens of MiB as the allocator and the
    driver reuse memory, so the verdict is on its trend: the least-squares slope over the run, times the run's length."""
    n = len(points)
    mean_x = sum(x for x, _ in points) / n
    mean_y = sum(y for _, y in points) / n
    spread = sum((x - mean_x) ** 2 for x, _ in points)
    slope = sum((x - mean_x) * (y - mean_y) for x, y in points) / spread if spread > 0 else 0.0
    trend = slope * (points[-1][0] - points[0][0]) / MIB
    low, high = min(y for _, y in points) / MIB, max(y for _, y in points) / MIB
    print(f"{label}: host resident {low:.1f} to {high:.1f} MiB, trend {trend:+.1f} MiB over the run; "
          f"device {device_first} -> {device_last}")
    problems = []
    if trend > host_growth_mib:
        problems.append(f"host memory grows: {trend:+.1f} MiB over the run by its trend (more than {host_growth_mib} MiB)")
    if device_last != device_first:
        problems.append(f"device memory changed from {device_first} to {device_last}")
    for p in problems:
        print(f"FAIL: {p}")
    return 1 if problems else 0


def soak_frames(args):
    """`fredholm render --frames 0:N-1` of an animated scene; each frame's --stats holds the memory held as it ends."""
    work = args.workdir or tempfile.mkdtemp(prefix="fh_soak_frames_")
    os.makedirs(work, exist_ok=True)
    scene = args.scene or make_animated_scene(os.path.join(work, "scenes"))
    for old in glob.glob(os.path.join(work, "frame_*")):
        os.remove(old)
    command = [args.fredholm, "render", scene, "--frames", f"0:{args.frames - 1}", "--fps", "240",
               "-o", os.path.join(work, "frame_#####.exr"), "--stats", os.path.join(work, "frame_#####.json"),
               "--width", "16", "--height", "16", "--spp", "1", "--quiet"]
    print(" ".join(command), flush=True)
    began = time.monotonic()
    subprocess.run(command, check=True)
    seconds = time.monotonic() - began
    rows = []
    for frame in range(args.frames):
        with open(os.path.join(work, f"frame_{frame:05d}.json")) as f:
            stats = json.load(f)
        rows.append((frame + 1, stats["host_resident_bytes"], stats["device_memory_bytes"], stats["device_allocations"]))
    columns = ("frame", "host_resident", "device_bytes", "allocations")
    with open(os.path.join(work, "memory.csv"), "w", newline="") as f:
        csv.writer(f).writerows([columns, *rows])
    print(f"{args.frames} frames in {seconds:.0f} s; memory per frame in {os.path.join(work, 'memory.csv')}")
    marks = {1, 10, 100, 250, 500, 750, args.frames}
    print_curve(rows, columns, marks)
    settled = rows[len(rows) // 10:]  # after the first tenth: the driver's caches are warm
    return judge(f"frames {settled[0][0]} to {rows[-1][0]}", [(r[0], r[1]) for r in settled],
                 (settled[0][2], settled[0][3]), (rows[-1][2], rows[-1][3]), args.host_growth)


def resident_bytes(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return None


def find_viewer(parent_pid, fredholm):
    """The `fredholm view` process xvfb-run started (a descendant of `parent_pid` running the binary itself)."""
    out = subprocess.run(["ps", "-eo", "pid=,ppid=,args="], stdout=subprocess.PIPE, text=True).stdout
    table = [line.split(None, 2) for line in out.splitlines()]
    parents = {int(t[0]): int(t[1]) for t in table if len(t) >= 2}
    for t in table:
        if len(t) == 3 and t[2].split()[:2] == [fredholm, "view"]:
            up = int(t[0])
            while up in parents and up not in (parent_pid, 1):
                up = parents[up]
            if up == parent_pid:
                return int(t[0])
    return None


def soak_viewer(args):
    """`fredholm view --frames N` in Xvfb with the camera orbiting, zooming, panning and the window resized throughout;
    its resident set sampled twice a second, and the viewer's own line of memory after the first and last frame."""
    work = args.workdir or tempfile.mkdtemp(prefix="fh_soak_viewer_")
    os.makedirs(work, exist_ok=True)
    scene = args.scene or os.path.join(ROOT, "scenes", "cornell.gltf")
    moves = max(10, args.frames // 25 // 10 * 10)  # an action every 25 frames, resizes an even number: the first size
    script = ",".join(["orbit", "zoom", "pan", "orbit", "resize"][i % 5] for i in range(moves))
    command = ["xvfb-run", "-a", "-s", "-screen 0 640x480x24", args.fredholm, "view", scene, "--frames",
               str(args.frames), "--script", script, "--screenshot", os.path.join(work, "last.exr")]
    print(" ".join(command[:8]) + f" --script <{moves} actions> ...", flush=True)
    process = subprocess.Popen(command, stderr=subprocess.PIPE, text=True)
    samples = []
    began = time.monotonic()
    stderr = []
    reader = threading.Thread(target=lambda: stderr.extend(process.stderr), daemon=True)
    reader.start()
    viewer = None
    while process.poll() is None:
        viewer = viewer or find_viewer(process.pid, args.fredholm)
        rss = resident_bytes(viewer) if viewer else None
        if rss:
            samples.append((round(time.monotonic() - began, 1), rss))
        time.sleep(0.5)
    reader.join()
    text = "".join(stderr)
    print(text.strip())
    if process.returncode != 0:
        print(f"FAIL: fredholm view exited {process.returncode}")
        return 1
    with open(os.path.join(work, "memory.csv"), "w", newline="") as f:
        csv.writer(f).writerows([("seconds", "host_resident"), *samples])
    if len(samples) < 4:
        print("FAIL: too few memory samples (the run was too short to judge)")
        return 1
    n = len(samples)
    marks = {samples[int(i * (n - 1) / 8)][0] for i in range(9)}
    print(f"{args.frames} frames in {samples[-1][0]:.0f} s; resident set sampled {n} times, in "
          f"{os.path.join(work, 'memory.csv')}")
    print_curve(samples, ("seconds", "host_resident"), marks)
    line = [l for l in text.splitlines() if "memory after frame 1" in l]
    if not line:
        print("FAIL: the viewer printed no memory line")
        return 1
    device = line[0].split("; device ")[1].split(", ")
    return judge("viewer, after its first tenth", samples[n // 10:], device[0], device[1], args.host_growth)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("kind", choices=("frames", "viewer"))
    p.add_argument("--fredholm", required=True)
    p.add_argument("--scene", help="default: an animated square (frames), the Cornell box (viewer)")
    p.add_argument("--frames", type=int, help="default 1000 (frames), 5000 (viewer)")
    p.add_argument("--workdir", help="images and memory.csv go here (default: a new temporary folder)")
    p.add_argument("--host-growth", type=float, default=16.0, help="MiB the resident set may grow (default 16)")
    args = p.parse_args()
    args.frames = args.frames or (1000 if args.kind == "frames" else 5000)
    args.fredholm = os.path.abspath(args.fredholm)
    return soak_frames(args) if args.kind == "frames" else soak_viewer(args)


if __name__ == "__main__":
    sys.exit(main())
