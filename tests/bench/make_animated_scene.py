#!/usr/bin/env python3
"""Writes animated_boxes.gltf: a scene that exercises every kind of glTF animation, for comparing Fredholm's poses with
Blender's glTF importer (compare_assets.py --time T). Standard library only.

usage: make_animated_scene.py OUT_DIR

Diffuse (Lambertian: KHR_materials_specular 0) surfaces over a static ground square, animated from t = 0 to t = 1:
- a box that turns a quarter turn about +Y and slides along +X (node TRS, LINEAR: slerp and lerp);
- a bar of 8 x 1 cells skinned to two joints: the second turns 60 degrees about +Z; the vertices of the middle cell
  belong half to each joint (linear blend skinning);
- a square whose morph target raises one corner by 1, its weight animated from 0 to 1 (CUBICSPLINE, zero tangents);
- a box that jumps up by 0.5 at t = 0.5 (STEP).
At t = 0.5 (frame 12 at 24 fps) each two-key rotation is half-way, where slerp and Blender's normalised
component-wise interpolation agree.
"""
import math
import struct
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "stability" / "render"))
from make_stability_scenes import Gltf, quad  # noqa: E402


def box(x0, y0, z0, x1, y1, z1):
    """12 triangles of an axis-aligned box, outward (glTF counter-clockwise front faces)."""
    p = [(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]  # index = 4 xi + 2 yi + zi
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = []
    for a, b, c, d in faces:
        tris += [(p[a], p[b], p[c]), (p[a], p[c], p[d])]
    return tris


def diffuse(g, rgb):
    m = g.add_material(base=rgb)
    return m


def channel(g, animation, node, path, times, values, kind, count, interpolation="LINEAR"):
    t = g.add_floats(times, "SCALAR", len(times))
    v = g.add_floats(values, kind, count)
    animation["samplers"].append({"input": t, "output": v, "interpolation": interpolation})
    animation["channels"].append({"sampler": len(animation["samplers"]) - 1, "target": {"node": node, "path": path}})


def add_bytes(g, data, component_type, count, kind):
    while len(g.blob) % 4:
        g.blob.append(0)
    offset = len(g.blob)
    g.blob += data
    g.doc["bufferViews"].append({"buffer": 0, "byteOffset": offset, "byteLength": len(data)})
    g.doc["accessors"].append({"bufferView": len(g.doc["bufferViews"]) - 1, "componentType": component_type,
                               "count": count, "type": kind})
    return len(g.doc["accessors"]) - 1


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    g = Gltf()
    anim = {"name": "everything", "samplers": [], "channels": []}
    g.add_node({"mesh": g.add_mesh(quad(-2.2, -1.6, 2.8, 1.6, 0.0), diffuse(g, (0.7, 0.7, 0.7)))}, root=False)
    g.doc["nodes"][-1]["rotation"] = [-math.sqrt(0.5), 0, 0, math.sqrt(0.5)]  # the xy square onto the xz ground
    g.doc["scenes"][0]["nodes"].append(len(g.doc["nodes"]) - 1)

    # Turning, sliding box.
    turning = g.add_node({"mesh": g.add_mesh(box(-0.4, 0, -0.4, 0.4, 0.8, 0.4), diffuse(g, (0.8, 0.3, 0.2))),
                          "translation": [-1.5, 0, 0]})
    s = math.sqrt(0.5)
    channel(g, anim, turning, "rotation", [0.0, 1.0], [0, 0, 0, 1, 0, s, 0, s], "VEC4", 2)
    channel(g, anim, turning, "translation", [0.0, 1.0], [-1.5, 0, 0, -0.5, 0, 0], "VEC3", 2)

    # Skinned bar along +x from 0 to 2 (8 cells), 0.25 tall, its front face toward +z; joints at x = 0 and x = 1.
    tris, joints, weights = [], [], []
    for i in range(8):
        x0, x1 = 0.25 * i, 0.25 * (i + 1)
        cell = [((x0, 0, 0.2), (x1, 0, 0.2), (x1, 0.25, 0.2)), ((x0, 0, 0.2), (x1, 0.25, 0.2), (x0, 0.25, 0.2))]
        for t in cell:
            for p in t:
                w1 = 0.0 if p[0] < 0.999 else (0.5 if p[0] < 1.001 else 1.0)
                joints += [0, 1, 0, 0]
                weights += [1.0 - w1, w1, 0.0, 0.0]
        tris += cell
    bar_mesh = g.add_mesh(tris, diffuse(g, (0.2, 0.6, 0.8)))
    prim = g.doc["meshes"][bar_mesh]["primitives"][0]
    prim["attributes"]["JOINTS_0"] = add_bytes(g, bytes(joints), 5121, len(joints) // 4, "VEC4")
    prim["attributes"]["WEIGHTS_0"] = g.add_floats(weights, "VEC4", len(weights) // 4)
    j1 = g.add_node({"translation": [1.0, 0, 0]}, root=False)
    j0 = g.add_node({"children": [j1], "translation": [0.5, 0.3, 0.5]})
    inverse_bind = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -0.5, -0.3, -0.5, 1,   # inverse of j0's world (translate)
                    1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1.5, -0.3, -0.5, 1]   # inverse of j1's world
    g.doc["skins"] = [{"joints": [j0, j1], "inverseBindMatrices": g.add_floats(inverse_bind, "MAT4", 2)}]
    g.add_node({"mesh": bar_mesh, "skin": 0, "translation": [0.5, 0.3, 0.5]})
    z60 = math.sin(math.radians(30)), math.cos(math.radians(30))
    channel(g, anim, j1, "rotation", [0.0, 1.0], [0, 0, 0, 1, 0, 0, z60[0], z60[1]], "VEC4", 2)

    # Morphing square: its target lifts the (+x, +y) corner by 1 (two triangles, the corner in both).
    sq = quad(0.0, 0.0, 1.0, 1.0, 0.0)
    lift = [c for t in sq for p in t for c in ((0.0, 0.0, 1.0) if p[0] == 1.0 and p[1] == 1.0 else (0.0, 0.0, 0.0))]
    sq_mesh = g.add_mesh(sq, diffuse(g, (0.9, 0.8, 0.2)))
    g.doc["meshes"][sq_mesh]["primitives"][0]["targets"] = [{"POSITION": g.add_floats(lift)}]
    g.doc["meshes"][sq_mesh]["weights"] = [0.0]
    morph = g.add_node({"mesh": sq_mesh, "translation": [-0.5, 0.01, 1.2], "rotation": [-s, 0, 0, s]})
    channel(g, anim, morph, "weights", [0.0, 1.0], [0.0, 0.0, 0.0, 0.0, 1.0, 0.0], "SCALAR", 6, "CUBICSPLINE")

    # Stepping box.
    step = g.add_node({"mesh": g.add_mesh(box(-0.25, 0, -0.25, 0.25, 0.5, 0.25), diffuse(g, (0.5, 0.8, 0.3))),
                       "translation": [2.2, 0, -1.0]})
    channel(g, anim, step, "translation", [0.0, 0.5], [2.2, 0, -1.0, 2.2, 0.5, -1.0], "VEC3", 2, "STEP")

    g.doc["animations"] = [anim]
    g.write(out / "animated_boxes.gltf")
    print(out / "animated_boxes.gltf")


if __name__ == "__main__":
    main()
