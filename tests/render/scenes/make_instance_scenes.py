#!/usr/bin/env python3
"""Writes the render-test scenes for instancing (standard library only).

usage: make_instance_scenes.py OUT_DIR

  instances_nodes.gltf  a floor and a ceiling light (world space) and one smooth icosphere mesh drawn by nine
                        nodes: rotated, non-uniformly scaled and one mirrored (negative scale). The loader
                        stores the sphere once and places it nine times (two-level BVH).
  instances_gpu.gltf    the same nine placements as one node with EXT_mesh_gpu_instancing: must render
                        bit-identical to instances_nodes.gltf (both are the same instances).
  instances_billion.gltf a 100,352-triangle grid mesh drawn 10,000 times by EXT_mesh_gpu_instancing
                        (1,003,520,000 rendered triangles) under a directional light: must load and render.
Transforms use values exact in float, so that node TRS (JSON doubles) and instancing accessors (floats) agree.
"""
import json
import math
import struct
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "stability" / "render"))
from make_stability_scenes import Gltf, icosphere  # noqa: E402


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def quat(axis, degrees):
    """Unit quaternion (x, y, z, w) rounded to float."""
    n = math.sqrt(sum(a * a for a in axis))
    s = math.sin(math.radians(degrees) / 2.0)
    return [f32(a / n * s) for a in axis] + [f32(math.cos(math.radians(degrees) / 2.0))]


PLACEMENTS = [  # translation, rotation, scale
    ([-1.0, 0.5, -1.0], quat((0, 1, 0), 0.0), [0.5, 0.5, 0.5]),
    ([0.0, 0.5, -1.0], quat((1, 0, 0), 30.0), [0.5, 0.25, 0.5]),
    ([1.0, 0.5, -1.0], quat((0, 0, 1), 45.0), [0.25, 0.5, 0.375]),
    ([-1.0, 0.5, 0.0], quat((1, 1, 0), 60.0), [0.5, 0.5, 0.5]),
    ([0.0, 0.5, 0.0], quat((0, 1, 1), 90.0), [-0.5, 0.5, 0.5]),  # mirrored
    ([1.0, 0.375, 0.0], quat((1, 0, 1), 120.0), [0.375, 0.375, 0.375]),
    ([-1.0, 0.25, 1.0], quat((0, 1, 0), 150.0), [0.25, 0.25, 0.5]),
    ([0.0, 0.5, 1.0], quat((1, 1, 1), 200.0), [0.5, 0.375, 0.25]),
    ([1.0, 0.5, 1.0], quat((0, 1, 0), 270.0), [0.5, 0.5, 0.5]),
]


def quad(c, e1, e2):
    """Two triangles of the parallelogram at corner c with edges e1, e2; front face cross(e1, e2)."""
    p = [tuple(c[k] + a * e1[k] + b * e2[k] for k in range(3)) for a, b in ((0, 0), (1, 0), (1, 1), (0, 1))]
    return [(p[0], p[1], p[2]), (p[0], p[2], p[3])]


def add_accessor(g, fmt_values, kind, count):
    while len(g.blob) % 4:
        g.blob.append(0)
    offset = len(g.blob)
    g.blob += fmt_values
    g.doc["bufferViews"].append({"buffer": 0, "byteOffset": offset, "byteLength": len(fmt_values)})
    g.doc["accessors"].append({"bufferView": len(g.doc["bufferViews"]) - 1, "componentType": 5126, "count": count,
                               "type": kind})
    return len(g.doc["accessors"]) - 1


def room(g):
    white = g.add_material()
    light = g.add_material(emission=4.0)
    floor = quad((-3, 0, -3), (0, 0, 6), (6, 0, 0))  # faces +y
    g.add_node({"mesh": g.add_mesh(floor, white)})
    ceiling = quad((-1, 3, -1), (2, 0, 0), (0, 0, 2))  # faces -y
    g.add_node({"mesh": g.add_mesh(ceiling, light)})
    g.add_perspective_camera({"translation": [0.0, 3.5, 4.0], "rotation": quat((1, 0, 0), -40.0)}, yfov=0.9)


def sphere_mesh(g):
    triangles = icosphere(2)
    normals = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for t in triangles for p in t]
    return g.add_mesh(triangles, g.add_material(base=(0.7, 0.5, 0.3)), normals=normals)


def write_nodes(out):
    g = Gltf()
    room(g)
    sphere = sphere_mesh(g)
    for t, r, s in PLACEMENTS:
        g.add_node({"mesh": sphere, "translation": t, "rotation": r, "scale": s})
    g.write(out / "instances_nodes.gltf")


def write_gpu(out):
    g = Gltf()
    room(g)
    sphere = sphere_mesh(g)
    n = len(PLACEMENTS)
    attributes = {
        "TRANSLATION": add_accessor(g, struct.pack(f"<{3 * n}f", *[c for t, _, _ in PLACEMENTS for c in t]), "VEC3", n),
        "ROTATION": add_accessor(g, struct.pack(f"<{4 * n}f", *[c for _, r, _ in PLACEMENTS for c in r]), "VEC4", n),
        "SCALE": add_accessor(g, struct.pack(f"<{3 * n}f", *[c for _, _, s in PLACEMENTS for c in s]), "VEC3", n),
    }
    g.doc["extensionsUsed"].append("EXT_mesh_gpu_instancing")
    g.add_node({"mesh": sphere, "extensions": {"EXT_mesh_gpu_instancing": {"attributes": attributes}}})
    g.write(out / "instances_gpu.gltf")


def write_billion(out):
    g = Gltf()
    cells = 224  # 224 x 224 x 2 = 100,352 triangles, indexed
    vertices = []
    for j in range(cells + 1):
        for i in range(cells + 1):
            x, z = i / cells - 0.5, j / cells - 0.5
            vertices += [x, 0.05 * math.sin(20.0 * x) * math.cos(20.0 * z), z]
    indices = []
    for j in range(cells):
        for i in range(cells):
            a = j * (cells + 1) + i
            indices += [a, a + cells + 1, a + 1, a + 1, a + cells + 1, a + cells + 2]
    position = add_accessor(g, struct.pack(f"<{len(vertices)}f", *vertices), "VEC3", len(vertices) // 3)
    g.doc["accessors"][position]["min"] = [min(vertices[k::3]) for k in range(3)]
    g.doc["accessors"][position]["max"] = [max(vertices[k::3]) for k in range(3)]
    index = add_accessor(g, struct.pack(f"<{len(indices)}I", *indices), "SCALAR", len(indices))
    g.doc["accessors"][index]["componentType"] = 5125
    g.doc["meshes"].append({"primitives": [{"attributes": {"POSITION": position}, "indices": index,
                                            "material": g.add_material()}]})
    side = 100
    translations = [c for j in range(side) for i in range(side) for c in (i - side / 2, 0.0, j - side / 2)]
    attributes = {"TRANSLATION": add_accessor(g, struct.pack(f"<{len(translations)}f", *translations), "VEC3",
                                              side * side)}
    g.doc["extensionsUsed"].append("EXT_mesh_gpu_instancing")
    g.add_node({"mesh": len(g.doc["meshes"]) - 1, "extensions": {"EXT_mesh_gpu_instancing": {"attributes": attributes}}})
    g.doc["extensions"]["KHR_lights_punctual"]["lights"].append(
        {"type": "directional", "intensity": 3.0, "color": [1.0, 1.0, 1.0]})
    g.add_node({"extensions": {"KHR_lights_punctual": {"light": 0}}, "rotation": quat((1, 0, 0), -60.0)})
    g.add_perspective_camera({"translation": [0.0, 12.0, 40.0], "rotation": quat((1, 0, 0), -15.0)}, yfov=1.0)
    g.write(out / "instances_billion.gltf")


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    write_nodes(out)
    write_gpu(out)
    write_billion(out)


if __name__ == "__main__":
    main()
