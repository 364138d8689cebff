"""The files a render reads (the glTF, every relative file it references, the --env map), packed for the workers."""
import json
import os
import struct
import urllib.parse
from dataclasses import dataclass, field
from typing import Dict, Optional

from .plan import UsageError

GLB_MAGIC = b"glTF"
GLB_JSON_CHUNK = 0x4E4F534A  # "JSON", little-endian


@dataclass
class SceneBundle:
    scene: str                 # the scene's path inside the bundle
    env: Optional[str]         # the --env map's path inside the bundle, None without one
    files: Dict[str, bytes] = field(default_factory=dict)  # bundle path -> contents


MAX_JSON_DEPTH = 1000  # as fredholm's own loader (engine/scene/gltf/json_limits.h)


def json_nesting_depth(data):
    """The deepest nesting of arrays and objects in JSON text (bytes), brackets inside strings left out."""
    depth = deepest = 0
    in_string = escaped = False
    for byte in data:
        if in_string:
            if escaped:
                escaped = False
            elif byte == 0x5C:  # backslash
                escaped = True
            elif byte == 0x22:  # quote
                in_string = False
        elif byte == 0x22:
            in_string = True
        elif byte in (0x5B, 0x7B):  # [ {
            depth += 1
            deepest = max(deepest, depth)
        elif byte in (0x5D, 0x7D):
            depth -= 1
    return deepest


def read_gltf_json(path):
    """The JSON document of a .gltf, or of a .glb's first chunk."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise UsageError(f"{path}: cannot read the scene: {e.strerror}")
    if path.lower().endswith(".glb") or data[:4] == GLB_MAGIC:
        if len(data) < 20 or data[:4] != GLB_MAGIC:
            raise UsageError(f"{path}: not a binary glTF (no glTF header)")
        length, kind = struct.unpack_from("<II", data, 12)
        if kind != GLB_JSON_CHUNK or 20 + length > len(data):
            raise UsageError(f"{path}: binary glTF without a JSON chunk first")
        data = data[20:20 + length]
    depth = json_nesting_depth(data)
    if depth > MAX_JSON_DEPTH:  # Python's parser would stop with a RecursionError
        raise UsageError(f"{path}: the JSON nests arrays and objects {depth} levels deep, more than the limit "
                         f"of {MAX_JSON_DEPTH}")
    try:
        return json.loads(data)
    except (ValueError, UnicodeDecodeError) as e:
        raise UsageError(f"{path}: not valid glTF JSON: {e}")


def list_referenced_files(scene_path):
    """Relative paths (as the OS spells them, relative to the scene's folder) of the buffers and images it uses."""
    document = read_gltf_json(scene_path)
    uris = [entry.get("uri") for key in ("buffers", "images") for entry in document.get(key, [])]
    files = []
    for uri in uris:
        if not uri or uri.startswith("data:"):
            continue
        if "://" in uri or uri.startswith("/") or os.path.isabs(uri):
            raise UsageError(f"{scene_path} references '{uri}', which is not a relative path: "
                             "only relative files can be shipped (use --shared-storage)")
        files.append(os.path.normpath(urllib.parse.unquote(uri)))
    return sorted(set(files))


def read_file(path, what):
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError as e:
        raise UsageError(f"{what} {path}: {e.strerror}")


def pack_scene(scene_path, env_path=None):
    """Reads the scene, its references and the --env map into a SceneBundle that keeps their relative layout.

    The scene and its references go under 'scene/', relative to the deepest folder holding all of them (a
    reference may climb out with '..'); the --env map goes under 'env/' with its own file name. Only file names
    reach fredholm's metadata, so the parts a worker renders from the bundle merge with each other.
    """
    if not os.path.isfile(scene_path):
        raise UsageError(f"scene {scene_path} not found")
    scene_abs = os.path.abspath(scene_path)
    folder = os.path.dirname(scene_abs)
    paths = [scene_abs] + [os.path.join(folder, rel) for rel in list_referenced_files(scene_path)]
    paths = [os.path.normpath(p) for p in paths]
    for p in paths[1:]:
        if not os.path.isfile(p):
            raise UsageError(f"{scene_path} references {os.path.relpath(p, folder)}, which does not exist")
    root = os.path.commonpath([os.path.dirname(p) for p in paths])
    bundle = SceneBundle(scene="scene/" + os.path.relpath(scene_abs, root).replace(os.sep, "/"), env=None)
    for p in paths:
        bundle.files["scene/" + os.path.relpath(p, root).replace(os.sep, "/")] = read_file(p, "scene file")
    if env_path is not None:
        if not os.path.isfile(env_path):
            raise UsageError(f"--env {env_path} not found")
        bundle.env = "env/" + os.path.basename(env_path)
        bundle.files[bundle.env] = read_file(env_path, "--env")
    return bundle
