"""The driver of a distributed render: connect to Ray, submit one task per chunk, collect the parts, merge them."""
import logging
import os
import re
import socket
import subprocess
import sys
import tempfile
import time
import uuid

import ray
import ray.cloudpickle

from . import worker
from .plan import make_chunks, name_frame_file
from .scene_bundle import pack_scene


class RenderFailed(Exception):
    """A chunk or a merge failed: main prints the one line and exits 1."""


def say(request, text):
    if not request.quiet:
        print(f"fredholm-ray: {text}", file=sys.stderr, flush=True)


def check_reachable(address):
    """Fails fast on a host:port nobody listens at (Ray itself retries for minutes, printing as it goes)."""
    if not address or address in ("auto", "local") or "://" in address:
        return
    host, _, port = address.rpartition(":")
    try:
        socket.create_connection((host, int(port)), timeout=5).close()
    except (OSError, ValueError) as e:
        raise RenderFailed(f"cannot reach the Ray cluster at {address}: {getattr(e, 'strerror', None) or e}")


def connect(address):
    check_reachable(address or os.environ.get("RAY_ADDRESS"))
    try:
        ray.init(address=address, log_to_driver=False, logging_level=logging.ERROR, configure_logging=True)
    except Exception as e:
        where = f"the Ray cluster at {address}" if address else "Ray"
        raise RenderFailed(f"cannot connect to {where}: {first_line(e)}")


def first_line(error):
    lines = [line.strip() for line in str(error).splitlines() if line.strip()]
    return lines[0] if lines else type(error).__name__


def count_task_slots(cpus_per_task):
    cpus = ray.cluster_resources().get("CPU", 0.0)
    return max(1, int(cpus // cpus_per_task)) if cpus_per_task > 0 else max(1, int(cpus))


def describe_task_error(chunk, error, retries):
    """The one failure line for a chunk whose task raised `error` (from ray.get)."""
    if isinstance(error, ray.exceptions.RayTaskError):
        cause = error.cause
        if hasattr(cause, "line") and hasattr(cause, "node"):  # worker.ChunkFailed, shipped by value
            return f"{chunk.describe()} failed on {cause.node}: {cause.line}"
        # ray.get raises a copy that lacks .ip; its message names the node as "(pid=..., ip=...)".
        match = re.search(r"\bip=([^\s,)]+)", str(error))
        node = match.group(1) if match else "a worker"
        return f"{chunk.describe()} failed on {node}: {type(cause).__name__}: {first_line(cause)}"
    if isinstance(error, ray.exceptions.WorkerCrashedError):
        tries = "once" if retries == 0 else f"{retries + 1} times"
        return f"{chunk.describe()} failed: its Ray worker died, {tries} (--retries {retries})"
    return f"{chunk.describe()} failed: {first_line(error)}"


def count_attempts(run_id):
    """Task attempts the workers recorded for this run (None if the store could not be read); clears them."""
    try:
        from ray.experimental import internal_kv
        keys = internal_kv._internal_kv_list(run_id + "/", namespace=worker.KV_NAMESPACE)
        internal_kv._internal_kv_del(run_id + "/", del_by_prefix=True, namespace=worker.KV_NAMESPACE)
        return len(keys)
    except Exception:
        return None


def merge_frame(request, frame, part_files):
    """fredholm merge of one frame's parts (it checks that they belong together and writes atomically)."""
    output = request.output if frame is None else name_frame_file(request.output, frame)
    command = [request.binary, "merge"] + part_files + ["-o", output, "-q"]
    if request.png:
        command += ["--png", request.png if frame is None else name_frame_file(request.png, frame)]
        command += request.merge_options
    result = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    if result.returncode != 0:
        lines = [line for line in result.stderr.decode(errors="replace").splitlines() if line.strip()]
        why = lines[-1].strip() if lines else f"exit status {result.returncode}"
        raise RenderFailed(f"merging {output} failed: {why}")
    return output


def submit_chunks(request, bundle, chunks, run_id):
    """One Ray task per chunk (bundle: the SceneBundle to ship, None with shared storage); {ObjectRef: chunk}."""
    # Ship worker.py by value: the workers need Ray and fredholm, not this package.
    ray.cloudpickle.register_pickle_by_value(worker)
    task = ray.remote(worker.render_chunk).options(max_retries=request.retries, retry_exceptions=False,
                                                   num_cpus=request.cpus_per_task, name="fredholm_render_chunk")
    if bundle is None:
        files, scene, env = None, os.path.abspath(request.scene), request.env and os.path.abspath(request.env)
    else:
        files, scene, env = ray.put(bundle.files), bundle.scene, bundle.env  # one copy in the object store
    refs = {}
    for chunk in chunks:
        options = list(request.options)
        if chunk.time is not None:
            options += ["--time", chunk.time]
        if chunk.crop is not None:
            options += ["--crop", "{},{},{},{}".format(*chunk.crop)]
        ref = task.remote(request.binary_for_workers, files, scene, env, options, chunk.first, chunk.end, run_id,
                          chunk.index)
        refs[ref] = chunk
    return refs


def collect_parts(request, refs, parts_dir, start):
    """Waits for the chunks, writes each part to disk, merges each frame once its parts are in; returns outputs."""
    pending = list(refs)
    per_frame = {}
    for chunk in refs.values():
        per_frame.setdefault(chunk.frame, []).append(chunk)
    written = {frame: [] for frame in per_frame}
    outputs = []
    while pending:
        done, pending = ray.wait(pending, num_returns=1)
        for ref in done:
            chunk = refs[ref]
            try:
                data = ray.get(ref)
            except ray.exceptions.RayError as e:
                for other in pending:  # without force: a cancelled task kills its fredholm and cleans up
                    ray.cancel(other)
                # One line is the report: Ray would log each other chunk that failed meanwhile as "unhandled".
                os.environ["RAY_IGNORE_UNHANDLED_ERRORS"] = "1"
                raise RenderFailed(describe_task_error(chunk, e, request.retries))
            frame = "still" if chunk.frame is None else chunk.frame
            tile = "" if chunk.crop is None else "_{}_{}".format(*chunk.crop[:2])
            name = f"part_{frame}{tile}_{chunk.first:08d}_{chunk.end:08d}.exr"
            path = os.path.join(parts_dir, name)
            with open(path, "wb") as f:
                f.write(data)
            del data
            written[chunk.frame].append((chunk.first, path))
            finished = len(refs) - len(pending)
            say(request, f"{finished}/{len(refs)} chunks done, {time.monotonic() - start:.1f} s")
            if len(written[chunk.frame]) == len(per_frame[chunk.frame]):
                parts = [p for _, p in sorted(written[chunk.frame])]
                outputs.append(merge_frame(request, chunk.frame, parts))
                for p in parts:
                    os.remove(p)
    return outputs


def run_render(request):
    """The whole distributed render of a RenderRequest; raises RenderFailed (or UsageError) with one line."""
    start = time.monotonic()
    bundle = None if request.shared_storage else pack_scene(request.scene, request.env)  # errors before Ray starts
    connect(request.address)
    chunks_per_frame = request.chunks or count_task_slots(request.cpus_per_task)
    chunks = make_chunks(request.spp, chunks_per_frame, request.frames, request.fps, request.crops)
    run_id = uuid.uuid4().hex
    nodes = sum(1 for node in ray.nodes() if node.get("Alive"))
    refs = submit_chunks(request, bundle, chunks, run_id)
    say(request, f"{len(chunks)} chunks submitted to {nodes} node(s), {time.monotonic() - start:.1f} s")
    try:
        with tempfile.TemporaryDirectory(prefix="fredholm-ray-parts-") as parts_dir:
            outputs = collect_parts(request, refs, parts_dir, start)
    finally:
        attempts = count_attempts(run_id)
    retries = "unknown" if attempts is None else str(attempts - len(chunks))
    target = outputs[0] if len(outputs) == 1 else f"{len(outputs)} frames"
    say(request, f"{target}: {request.spp} spp in {len(chunks)} chunks on {nodes} node(s), "
                 f"{time.monotonic() - start:.1f} s, retries {retries}")
    return outputs
