#!/usr/bin/env python3
"""Writes the large-mesh benchmark scene: a displaced icosphere inside an open box under one area light, as a .glb.

  python3 tests/bench/make_displaced_sphere.py --subdivisions 8 -o sphere8.glb      (1,310,720 sphere triangles)

The icosphere of `--subdivisions` S has 20 x 4^S triangles (S = 3: 1,280; 5: 20,480; 8: 1,310,720) with shared,
indexed vertices, displaced along the normal by a smooth sum of sinusoids (up to 6% of the radius), so that no two
triangles are alike and the BVH has no flat regions to exploit. It sits on the floor of a 6 x 6 x 4 box open towards
the camera (back wall, two side walls; the floor reaches under the camera), lit by a 1.5 x 1.5 emitting quad under the ceiling; every surface is
Lambertian (KHR_materials_specular specularFactor 0), so Mitsuba 3 and Embree-driven peers see the same scene
(tests/bench/compare_efficiency.py, compare_embree.py). Needs numpy.
"""
import argparse
import json
import struct

import numpy as np

PHI = (1.0 + 5.0 ** 0.5) / 2.0


def icosahedron():
    v = np.array([[-1, PHI, 0], [1, PHI, 0], [-1, -PHI, 0], [1, -PHI, 0], [0, -1, PHI], [0, 1, PHI],
                  [0, -1, -PHI], [0, 1, -PHI], [PHI, 0, -1], [PHI, 0, 1], [-PHI, 0, -1], [-PHI, 0, 1]], dtype=np.float64)
    f = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
                  [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11],
                  [6, 2, 10], [8, 6, 7], [9, 8, 1]], dtype=np.int64)
    return v / np.linalg.norm(v, axis=1, keepdims=True), f


def subdivide(v, f):
    """Each triangle into four, edge midpoints shared between neighbours and pushed onto the unit sphere."""
    edges = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    keys = np.sort(edges, axis=1)
    unique, inverse = np.unique(keys, axis=0, return_inverse=True)
    mid = v[unique[:, 0]] + v[unique[:, 1]]
    mid /= np.linalg.norm(mid, axis=1, keepdims=True)
    m = inverse.reshape(3, -1).T + len(v)  # midpoints of edges (01, 12, 20) of each face
    a, b, c = f[:, 0], f[:, 1], f[:, 2]
    ab, bc, ca = m[:, 0], m[:, 1], m[:, 2]
    faces = np.concatenate([np.stack([a, ab, ca], 1), np.stack([b, bc, ab], 1), np.stack([c, ca, bc], 1),
                            np.stack([ab, bc, ca], 1)])
    return np.concatenate([v, mid]), faces


def displaced_sphere(subdivisions):
    v, f = icosahedron()
    for _ in range(subdivisions):
        v, f = subdivide(v, f)
    x, y, z = v[:, 0], v[:, 1], v[:, 2]
    bumps = 0.03 * np.sin(7 * x + 3 * y) * np.cos(5 * z - 2 * x) + 0.02 * np.sin(13 * y + 11 * z) + \
        0.01 * np.sin(29 * x - 23 * y + 17 * z)
    return v * (1.0 + bumps)[:, None], f


def quad(x0, y0, z0, e1, e2):
    """Two triangles of the parallelogram at (x0, y0, z0) spanned by e1 and e2 (normal e1 x e2)."""
    p = np.array([x0, y0, z0], dtype=np.float64)
    e1, e2 = np.array(e1, dtype=np.float64), np.array(e2, dtype=np.float64)
    return np.array([p, p + e1, p + e1 + e2, p + e2]), np.array([[0, 1, 2], [0, 2, 3]])


def write_glb(path, meshes, camera):
    """meshes: (positions, indices, material dict); one node each, and a perspective camera node."""
    blob, views, accessors, gltf_meshes, nodes = bytearray(), [], [], [], []

    def add(data, target, kind, component):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": data.nbytes, "target": target})
        blob.extend(data.tobytes())
        accessor = {"bufferView": len(views) - 1, "componentType": component, "count": len(data), "type": kind}
        if kind == "VEC3":
            accessor["min"], accessor["max"] = data.min(0).tolist(), data.max(0).tolist()
        accessors.append(accessor)
        return len(accessors) - 1

    materials = []
    for positions, indices, material in meshes:
        pos = add(positions.astype(np.float32), 34962, "VEC3", 5126)
        idx = add(indices.astype(np.uint32).reshape(-1), 34963, "SCALAR", 5125)
        materials.append(material)
        gltf_meshes.append({"primitives": [{"attributes": {"POSITION": pos}, "indices": idx,
                                            "material": len(materials) - 1}]})
        nodes.append({"mesh": len(gltf_meshes) - 1})
    nodes.append({"camera": 0, **camera["node"]})
    doc = {"asset": {"version": "2.0", "generator": "fredholm tests/bench/make_displaced_sphere.py"},
           "extensionsUsed": ["KHR_materials_specular", "KHR_materials_emissive_strength"],
           "scene": 0, "scenes": [{"nodes": list(range(len(nodes)))}], "nodes": nodes, "meshes": gltf_meshes,
           "materials": materials, "accessors": accessors, "bufferViews": views,
           "buffers": [{"byteLength": len(blob)}], "cameras": [camera["camera"]]}
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    blob += b"\0" * (-len(blob) % 4)
    with open(path, "wb") as out:
        out.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(blob)))
        out.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
        out.write(struct.pack("<II", len(blob), 0x004E4942) + bytes(blob))


def lambert(colour, emission=0.0):
    m = {"pbrMetallicRoughness": {"baseColorFactor": [*colour, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0},
         "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}
    if emission > 0.0:
        m["emissiveFactor"] = [1.0, 1.0, 1.0]
        m["extensions"]["KHR_materials_emissive_strength"] = {"emissiveStrength": emission}
    return m


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--subdivisions", type=int, default=8)
    ap.add_argument("-o", "--output", required=True)
    args = ap.parse_args()
    v, f = displaced_sphere(args.subdivisions)
    v = v + np.array([0.0, 1.06, 0.0])  # resting on the floor at y = 0
    meshes = [(v, f, lambert((0.7, 0.7, 0.7)))]
    for corner, e1, e2, colour in [((-3, 0, 9), (6, 0, 0), (0, 0, -12), (0.75, 0.75, 0.75)),   # floor, up
                                   ((-3, 0, -3), (6, 0, 0), (0, 4, 0), (0.75, 0.75, 0.75)),    # back wall, facing +z
                                   ((-3, 0, 3), (0, 0, -6), (0, 4, 0), (0.63, 0.065, 0.05)),   # left wall, facing +x
                                   ((3, 0, -3), (0, 0, 6), (0, 4, 0), (0.14, 0.45, 0.091))]:   # right wall, facing -x
        positions, indices = quad(*corner, e1, e2)
        meshes.append((positions, indices, lambert(colour)))
    positions, indices = quad(-0.75, 3.99, -0.75, (1.5, 0, 0), (0, 0, 1.5))  # light under the ceiling, facing down
    meshes.append((positions, indices, lambert((0.0, 0.0, 0.0), emission=12.0)))
    camera = {"camera": {"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.01, "aspectRatio": 1.0}},
              "node": {"translation": [0.0, 2.0, 7.5], "rotation": [-0.0868, 0.0, 0.0, 0.9962]}}
    write_glb(args.output, meshes, camera)
    print(f"wrote {args.output}: {len(f)} sphere triangles, {len(v)} vertices")


if __name__ == "__main__":
    main()
