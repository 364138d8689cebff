"""What runs in a Ray worker: unpack the scene, render one sample range with fredholm, return the part's bytes.

This module is shipped to the workers by value (driver.py registers it with cloudpickle), so a worker needs Ray
and the fredholm binary but not this package: it may import only the standard library and ray.
"""
import ctypes
import os
import re
import shutil
import signal
import socket
import subprocess
import tempfile
import time

import ray

# Stand-ins in the command line for paths that only the worker knows. NUL cannot occur in a real argument.
SCENE_TOKEN = "\0scene\0"
ENV_TOKEN = "\0env\0"
KV_NAMESPACE = "fredholm-ray"
PR_SET_PDEATHSIG = 1


class ChunkFailed(RuntimeError):
    """fredholm could not render a chunk: its last stderr line and the node it ran on (not retried by Ray)."""

    def __init__(self, line, node):
        super().__init__(line, node)
        self.line = line
        self.node = node

    def __str__(self):
        return f"{self.line} (on {self.node})"


def describe_node():
    try:
        address = ray.util.get_node_ip_address()
    except Exception:  # outside a Ray worker
        address = "?"
    return f"{socket.gethostname()} ({address})"


def record_attempt(run_id, chunk_index):
    """Notes this attempt in the cluster's key-value store, so the driver can count retries (best effort)."""
    try:
        from ray.experimental import internal_kv
        key = f"{run_id}/{chunk_index}/{socket.gethostname()}-{os.getpid()}-{time.monotonic_ns()}"
        internal_kv._internal_kv_put(key, b"", namespace=KV_NAMESPACE)
    except Exception:
        pass


def make_death_signal_setter():
    """A preexec function that makes the child die with this worker (Linux prctl), or None where unavailable.

    Ray retries a chunk whose worker was killed; without this, the killed worker's fredholm would keep the GPU busy
    rendering a part nobody collects. The function is resolved here, before fork, so the child only makes one call.
    """
    try:
        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None

    def set_death_signal():
        prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL))

    return set_death_signal


def remove_stale_folders():
    """Removes the scratch folders of workers that were killed mid-chunk (their pid, in the name, is gone)."""
    root = tempfile.gettempdir()
    for name in os.listdir(root):
        match = re.fullmatch(r"fredholm-ray-(\d+)-\w+", name)
        if not match:
            continue
        try:
            os.kill(int(match.group(1)), 0)
        except ProcessLookupError:
            shutil.rmtree(os.path.join(root, name), ignore_errors=True)
        except OSError:  # alive, another user's
            pass


def write_files(files, folder):
    for name, data in files.items():
        path = os.path.join(folder, *name.split("/"))
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as f:
            f.write(data)


def describe_failure(result, binary):
    lines = [line.strip() for line in (result.stderr or b"").decode(errors="replace").splitlines() if line.strip()]
    if lines:
        return lines[-1]
    if result.returncode < 0:
        return f"{binary} was killed by {signal.Signals(-result.returncode).name}"
    return f"{binary} exited with status {result.returncode} and no message"


def render_chunk(binary, files, scene, env, options, first, end, run_id, chunk_index):
    """Renders samples [first, end) with `binary render` and returns the part EXR's bytes.

    binary: None for this node's $FREDHOLM_BIN, else `fredholm` on its PATH; files: bundle path -> bytes (None with
    shared storage: `scene` and `env` are then real paths); options: the render options, with SCENE_TOKEN and
    ENV_TOKEN where the scene and --env paths go.
    """
    binary = binary or os.environ.get("FREDHOLM_BIN") or "fredholm"
    record_attempt(run_id, chunk_index)
    remove_stale_folders()
    folder = tempfile.mkdtemp(prefix=f"fredholm-ray-{os.getpid()}-")
    try:
        if files is not None:
            write_files(files, folder)
            scene = os.path.join(folder, scene)
            env = os.path.join(folder, env) if env else None
        replace = {SCENE_TOKEN: scene, ENV_TOKEN: env}
        part = os.path.join(folder, "part.exr")
        command = [binary, "render"] + [replace.get(o, o) for o in options]
        command += ["--samples", f"{first}:{end}", "-o", part, "-q"]
        try:
            result = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                    preexec_fn=make_death_signal_setter())
        except OSError as e:
            raise ChunkFailed(f"cannot run {binary}: {e.strerror}", describe_node()) from None
        if result.returncode != 0:
            raise ChunkFailed(describe_failure(result, binary), describe_node())
        if not os.path.isfile(part):
            raise ChunkFailed(f"{binary} exited with status 0 but wrote no part file", describe_node())
        with open(part, "rb") as f:
            return f.read()
    finally:
        shutil.rmtree(folder, ignore_errors=True)
