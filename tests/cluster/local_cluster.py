"""A throw-away multi-node Ray cluster on this machine: a head and worker nodes, each one `ray start --block`.

Every node is its own process group (so stopping it never touches another cluster on the machine; `ray stop` would
stop them all) and advertises a loopback address. It is 127.0.0.2, not 127.0.0.1: Ray replaces 127.0.0.1 and
'localhost' by the machine's routable address (ray._private.services.resolve_ip_for_localhost), but the whole of
127.0.0.0/8 is loopback on Linux, so 127.0.0.2 keeps the cluster's traffic on this machine. Ray's servers still
listen on all interfaces (it has no option to bind one); the ports are chosen at random.
"""
import os
import secrets
import signal
import socket
import subprocess
import time

READY_LINE = "Ray runtime started"
# Unix socket paths (TEMP/session_<date>_<pid>/sockets/plasma_store) must stay under 108 bytes.
LONGEST_TEMP_DIR = 40


def make_client_env(cluster, base=None):
    """The environment a driver needs to connect to `cluster` (its token)."""
    env = dict(os.environ if base is None else base)
    env.update({k: cluster.env[k] for k in ("RAY_AUTH_MODE", "RAY_AUTH_TOKEN")})
    return env


def find_free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class LocalCluster:
    def __init__(self, ray_cli, temp_dir, log_dir, workers=2, cpus_per_worker=1, node_ip="127.0.0.2", env=None):
        self.ray_cli = ray_cli
        self.temp_dir = temp_dir
        self.log_dir = log_dir
        self.workers = workers
        self.cpus_per_worker = cpus_per_worker
        self.node_ip = node_ip
        # Its own token: the cluster's ports are reachable from the network, and a token in ~/.ray (which a local
        # ray.init() leaves there) would otherwise switch the head, but not the workers, to token authentication.
        self.env = dict(os.environ if env is None else env, RAY_USAGE_STATS_ENABLED="0", RAY_AUTH_MODE="token",
                        RAY_AUTH_TOKEN=secrets.token_hex(32))
        self.nodes = []  # (name, Popen of `ray start --block`)
        self.address = None
        self.start_seconds = {}

    def start_node(self, name, arguments, env):
        log_path = os.path.join(self.log_dir, f"ray_{name}.log")
        command = [self.ray_cli, "start", "--block", "--disable-usage-stats", "--node-ip-address", self.node_ip,
                   "--temp-dir", self.temp_dir, "--dashboard-agent-listen-port", str(find_free_port())] + arguments
        began = time.monotonic()
        with open(log_path, "w") as log:
            process = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                       env=env, start_new_session=True)
        self.nodes.append((name, process))
        wait_for_line(process, log_path, READY_LINE, 120, name)
        self.start_seconds[name] = time.monotonic() - began

    def start(self):
        os.makedirs(self.temp_dir, exist_ok=True)
        os.makedirs(self.log_dir, exist_ok=True)
        # The head's autoscaler monitor and dashboard export metrics on fixed ports by default: move them aside
        # so this cluster can run beside another one.
        head_env = dict(self.env, AUTOSCALER_METRIC_PORT=str(find_free_port()),
                        DASHBOARD_METRIC_PORT=str(find_free_port()))
        self.start_node("head", ["--head", "--port", "0", "--num-cpus", "0", "--include-dashboard", "false",
                                 "--ray-client-server-port", str(find_free_port())], head_env)
        with open(os.path.join(self.temp_dir, "ray_current_cluster")) as f:
            self.address = f.read().strip()
        for _ in range(self.workers):
            self.add_worker()
        return self

    def add_worker(self):
        """Starts one more worker node and returns its name."""
        name = f"worker{sum(1 for n, _ in self.nodes if n != 'head') + 1}"
        # One log monitor per machine is enough (the head's); a second would repeat every line.
        self.start_node(name, ["--address", self.address, "--num-cpus", str(self.cpus_per_worker),
                               "--include-log-monitor", "false"], self.env)
        return name

    def stop(self, grace_seconds=20):
        """Workers first (they drain through the head), then the head: SIGTERM to `ray start`, then SIGKILL."""
        for group in ([p for name, p in self.nodes if name != "head"], [p for name, p in self.nodes if name == "head"]):
            for process in group:
                if process.poll() is None:
                    process.send_signal(signal.SIGTERM)
            deadline = time.monotonic() + grace_seconds
            for process in group:
                try:
                    process.wait(timeout=max(0.1, deadline - time.monotonic()))
                except subprocess.TimeoutExpired:
                    pass
            for process in group:  # what is left of the node (raylet, workers, agents) shares its process group
                try:
                    os.killpg(process.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
                process.wait()
        self.nodes = []

    def __enter__(self):
        try:
            return self.start()
        except BaseException:
            self.stop()
            raise

    def __exit__(self, *exc):
        self.stop()


def wait_for_line(process, log_path, line, timeout, name):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        with open(log_path, errors="replace") as f:
            if line in f.read():
                return
        if process.poll() is not None:
            break
        time.sleep(0.2)
    with open(log_path, errors="replace") as f:
        tail = [l.rstrip() for l in f.read().splitlines() if l.strip()][-5:]
    state = f"exited with status {process.returncode}" if process.poll() is not None else f"not up after {timeout} s"
    raise RuntimeError(f"ray node {name} {state} ({log_path}): " + " | ".join(tail))
