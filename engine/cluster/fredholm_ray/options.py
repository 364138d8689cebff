"""The fredholm-ray command line: its own options, and the render options it passes through to fredholm render."""
import argparse
import os
import shutil
from dataclasses import dataclass
from typing import List, Optional

from .plan import UsageError, name_frame_file, parse_frames, parse_tiles
from .worker import ENV_TOKEN, SCENE_TOKEN

# Options fredholm-ray sets on every part itself, or that make no sense for a part: not accepted as pass-through.
OWNED_OPTIONS = ("-o", "--output", "--samples", "--spp", "--frames", "--fps", "--png", "--stats", "--resume",
                 "-q", "--quiet", "--crop")
DEFAULT_SIZE = 512  # fredholm render's --width and --height

USAGE_EPILOG = """\
Any other option (or everything after --) is passed unchanged to every `fredholm render`, e.g.
  fredholm-ray render scenes/cornell.gltf -o out.exr --spp 1024 --chunks 16 --width 512 --height 512
"""


@dataclass
class RenderRequest:
    scene: str
    output: str
    png: Optional[str]
    spp: int
    chunks: Optional[int]              # None: one per CPU slot of the cluster
    frames: Optional[tuple]            # (first, last) inclusive, or None for a still
    crops: Optional[list]              # --tiles: the (x0, y0, x1, y1) crops that tile the image, None for 1x1
    fps: float
    address: Optional[str]
    binary: str                        # fredholm on the driver (merge); also what the workers run
    binary_for_workers: Optional[str]  # None: each worker's own $FREDHOLM_BIN or `fredholm` on its PATH
    retries: int
    cpus_per_task: float
    shared_storage: bool
    quiet: bool
    env: Optional[str]                 # the --env map among the pass-through options
    options: List[str]                 # render options: SCENE_TOKEN first, ENV_TOKEN for the --env value
    merge_options: List[str]           # --exposure, --tonemap: for fredholm merge's PNG


class OneLineParser(argparse.ArgumentParser):
    """argparse whose errors are one UsageError line, not usage text plus an exit."""

    def error(self, message):
        raise UsageError(f"{message} (see fredholm-ray render --help)")


def make_parser():
    parser = OneLineParser(prog="fredholm-ray", allow_abbrev=False,
                           description="Render one Fredholm image (or sequence) across a Ray cluster.")
    commands = parser.add_subparsers(dest="command", required=True)
    render = commands.add_parser("render", allow_abbrev=False, epilog=USAGE_EPILOG,
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 help="split the samples into chunks, render them as Ray tasks, merge the parts")
    render.add_argument("scene", help="glTF 2.0 scene (.gltf or .glb); put it first")
    render.add_argument("-o", "--output", required=True, help="merged OpenEXR image (with --frames: a #### pattern)")
    render.add_argument("--spp", type=int, required=True, help="samples per pixel of the merged image")
    render.add_argument("--chunks", type=int, help="sample ranges per frame, one Ray task each "
                        "(default: one per CPU slot of the cluster)")
    render.add_argument("--tiles", default="1x1", help="also split the image into COLSxROWS crops, each rendered "
                        "--chunks times (an image too large for one device's film; default 1x1)")
    render.add_argument("--frames", help="render frames A:B (inclusive) of the animation, frame f at time f / --fps")
    render.add_argument("--fps", type=float, default=24.0, help="frames per second of --frames (default 24)")
    render.add_argument("--address", help="Ray cluster address (default: $RAY_ADDRESS, else the running local "
                        "cluster, else a new local Ray)")
    render.add_argument("--fredholm", help="fredholm binary (default: $FREDHOLM_BIN, else fredholm on PATH)")
    render.add_argument("--retries", type=int, default=3, help="times Ray reruns a chunk whose worker died "
                        "(default 3; a chunk fredholm fails is not retried)")
    render.add_argument("--cpus-per-task", type=float, default=1.0, help="Ray CPUs each chunk holds (default 1)")
    render.add_argument("--shared-storage", action="store_true", help="workers read the scene at its path "
                        "(shared file system) instead of receiving a copy through the object store")
    render.add_argument("--png", help="also write a tone-mapped PNG of the merged image")
    render.add_argument("-q", "--quiet", action="store_true", help="no progress or summary lines")
    return parser


def find_binary(given):
    """(binary for the driver, binary for the workers) from --fredholm, $FREDHOLM_BIN or PATH."""
    name = given or os.environ.get("FREDHOLM_BIN")
    if name and os.sep in name:
        path = os.path.abspath(name)
        if not (os.path.isfile(path) and os.access(path, os.X_OK)):
            raise UsageError(f"fredholm binary {name} not found or not executable")
        return path, path
    found = shutil.which(name or "fredholm")
    if not found:
        raise UsageError(f"fredholm binary '{name or 'fredholm'}' not found on PATH "
                         "(give --fredholm PATH or set FREDHOLM_BIN)")
    return found, name


def take_option(options, name):
    """Removes `name VALUE` / `name=VALUE` (the last one counts, as in fredholm); returns (options, VALUE or None)."""
    rest, value = [], None
    i = 0
    while i < len(options):
        if options[i] == name:
            if i + 1 >= len(options):
                raise UsageError(f"{name} needs a value")
            value = options[i + 1]
            i += 2
            continue
        if options[i].startswith(name + "="):
            value = options[i][len(name) + 1:]
        else:
            rest.append(options[i])
        i += 1
    return rest, value


def peek_option(options, name, default):
    """The value of the last `name VALUE` / `name=VALUE` among the options, left in place, as an int."""
    _, value = take_option(list(options), name)
    if value is None:
        return default
    try:
        return int(value)
    except ValueError:
        raise UsageError(f"{name} '{value}' is not a whole number")


def check_pass_through(options, frames):
    for option in options:
        name = option.split("=", 1)[0]
        if name == "--crop":
            raise UsageError("--crop is set by fredholm-ray itself: split the image with --tiles COLSxROWS")
        if name in OWNED_OPTIONS:
            raise UsageError(f"{name} is set by fredholm-ray itself; see fredholm-ray render --help")
        if name == "--time" and frames is not None:
            raise UsageError("--time cannot be combined with --frames (each frame's time is frame / --fps)")


def check_output(path, what):
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise UsageError(f"{what} {path}: folder {folder} does not exist")
    if not os.access(folder, os.W_OK):
        raise UsageError(f"{what} {path}: folder {folder} is not writable")


def parse_render_request(argv):
    """The RenderRequest of a command line (argv without the program name); raises UsageError."""
    extra = []
    if "--" in argv:
        cut = argv.index("--")
        argv, extra = argv[:cut], argv[cut + 1:]
    args, unknown = make_parser().parse_known_args(argv)
    options = unknown + extra
    frames = parse_frames(args.frames) if args.frames is not None else None
    check_pass_through(options, frames)
    if args.chunks is not None and args.chunks < 1:
        raise UsageError(f"--chunks {args.chunks} must be at least 1")
    if args.spp < 1:
        raise UsageError(f"--spp {args.spp} must be at least 1")
    if not args.fps > 0:
        raise UsageError(f"--fps {args.fps} must be positive")
    if args.retries < 0:
        raise UsageError(f"--retries {args.retries} must not be negative")
    if args.cpus_per_task < 0:
        raise UsageError(f"--cpus-per-task {args.cpus_per_task} must not be negative")
    if not os.path.isfile(args.scene):
        raise UsageError(f"scene {args.scene} not found")
    for path, what in ((args.output, "-o"), (args.png, "--png")):
        if path is None:
            continue
        if frames is not None:
            path = name_frame_file(path, frames[0])
        check_output(path, what)
    crops = parse_tiles(args.tiles, peek_option(options, "--width", DEFAULT_SIZE),
                        peek_option(options, "--height", DEFAULT_SIZE))
    options, env = take_option(options, "--env")
    if env is not None:
        if not os.path.isfile(env):
            raise UsageError(f"--env {env} not found")
        options += ["--env", ENV_TOKEN]
    merge_options = []
    for name in ("--exposure", "--tonemap"):  # they shape the merged PNG, not the film
        options, value = take_option(options, name)
        if value is not None:
            merge_options += [name, value]
    binary, binary_for_workers = find_binary(args.fredholm)
    return RenderRequest(scene=args.scene, output=args.output, png=args.png, spp=args.spp, chunks=args.chunks,
                         frames=frames, crops=crops, fps=args.fps, address=args.address, binary=binary,
                         binary_for_workers=binary_for_workers, retries=args.retries,
                         cpus_per_task=args.cpus_per_task, shared_storage=args.shared_storage, quiet=args.quiet,
                         env=env, options=[SCENE_TOKEN] + options, merge_options=merge_options)
