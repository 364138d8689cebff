#!/usr/bin/env python3
"""Writes the render-test scenes of the thin lens (standard library only).

usage: make_camera_scenes.py OUT_DIR

Each has an analytic criterion, stated beside its test in tests/render/CMakeLists.txt. A perspective camera at
z = 2 looks down -Z (yfov 0.7 rad) at black emitters (base colour 0, so nothing but emission reaches the film):
  lens_wall.gltf     an emitter of radiance 1 filling the view at z = 0: every pixel reads 1 through any aperture
                     focused anywhere (every ray from the lens meets the same radiance; no vignetting term).
  lens_checker.gltf  an 8 x 8 checker of emitters (radiance 1 and 0, cells 0.25 wide) at z = 0, 2 units ahead: in
                     focus (focus distance 2) a lens images it as the pinhole does.
  anim_square.gltf   an emitter of radiance 1, 0.5 wide, sliding along x from -1 at t = 0 to 1 at t = 1 (LINEAR):
                     posed at t = 0.5 it is where static_square.gltf has it, at x = 0.
  static_square.gltf the same square, not animated, at x = 0.
  skinned_square.gltf the square skinned to a joint that slides like anim_square's node (and a morph target of weight
                     0, animated to 0): posed at t = 0.5 it is where static_square.gltf has it.
  anim_camera.gltf   static_square.gltf's square, and the camera sliding along x from 1 at t = 0 to -1 at t = 1: the
                     square moves across its view as anim_square's does across the still camera's.
  spin_bar.gltf      an emitter bar 1 x 0.1 at z = 0 turning half a turn about its centre (+Z) from t = 0 to 1 (LINEAR
                     rotation keys every 90 degrees): turning in its plane it keeps its projected area, so motion blur
                     over the turn keeps the image mean of the still bar.
  lens_point.gltf    a 0.15 x 0.15 emitter at z = -6, 8 units ahead: out of focus it spreads into the aperture's
                     shape, of the thin-lens diameter c = A |d - s| / (d s) x H / (2 tan(yfov / 2)) pixels.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "stability" / "render"))
from make_stability_scenes import Gltf, quad  # noqa: E402

YFOV = 0.7
CAMERA_Z = 2.0


def scene_with(emitters):
    """emitters: [(triangles, radiance)], each a black-based emitter; the camera as the module says."""
    g = Gltf()
    for triangles, radiance in emitters:
        material = g.add_material(base=(0.0, 0.0, 0.0), emission=radiance)
        g.add_node({"mesh": g.add_mesh(triangles, material)})
    g.add_perspective_camera({"translation": [0.0, 0.0, CAMERA_Z]}, YFOV)
    return g


def checker():
    cells = ([], [])  # dark, lit: the dark cells are black surfaces, so --focus-on finds them too
    for i in range(8):
        for j in range(8):
            x0, y0 = -1.0 + 0.25 * i, -1.0 + 0.25 * j
            cells[(i + j) % 2 == 0].extend(quad(x0, y0, x0 + 0.25, y0 + 0.25, 0.0))
    return scene_with([(cells[0], 0.0), (cells[1], 1.0)])


def square(animated):
    g = scene_with([])
    material = g.add_material(base=(0.0, 0.0, 0.0), emission=1.0)
    node = g.add_node({"mesh": g.add_mesh(quad(-0.25, -0.25, 0.25, 0.25, 0.0), material)})
    if animated:
        times = g.add_floats([0.0, 1.0], "SCALAR", 2)
        values = g.add_floats([-1.0, 0.0, 0.0, 1.0, 0.0, 0.0])
        g.doc["animations"] = [{"name": "slide", "samplers": [{"input": times, "output": values}],
                                "channels": [{"sampler": 0, "target": {"node": node, "path": "translation"}}]}]
    return g


def sliding_camera():
    g = Gltf()
    material = g.add_material(base=(0.0, 0.0, 0.0), emission=1.0)
    g.add_node({"mesh": g.add_mesh(quad(-0.25, -0.25, 0.25, 0.25, 0.0), material)})
    camera = g.add_perspective_camera({"translation": [0.0, 0.0, CAMERA_Z]}, YFOV)
    times = g.add_floats([0.0, 1.0], "SCALAR", 2)
    values = g.add_floats([1.0, 0.0, CAMERA_Z, -1.0, 0.0, CAMERA_Z])
    g.doc["animations"] = [{"name": "pan", "samplers": [{"input": times, "output": values}],
                            "channels": [{"sampler": 0, "target": {"node": camera, "path": "translation"}}]}]
    return g


def spin_bar():
    g = scene_with([])
    material = g.add_material(base=(0.0, 0.0, 0.0), emission=1.0)
    node = g.add_node({"mesh": g.add_mesh(quad(-0.5, -0.05, 0.5, 0.05, 0.0), material)})
    h = 0.5 ** 0.5
    times = g.add_floats([0.0, 0.5, 1.0], "SCALAR", 3)
    turns = g.add_floats([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, h, h, 0.0, 0.0, 1.0, 0.0], "VEC4", 3)
    g.doc["animations"] = [{"name": "spin", "samplers": [{"input": times, "output": turns}],
                            "channels": [{"sampler": 0, "target": {"node": node, "path": "rotation"}}]}]
    return g


def skinned_square():
    g = scene_with([])
    material = g.add_material(base=(0.0, 0.0, 0.0), emission=1.0)
    triangles = quad(-0.25, -0.25, 0.25, 0.25, 0.0)
    mesh = g.add_mesh(triangles, material)
    vertices = 3 * len(triangles)
    prim = g.doc["meshes"][mesh]["primitives"][0]
    while len(g.blob) % 4:
        g.blob.append(0)
    offset = len(g.blob)
    g.blob += bytes([1, 0, 0, 0] * vertices)  # every vertex on joint 1 (unsigned byte JOINTS_0)
    g.doc["bufferViews"].append({"buffer": 0, "byteOffset": offset, "byteLength": 4 * vertices})
    g.doc["accessors"].append({"bufferView": len(g.doc["bufferViews"]) - 1, "componentType": 5121,
                               "count": vertices, "type": "VEC4"})
    prim["attributes"]["JOINTS_0"] = len(g.doc["accessors"]) - 1
    prim["attributes"]["WEIGHTS_0"] = g.add_floats([1.0, 0.0, 0.0, 0.0] * vertices, "VEC4", vertices)
    prim["targets"] = [{"POSITION": g.add_floats([0.0, 0.0, 5.0] * vertices)}]
    identity = [1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0]
    joint0 = g.add_node({}, root=False)
    joint1 = g.add_node({"translation": [-3.0, 0.0, 0.0]}, root=False)  # at rest elsewhere: the pose must move it
    g.add_node({"children": [joint0, joint1]})
    g.doc["skins"] = [{"joints": [joint0, joint1], "inverseBindMatrices": g.add_floats(identity * 2, "MAT4", 2)}]
    skinned = g.add_node({"mesh": mesh, "skin": 0, "translation": [7.0, 0.0, 0.0]})
    times = g.add_floats([0.0, 1.0], "SCALAR", 2)
    slide = g.add_floats([-1.0, 0.0, 0.0, 1.0, 0.0, 0.0])
    weights = g.add_floats([0.0, 0.0], "SCALAR", 2)
    g.doc["animations"] = [{"name": "slide", "samplers": [{"input": times, "output": slide},
                                                          {"input": times, "output": weights}],
                            "channels": [{"sampler": 0, "target": {"node": joint1, "path": "translation"}},
                                         {"sampler": 1, "target": {"node": skinned, "path": "weights"}}]}]
    return g


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    scenes = {
        "lens_wall": scene_with([(quad(-100.0, -100.0, 100.0, 100.0, 0.0), 1.0)]),
        "lens_checker": checker(),
        "anim_square": square(True),
        "static_square": square(False),
        "anim_camera": sliding_camera(),
        "spin_bar": spin_bar(),
        "skinned_square": skinned_square(),
        "lens_point": scene_with([(quad(-0.075, -0.075, 0.075, 0.075, -6.0), 1.0)]),
    }
    for name, g in scenes.items():
        g.write(out / f"{name}.gltf")


if __name__ == "__main__":
    main()
