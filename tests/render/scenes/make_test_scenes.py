#!/usr/bin/env python3
"""Writes the small analytic test scenes used by the render tests (standard library only).

furnace.gltf: a closed cube [-1,1]^3 whose inward faces are Lambertian with albedo RHO and emit LE from
their inner side only; a camera at the centre. Every pixel must read LE / (1 - RHO) with unlimited depth,
or LE (1 - RHO^D) / (1 - RHO) with --max-depth D.
"""
import base64
import json
import struct
import sys
from pathlib import Path

RHO = 0.8
LE = 0.5


def cube_faces_inward():
    """12 triangles of the cube [-1,1]^3, wound so (p1-p0)x(p2-p0) points into the cube."""
    tris = []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            u, v = (axis + 1) % 3, (axis + 2) % 3
            corners = []
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis], p[u], p[v] = sign, a, b
                corners.append(p)
            quad = [(0, 1, 2), (0, 2, 3)]
            for i, j, k in quad:
                t = [corners[i], corners[j], corners[k]]
                e1 = [t[1][n] - t[0][n] for n in range(3)]
                e2 = [t[2][n] - t[0][n] for n in range(3)]
                normal_axis = e1[(axis + 1) % 3] * e2[(axis + 2) % 3] - e1[(axis + 2) % 3] * e2[(axis + 1) % 3]
                if normal_axis * -sign < 0:  # must point towards the centre (-sign along axis)
                    t = [t[0], t[2], t[1]]
                tris.append(t)
    return tris


def gltf_with_triangles(tris, material, camera):
    positions = [c for t in tris for p in t for c in p]
    blob = struct.pack(f"<{len(positions)}f", *positions)
    lo = [min(positions[i::3]) for i in range(3)]
    hi = [max(positions[i::3]) for i in range(3)]
    return {
        "asset": {"version": "2.0", "generator": "fredholm tests/render/scenes/make_test_scenes.py"},
        "extensionsUsed": ["KHR_materials_emissive_strength", "KHR_materials_specular"],
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, **camera}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 1.2, "znear": 0.01}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
        "materials": [material],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(tris) * 3, "type": "VEC3",
                       "min": lo, "max": hi}],
        "bufferViews": [{"buffer": 0, "byteLength": len(blob)}],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
    }


def furnace():
    material = {
        "name": "furnace_wall",
        "doubleSided": False,
        "pbrMetallicRoughness": {"baseColorFactor": [RHO, RHO, RHO, 1.0], "metallicFactor": 0.0,
                                 "roughnessFactor": 1.0},
        "emissiveFactor": [1.0, 1.0, 1.0],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": LE},
                       "KHR_materials_specular": {"specularFactor": 0.0}},
    }
    return gltf_with_triangles(cube_faces_inward(), material, {"translation": [0.1, -0.2, 0.3]})


def main():
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent
    (out / "furnace.gltf").write_text(json.dumps(furnace(), indent=1) + "\n")


if __name__ == "__main__":
    main()
