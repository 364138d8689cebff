#!/usr/bin/env python3
"""fredholm-ray on a real multi-node Ray cluster (a head and two worker nodes on this machine, loopback only).

(a) the merged image of a render split into chunks across the nodes equals a single-process `fredholm render` of
    the same settings (compared by --compare-cmd, e.g. "fh_compare {test} --identical {reference}": the EXRs'
    metadata may differ, so their bytes are not compared);
(b) the same while one Ray worker that is running a chunk is SIGKILLed (the worker, not only its fredholm): Ray
    reruns the chunk and the image is still identical;
(c) a worker that cannot open the Vulkan device fails its chunk: one line names chunk, node and error; exit 1;
(d) the image split into 2x2 tiles (--crop parts) as well as sample ranges equals the single-process render.

  /opt/ray-venv/bin/python tests/cluster/test_ray_cluster.py --fredholm build/fredholm --scene scenes/cornell.gltf \\
      --workdir /tmp/fh-ray-test --compare-cmd "build/fh_compare {test} --identical {reference}"

Needs Ray in the Python that runs it (fredholm-ray runs as `python -m fredholm_ray` from engine/cluster, not
installed). Prints one line per check; exits 1 on any failure, leaving the images and node logs in --workdir.
"""
import argparse
import re
import os
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time

from local_cluster import LONGEST_TEMP_DIR, LocalCluster, make_client_env

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PACKAGE_DIR = os.path.join(REPO, "engine", "cluster")


class CheckFailed(Exception):
    pass


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--fredholm", required=True, help="fredholm binary")
    p.add_argument("--scene", required=True, help="scene to render (e.g. scenes/cornell.gltf)")
    p.add_argument("--workdir", required=True, help="images, logs and the cluster's temp dir go here")
    p.add_argument("--compare-cmd", required=True,
                   help="command that exits 0 when two EXRs hold the same pixels: {test} and {reference} replaced")
    p.add_argument("--width", type=int, default=32)
    p.add_argument("--height", type=int, default=32)
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--chunks", type=int, default=16)
    p.add_argument("--render-args", default="", help="more render options for every render, e.g. '--max-depth 8' "
                   "(a single option without a space: --render-args=--rr)")
    p.add_argument("--kill-spp", type=int, help="spp of the run with the kill (default --spp; raise it if no "
                   "chunk lives long enough to be caught)")
    p.add_argument("--kill-chunks", type=int, help="chunks of the run with the kill (default --chunks)")
    p.add_argument("--kills", type=int, default=1, help="Ray workers killed one after another in that run (the soak: "
                   "tests/soak/README.md; raise --kill-chunks and --kill-spp with it)")
    p.add_argument("--only-kills", action="store_true", help="run the check with the kills alone (b), not (a), (c), (d)")
    p.add_argument("--workers", type=int, default=2, help="worker nodes, one CPU each")
    p.add_argument("--node-ip", default="127.0.0.2", help="loopback address the nodes advertise")
    p.add_argument("--ray", help="ray command (default: the one beside this Python)")
    p.add_argument("--timeout", type=float, default=600, help="seconds allowed for each fredholm-ray run")
    return p.parse_args()


def render_options(args):
    return ["--width", str(args.width), "--height", str(args.height)] + shlex.split(args.render_args)


def render_reference(args, spp, output):
    command = [args.fredholm, "render", args.scene, "-o", output, "--spp", str(spp), "-q"] + render_options(args)
    result = subprocess.run(command, stderr=subprocess.PIPE, text=True)
    if result.returncode != 0:
        raise CheckFailed(f"reference render failed: {shlex.join(command)}: {result.stderr.strip()}")


def start_fredholm_ray(args, cluster, spp, chunks, output, log_path, more=()):
    command = [sys.executable, "-m", "fredholm_ray", "render", args.scene, "-o", output, "--spp", str(spp),
               "--chunks", str(chunks), "--address", cluster.address, "--fredholm", args.fredholm] + list(more)
    command += render_options(args)
    env = make_client_env(cluster)
    env["PYTHONPATH"] = PACKAGE_DIR + os.pathsep + os.environ.get("PYTHONPATH", "")
    log = open(log_path, "w")
    return command, subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, env=env), log


def finish_fredholm_ray(command, process, log, log_path, timeout):
    try:
        process.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()
    log.close()
    with open(log_path) as f:
        text = f.read()
    if process.returncode != 0:
        raise CheckFailed(f"fredholm-ray exited {process.returncode}: {shlex.join(command)}\n{text.strip()}")
    return text


def compare(args, test, reference):
    command = [t.format(test=test, reference=reference) for t in shlex.split(args.compare_cmd)]
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if result.returncode != 0:
        raise CheckFailed(f"{test} differs from {reference}: {shlex.join(command)}: {result.stdout.strip()}")


def list_processes():
    out = subprocess.run(["ps", "-eo", "pid=,ppid=,pgid=,args="], stdout=subprocess.PIPE, text=True).stdout
    processes = {}
    for line in out.splitlines():
        fields = line.split(None, 3)
        if len(fields) == 4:
            processes[int(fields[0])] = (int(fields[1]), int(fields[2]), fields[3])
    return processes


def find_chunk_worker(binary, cluster_groups):
    """(worker pid, fredholm pid, fredholm args) of a Ray worker of this cluster's worker nodes whose fredholm
    child renders a chunk, or None."""
    processes = list_processes()
    for pid, (ppid, _, command) in processes.items():
        if binary in command and " render " in command and "--samples" in command and ppid in processes:
            raylet, _, parent_command = processes[ppid]
            # A Ray worker has a process group of its own; its raylet is in its node's.
            if parent_command.startswith("ray::") and raylet in processes and processes[raylet][1] in cluster_groups:
                return ppid, pid, command
    return None


def is_gone(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(") ", 1)[1].startswith("Z")  # dead, not yet reaped
    except OSError:
        return True


def wait_until_gone(pid, seconds):
    deadline = time.monotonic() + seconds
    while not is_gone(pid):
        if time.monotonic() > deadline:
            return False
        time.sleep(0.05)
    return True


def kill_one_worker(binary, cluster_groups, process, timeout):
    """SIGKILLs the first Ray worker seen running a chunk; returns a description once it (and its fredholm) died."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and process.poll() is None:
        found = find_chunk_worker(binary, cluster_groups)
        if found:
            worker, child, command = found
            os.kill(worker, signal.SIGKILL)
            if not wait_until_gone(worker, 10):
                raise CheckFailed(f"Ray worker {worker} still alive 10 s after SIGKILL")
            samples = command[command.index("--samples"):].split(" -o ")[0]
            if not wait_until_gone(child, 10):
                raise CheckFailed(f"fredholm pid {child} still renders 10 s after its Ray worker {worker} was killed")
            return f"worker pid {worker} running {samples}; its fredholm (pid {child}) died with it"
        time.sleep(0.02)
    return None


def check_plain_render(args, cluster, workdir):
    reference = os.path.join(workdir, "reference.exr")
    output = os.path.join(workdir, "ray.exr")
    render_reference(args, args.spp, reference)
    log_path = os.path.join(workdir, "fredholm_ray_a.log")
    command, process, log = start_fredholm_ray(args, cluster, args.spp, args.chunks, output, log_path)
    text = finish_fredholm_ray(command, process, log, log_path, args.timeout)
    nodes = 1 + args.workers
    if f"to {nodes} node(s)" not in text:
        raise CheckFailed(f"fredholm-ray did not see {nodes} nodes: {text.strip()}")
    compare(args, output, reference)
    print(f"ok (a): {args.chunks} chunks of {args.spp} spp on {nodes} nodes == single-process render")
    return reference


def check_render_with_kill(args, cluster, workdir, reference):
    spp = args.kill_spp or args.spp
    chunks = args.kill_chunks or args.chunks
    if spp != args.spp or reference is None:
        reference = os.path.join(workdir, "reference_kill.exr")
        render_reference(args, spp, reference)
    output = os.path.join(workdir, "ray_kill.exr")
    log_path = os.path.join(workdir, "fredholm_ray_b.log")
    command, process, log = start_fredholm_ray(args, cluster, spp, chunks, output, log_path)
    groups = {p.pid for name, p in cluster.nodes if name != "head"}
    kills = []
    try:
        while len(kills) < args.kills:
            killed = kill_one_worker(os.path.abspath(args.fredholm), groups, process, args.timeout)
            if killed is None:
                break
            kills.append(killed)
            print(f"ok (b): kill {len(kills)} of {args.kills}: {killed}", flush=True)
    except BaseException:
        process.kill()
        process.wait()
        log.close()
        raise
    text = finish_fredholm_ray(command, process, log, log_path, args.timeout)
    if len(kills) < args.kills:
        raise CheckFailed(f"{len(kills)} of {args.kills} Ray workers were caught running a chunk (raise --kill-spp "
                          "and --kill-chunks so chunks last longer)")
    print(f"ok (b): killed {len(kills)} Ray worker(s) mid-chunk")
    # fredholm-ray's last line says how many chunks were retried (Ray's own log lines may follow it).
    summaries = [line for line in text.strip().splitlines() if re.search(r", retries (\d+|unknown)", line)]
    summary = summaries[-1] if summaries else text.strip().splitlines()[-1]
    retries = re.search(r"retries (\d+)", summary)
    if "retries 0" in summary or (retries and int(retries.group(1)) < len(kills)):
        raise CheckFailed(f"fredholm-ray saw fewer retries than the {len(kills)} kill(s): {summary}")
    compare(args, output, reference)
    print(f"ok (b): image after the kill == single-process render ({summary.split(', ')[-1]})")


def check_worker_without_device(args, cluster, workdir):
    """(c) A worker that cannot open the Vulkan device asked for (`--device` naming none of its devices, as on a node
    without a GPU) fails its chunk: fredholm-ray exits 1 with one line naming the chunk, the node and fredholm's
    error, and writes no image."""
    output = os.path.join(workdir, "ray_no_device.exr")
    log_path = os.path.join(workdir, "fredholm_ray_c.log")
    saved = args.render_args
    args.render_args = saved + " --device NoSuchGPU"
    try:
        command, process, log = start_fredholm_ray(args, cluster, 4, 2, output, log_path)
    finally:
        args.render_args = saved
    try:
        finish_fredholm_ray(command, process, log, log_path, args.timeout)
    except CheckFailed:
        pass
    with open(log_path) as f:
        lines = [line for line in f.read().splitlines() if line.startswith("fredholm-ray:") and " failed" in line]
    expected = "no Vulkan device whose name contains 'NoSuchGPU'"
    if process.returncode != 1 or len(lines) != 1 or " failed on " not in lines[0] or expected not in lines[0]:
        raise CheckFailed(f"a chunk without its device: exit {process.returncode}, lines {lines}")
    if os.path.exists(output):
        raise CheckFailed(f"a failed run wrote {output}")
    print(f"ok (c): a worker without the device fails its chunk with one line: {lines[0]}")


def check_tiles(args, cluster, workdir, reference):
    output = os.path.join(workdir, "ray_tiles.exr")
    log_path = os.path.join(workdir, "fredholm_ray_d.log")
    command, process, log = start_fredholm_ray(args, cluster, args.spp, 4, output, log_path, ["--tiles", "2x2"])
    text = finish_fredholm_ray(command, process, log, log_path, args.timeout)
    if "in 16 chunks" not in text:
        raise CheckFailed(f"2x2 tiles of 4 chunks did not make 16 chunks: {text.strip()}")
    compare(args, output, reference)
    print("ok (d): 2x2 tiles x 4 sample ranges == single-process render")


def choose_temp_dir(workdir):
    """Ray's temp dir under the workdir when the socket paths fit, else a fresh one in /tmp (removed after)."""
    own = os.path.join(workdir, "ray")
    if len(own) <= LONGEST_TEMP_DIR:
        return own, False
    return tempfile.mkdtemp(prefix="fh-ray-", dir="/tmp"), True


def main():
    args = parse_args()
    args.fredholm = os.path.abspath(args.fredholm)
    args.scene = os.path.abspath(args.scene)
    workdir = os.path.abspath(args.workdir)
    os.makedirs(workdir, exist_ok=True)
    ray_cli = args.ray or os.path.join(os.path.dirname(sys.executable), "ray")
    temp_dir, remove_temp = choose_temp_dir(workdir)
    scratch = os.path.join(workdir, "scratch")  # the workers' TMPDIR: their chunk folders
    os.makedirs(scratch, exist_ok=True)
    cluster = LocalCluster(ray_cli, temp_dir, workdir, workers=args.workers, node_ip=args.node_ip,
                           env=dict(os.environ, TMPDIR=scratch))
    failed = False
    try:
        began = time.monotonic()
        with cluster:
            times = ", ".join(f"{name} {s:.1f} s" for name, s in cluster.start_seconds.items())
            print(f"cluster up at {cluster.address} in {time.monotonic() - began:.1f} s ({times})")
            if args.only_kills:
                check_render_with_kill(args, cluster, workdir, None)
            else:
                reference = check_plain_render(args, cluster, workdir)
                check_render_with_kill(args, cluster, workdir, reference)
                check_worker_without_device(args, cluster, workdir)
                check_tiles(args, cluster, workdir, reference)
    except (CheckFailed, RuntimeError) as e:
        print(f"FAIL: {e}")
        failed = True
    finally:
        if remove_temp:
            shutil.rmtree(temp_dir, ignore_errors=True)
    print("cluster stopped")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
