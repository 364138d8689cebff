#!/usr/bin/env python3
"""Gathers the fuzzer's seed corpus into OUT_DIR: the scenes we ship, the render-test scenes, the malformed
scenes of tests/robustness (ours and third-party), every past finding, plus variants made here so that no binary
is committed: a minified copy of each JSON scene (shorter inputs mutate faster) and a .glb of each scene whose
buffers are all data URIs.

    make_seed_corpus.py SOURCE_DIR OUT_DIR
"""
import base64
import json
import pathlib
import shutil
import struct
import subprocess
import sys
import tempfile

SEED_GLOBS = ["scenes/*.gltf", "tests/render/scenes/*.gltf", "tests/robustness/bad/*.gltf",
              "tests/robustness/bad/*.glb", "tests/robustness/thirdparty/**/*.gltf",
              "tests/robustness/thirdparty/**/*.glb", "tests/unit/meshes/*.glb", "tests/fuzz/regressions/*"]
MAX_SEED_BYTES = 64 * 1024  # as -max_len in .ci/fuzz: longer seeds would be cut anyway


def decode_data_uri(uri):
    if not uri.startswith("data:") or ";base64," not in uri:
        return None
    return base64.b64decode(uri.split(";base64,", 1)[1])


def pad(data, filler):
    return data + filler * (-len(data) % 4)


def make_glb(gltf):
    """A GLB 2.0 container (spec 4.4): the JSON chunk, then one BIN chunk holding every buffer back to back."""
    buffers = gltf.get("buffers", [])
    blobs = [decode_data_uri(b.get("uri", "")) for b in buffers]
    if not buffers or any(blob is None for blob in blobs):
        return None
    # Buffers after the first cannot live in the BIN chunk: append them to buffer 0 and move their views.
    starts, bin_data = [], b""
    for blob in blobs:
        bin_data = pad(bin_data, b"\0")
        starts.append(len(bin_data))
        bin_data += blob
    gltf = json.loads(json.dumps(gltf))
    for view in gltf.get("bufferViews", []):
        b = view.get("buffer", 0)
        if isinstance(b, int) and 0 <= b < len(starts):
            view["byteOffset"] = view.get("byteOffset", 0) + starts[b]
            view["buffer"] = 0
    gltf["buffers"] = [{"byteLength": len(bin_data)}]
    json_chunk = pad(json.dumps(gltf, separators=(",", ":")).encode(), b" ")
    bin_chunk = pad(bin_data, b"\0")
    body = (struct.pack("<I4s", len(json_chunk), b"JSON") + json_chunk +
            struct.pack("<I4s", len(bin_chunk), b"BIN\0") + bin_chunk)
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def main():
    source, out = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    count = 0
    # The textured, alpha and emitter scenes of the render tests (embedded PNGs: seeds for the image decoders).
    # The animated square of the camera scenes: a seed for the animation sampler. The material scenes: the material
    # extensions' readers (specular textures, specular-glossiness among them).
    for script in ("make_asset_scenes.py", "make_camera_scenes.py", "make_material_scenes.py"):
        with tempfile.TemporaryDirectory() as generated:
            subprocess.run([sys.executable, str(source / "tests/render/scenes" / script), generated], check=True)
            count += add_seeds(source, out, [str(p) for p in sorted(pathlib.Path(generated).glob("*.gltf"))], generated)
    count += add_seeds(source, out, SEED_GLOBS, None)
    print(f"{count} seeds in {out}")


def add_seeds(source, out, patterns, generated):
    """Copies each matching scene as a seed, with a minified copy and a .glb made from it."""
    count = 0
    for pattern in patterns:
        paths = [pathlib.Path(pattern)] if generated else sorted(source.glob(pattern))
        for path in paths:
            if not path.is_file() or path.suffix == ".md" or path.stat().st_size > MAX_SEED_BYTES:
                continue
            stem = ("generated_" + path.name) if generated else str(path.relative_to(source)).replace("/", "_")
            shutil.copyfile(path, out / stem)
            count += 1
            try:
                gltf = json.loads(path.read_bytes())
            except (ValueError, UnicodeDecodeError, RecursionError):
                continue  # malformed (or nested deeper than Python parses) on purpose: the copy is the seed
            if not isinstance(gltf, dict):
                continue
            (out / (stem + ".min.gltf")).write_text(json.dumps(gltf, separators=(",", ":")))
            count += 1
            try:
                glb = make_glb(gltf)
            except (ValueError, TypeError, AttributeError):
                glb = None  # a malformed scene: no container for it
            if glb is not None and len(glb) <= MAX_SEED_BYTES:
                (out / (stem + ".glb")).write_bytes(glb)
                count += 1
    return count


if __name__ == "__main__":
    main()
