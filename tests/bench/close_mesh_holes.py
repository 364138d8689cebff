#!/usr/bin/env python3
"""Writes one node of a glTF model as a closed mesh: its holes filled, optionally its smaller pieces dropped.

A volume (KHR_materials_volume) needs a closed surface, and modelled assets often lack one (Blender's Suzanne has
holes at its eyes, plugged by eyeballs that are open hemispheres). This makes a closed variant of such a mesh, to
compare renderers on it (shaders/lib/bsdf/README.md "Glass", "Open meshes"):

  /opt/refbench/cycles-venv/bin/python tests/bench/close_mesh_holes.py \\
      ../shared/scenes-thirdparty/IridescenceSuzanne/glTF/IridescenceSuzanne.gltf Suzanne3 /tmp/head.gltf --keep-largest
  /opt/refbench/cycles-venv/bin/python tests/bench/compare_assets.py --models /tmp/head.gltf --without iridescence

Each boundary loop (edges used by one triangle) is closed by a fan around the loop's centroid, wound against the
loop so that the fan faces the same way as the surface, with the fan's flat normal. --keep-largest first drops every
connected piece but the one with the most triangles. Prints the boundary loops found, the edge use counts after (all
2 for a closed mesh) and the signed volume (positive: wound outwards). The output keeps the node's first primitive,
its material and the model's textures (their images are copied beside OUT); the node's transform is dropped.
"""
import argparse
import collections
import json
import os
import shutil

import numpy as np

COMPONENT_TYPES = {5126: np.float32, 5125: np.uint32, 5123: np.uint16, 5121: np.uint8}
WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def read_accessor(doc, buffers, index):
    a = doc["accessors"][index]
    view = doc["bufferViews"][a["bufferView"]]
    width = WIDTHS[a["type"]]
    data = np.frombuffer(buffers[view["buffer"]], dtype=COMPONENT_TYPES[a["componentType"]], count=a["count"] * width,
                         offset=view.get("byteOffset", 0) + a.get("byteOffset", 0))
    return data.reshape(-1, width) if width > 1 else data


def weld(positions):
    """One index per distinct position (rounded to 1e-5), so that split vertices (seams) count as one."""
    ids = {}
    return np.array([ids.setdefault(tuple(np.round(p, 5)), len(ids)) for p in positions])


def largest_piece(triangles, welded):
    parent = list(range(int(welded.max()) + 1))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for t in welded[triangles]:
        parent[find(t[0])] = find(t[1])
        parent[find(t[1])] = find(t[2])
    pieces = collections.Counter(find(welded[t[0]]) for t in triangles)
    print("pieces (triangles):", sorted(pieces.values(), reverse=True))
    biggest = pieces.most_common(1)[0][0]
    return triangles[[find(welded[t[0]]) == biggest for t in triangles]]


def boundary_loops(triangles, welded):
    directed = set()
    for t in welded[triangles]:
        directed.update(((t[0], t[1]), (t[1], t[2]), (t[2], t[0])))
    following = {a: b for (a, b) in directed if (b, a) not in directed}
    loops, seen = [], set()
    for start in following:
        if start in seen:
            continue
        loop, v = [], start
        while v not in seen:
            seen.add(v)
            loop.append(v)
            v = following[v]
        loops.append(loop)
    return loops


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("model", help=".gltf with external buffers")
    ap.add_argument("node", help="the node's name")
    ap.add_argument("out", help="the closed mesh's .gltf (its .bin beside it)")
    ap.add_argument("--keep-largest", action="store_true", help="drop every piece but the largest first")
    args = ap.parse_args()
    doc = json.load(open(args.model))
    base = os.path.dirname(os.path.abspath(args.model))
    buffers = [open(os.path.join(base, b["uri"]), "rb").read() for b in doc["buffers"]]
    node = next((n for n in doc["nodes"] if n.get("name") == args.node), None)
    if node is None or "mesh" not in node:
        raise SystemExit(f"close_mesh_holes: {args.model} has no mesh node named {args.node}")
    prim = doc["meshes"][node["mesh"]]["primitives"][0]
    positions = [tuple(p) for p in read_accessor(doc, buffers, prim["attributes"]["POSITION"]).astype(np.float32)]
    normals = [tuple(n) for n in read_accessor(doc, buffers, prim["attributes"]["NORMAL"]).astype(np.float32)]
    uv_index = prim["attributes"].get("TEXCOORD_0")
    uvs = [tuple(t) for t in read_accessor(doc, buffers, uv_index).astype(np.float32)] if uv_index is not None else None
    triangles = read_accessor(doc, buffers, prim["indices"]).astype(np.int64).reshape(-1, 3)
    welded = weld(positions)
    if args.keep_largest:
        triangles = largest_piece(triangles, welded)
    loops = boundary_loops(triangles, welded)
    print("boundary loops (edges):", [len(loop) for loop in loops])
    corner_of = {}
    for v, w in enumerate(welded):
        corner_of.setdefault(w, v)
    out_triangles = [tuple(t) for t in triangles]

    def add_vertex(p, n, uv):
        positions.append(tuple(p))
        normals.append(tuple(n))
        if uvs is not None:
            uvs.append(tuple(uv))
        return len(positions) - 1

    for loop in loops:
        corners = [corner_of[w] for w in loop]
        centre = np.mean([positions[v] for v in corners], axis=0)
        fan = [(corners[(k + 1) % len(corners)], corners[k]) for k in range(len(corners))]  # against the loop
        area = sum(np.cross(np.array(positions[a]) - centre, np.array(positions[b]) - centre) for a, b in fan)
        n = area / np.linalg.norm(area)
        c = add_vertex(centre, n, (0.0, 0.0))
        for a, b in fan:
            out_triangles.append((add_vertex(positions[a], n, uvs[a] if uvs else None),
                                  add_vertex(positions[b], n, uvs[b] if uvs else None), c))
    p = np.array(positions, np.float32)
    nrm = np.array(normals, np.float32)
    idx = np.array(out_triangles, np.uint32)
    uses = collections.Counter()
    for t in weld(p)[idx]:
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            uses[(min(a, b), max(a, b))] += 1
    corners = p[idx]
    volume = np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2])).sum() / 6.0
    print("edge use counts after:", dict(collections.Counter(uses.values())), "signed volume:", float(volume))

    arrays = [p, nrm] + ([np.array(uvs, np.float32)] if uvs is not None else []) + [idx.reshape(-1)]
    blob, views, accessors = b"", [], []
    for array, kind, component in zip(arrays, ["VEC3", "VEC3"] + (["VEC2"] if uvs is not None else []) + ["SCALAR"],
                                      [5126] * (len(arrays) - 1) + [5125]):
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": array.nbytes})
        accessor = {"bufferView": len(views) - 1, "componentType": component, "type": kind,
                    "count": len(array)}
        if kind == "VEC3" and not accessors:
            accessor["min"], accessor["max"] = array.min(0).tolist(), array.max(0).tolist()
        accessors.append(accessor)
        blob += array.tobytes()
    bin_name = os.path.splitext(os.path.basename(args.out))[0] + ".bin"
    with open(os.path.join(os.path.dirname(os.path.abspath(args.out)), bin_name), "wb") as f:
        f.write(blob)
    attributes = {"POSITION": 0, "NORMAL": 1}
    if uvs is not None:
        attributes["TEXCOORD_0"] = 2
    material = doc["materials"][prim["material"]]
    out = {"asset": {"version": "2.0", "generator": "close_mesh_holes.py"},
           "extensionsUsed": sorted(material.get("extensions", {})),
           "buffers": [{"uri": bin_name, "byteLength": len(blob)}], "bufferViews": views, "accessors": accessors,
           "materials": [material],
           "meshes": [{"primitives": [{"attributes": attributes, "indices": len(accessors) - 1, "material": 0}]}],
           "nodes": [{"name": args.node, "mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}
    for key in ("textures", "images", "samplers"):
        if key in doc:
            out[key] = doc[key]
    out_dir = os.path.dirname(os.path.abspath(args.out))
    for image in doc.get("images", []):
        if "uri" in image and not image["uri"].startswith("data:"):
            shutil.copyfile(os.path.join(base, image["uri"]), os.path.join(out_dir, image["uri"]))
    with open(args.out, "w") as f:
        json.dump(out, f)


if __name__ == "__main__":
    main()
