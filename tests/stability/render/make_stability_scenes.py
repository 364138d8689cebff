#!/usr/bin/env python3
"""Writes the adversarial scenes of the stability suite (standard library only) into OUT_DIR.

usage: make_stability_scenes.py CORNELL.gltf OUT_DIR

Every scene has an analytic or a comparative pass criterion; tests/stability/render/CMakeLists.txt states it
next to the test that renders the scene. Units: emission and punctual intensities in the scene's radiometric
units (the renderer does not convert candela or lux).
"""
import base64
import copy
import json
import math
import struct
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "render" / "scenes"))
from make_test_scenes import cube_faces_inward  # noqa: E402 (the furnace cube [-1,1]^3, inward faces)

RHO = 0.8  # albedo of the furnace and grazing-light surfaces
LE = 0.5   # furnace emission: every pixel reads LE / (1 - RHO) = 2.5


# ---- glTF assembly ----------------------------------------------------------------------------------------

class Gltf:
    """A glTF document with one embedded buffer; meshes are lists of triangles ((p0, p1, p2), ...)."""

    def __init__(self):
        self.doc = {"asset": {"version": "2.0", "generator": "fredholm make_stability_scenes.py"},
                    "extensionsUsed": ["KHR_materials_emissive_strength", "KHR_materials_specular",
                                       "KHR_lights_punctual"],
                    "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "materials": [],
                    "accessors": [], "bufferViews": [], "cameras": [],
                    "extensions": {"KHR_lights_punctual": {"lights": []}}}
        self.blob = bytearray()

    def add_floats(self, values, kind="VEC3", count=None):
        while len(self.blob) % 4:
            self.blob.append(0)
        offset = len(self.blob)
        self.blob += struct.pack(f"<{len(values)}f", *values)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": offset, "byteLength": 4 * len(values)})
        n = count if count is not None else len(values) // 3
        accessor = {"bufferView": len(self.doc["bufferViews"]) - 1, "componentType": 5126, "count": n, "type": kind}
        finite = [v for v in values if math.isfinite(v)]
        if kind == "VEC3" and len(finite) == len(values) and values:
            accessor["min"] = [min(values[i::3]) for i in range(3)]
            accessor["max"] = [max(values[i::3]) for i in range(3)]
        self.doc["accessors"].append(accessor)
        return len(self.doc["accessors"]) - 1

    def add_material(self, base=(RHO, RHO, RHO), emission=0.0, emission_color=(1.0, 1.0, 1.0), double_sided=False):
        m = {"doubleSided": double_sided,
             "pbrMetallicRoughness": {"baseColorFactor": [*base, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0},
             "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}
        if emission > 0.0:
            m["emissiveFactor"] = list(emission_color)
            m["extensions"]["KHR_materials_emissive_strength"] = {"emissiveStrength": emission}
        self.doc["materials"].append(m)
        return len(self.doc["materials"]) - 1

    def add_mesh(self, triangles, material, normals=None):
        positions = [c for t in triangles for p in t for c in p]
        attributes = {"POSITION": self.add_floats(positions)}
        if normals is not None:
            attributes["NORMAL"] = self.add_floats([c for n in normals for c in n])
        self.doc["meshes"].append({"primitives": [{"attributes": attributes, "material": material}]})
        return len(self.doc["meshes"]) - 1

    def add_node(self, node, root=True):
        self.doc["nodes"].append(node)
        index = len(self.doc["nodes"]) - 1
        if root:
            self.doc["scenes"][0]["nodes"].append(index)
        return index

    def add_perspective_camera(self, node, yfov=1.0, root=True):
        self.doc["cameras"].append({"type": "perspective", "perspective": {"yfov": yfov, "znear": 0.001}})
        return self.add_node({"camera": len(self.doc["cameras"]) - 1, **node}, root)

    def add_orthographic_camera(self, node, half_extent, root=True):
        self.doc["cameras"].append({"type": "orthographic", "orthographic": {
            "xmag": half_extent, "ymag": half_extent, "znear": 0.0, "zfar": 1e9}})
        return self.add_node({"camera": len(self.doc["cameras"]) - 1, **node}, root)

    def add_light(self, light, node, root=True):
        lights = self.doc["extensions"]["KHR_lights_punctual"]["lights"]
        lights.append(light)
        return self.add_node({"extensions": {"KHR_lights_punctual": {"light": len(lights) - 1}}, **node}, root)

    def write(self, path):
        d = copy.deepcopy(self.doc)
        d["buffers"] = [{"byteLength": len(self.blob),
                         "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(self.blob)).decode()}]
        for key in ("cameras", "meshes", "materials"):
            if not d[key]:
                del d[key]
        if not d["extensions"]["KHR_lights_punctual"]["lights"]:
            del d["extensions"]
        Path(path).write_text(json.dumps(d, indent=1) + "\n")


def wrap_roots(doc, node):
    """Puts every root node of scene 0 under one new node (scale / translation), cameras included."""
    roots = doc["scenes"][0]["nodes"]
    doc["nodes"].append({**node, "children": roots})
    doc["scenes"][0]["nodes"] = [len(doc["nodes"]) - 1]
    return doc


# Quaternion (x, y, z, w) turning the camera's -Z view direction to look straight down (-Y... here -Z world).
LOOK_DOWN = [0.0, 0.0, 0.0, 1.0]  # cameras look down their -Z: place them above a plane at z = 0


def quad(x0, y0, x1, y1, z, facing_up=True):
    """Two triangles of the rectangle [x0,x1]x[y0,y1] at height z, front face +z (or -z)."""
    a, b, c, d = (x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)
    if facing_up:
        return [(a, b, c), (a, c, d)]
    return [(a, c, b), (a, d, c)]


def icosphere(level, radius=1.0, inward=False):
    """Triangles of a subdivided icosahedron on a sphere of `radius` at the origin (outward winding)."""
    t = (1.0 + 5.0 ** 0.5) / 2.0
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
             (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
             (6, 2, 10), (8, 6, 7), (9, 8, 1)]

    def unit(p):
        n = math.sqrt(sum(c * c for c in p))
        return tuple(c / n for c in p)

    tris = [tuple(unit(verts[i]) for i in f) for f in faces]
    for _ in range(level):
        finer = []
        for a, b, c in tris:
            ab, bc, ca = (unit(tuple((x + y) / 2 for x, y in zip(p, q))) for p, q in ((a, b), (b, c), (c, a)))
            finer += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
        tris = finer
    out = []
    for a, b, c in tris:
        tri = tuple(tuple(radius * x for x in p) for p in (a, b, c))
        out.append((tri[0], tri[2], tri[1]) if inward else tri)
    return out


def uv_sphere(segments, rings, radius):
    """A low-poly UV sphere with smooth (analytic) vertex normals: triangles and per-corner normals."""
    def point(i, j):
        if j in (0, rings):  # exact poles, so the degenerate halves of the polar quads are recognised
            return (0.0, 0.0, 1.0 if j == 0 else -1.0)
        theta, phi = math.pi * j / rings, 2.0 * math.pi * (i % segments) / segments  # closed seam
        return (math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta))

    tris, normals = [], []
    for j in range(rings):
        for i in range(segments):
            a, b, c, d = point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1)
            for t in ((a, d, c), (a, c, b)):
                if len({t[0], t[1], t[2]}) < 3:
                    continue  # the poles' degenerate halves
                tris.append(tuple(tuple(radius * x for x in p) for p in t))
                normals += list(t)
    return tris, normals


# ---- Scenes -----------------------------------------------------------------------------------------------

def cornell_variants(cornell, out):
    """Cornell box scaled by s or translated by t (camera inside the wrapper, so it moves with the box)."""
    base = json.loads(Path(cornell).read_text())
    for s in ("1e-4", "1e-2", "1e2", "1e4"):
        f = float(s)
        doc = wrap_roots(copy.deepcopy(base), {"scale": [f, f, f]})
        (out / f"cornell_scale_{s}.gltf").write_text(json.dumps(doc) + "\n")
    for t in ("1e3", "1e5", "1e7"):
        f = float(t)
        doc = wrap_roots(copy.deepcopy(base), {"translation": [f, 0.5 * f, -0.7 * f]})
        (out / f"cornell_translate_{t}.gltf").write_text(json.dumps(doc) + "\n")
    (out / "cornell.gltf").write_text(json.dumps(base) + "\n")


def box_furnaces(out):
    """The closed furnace (every pixel LE / (1 - RHO)) scaled and translated: rays must never escape."""
    for name, node in (("scale_1e-4", {"scale": [1e-4] * 3}), ("scale_1e4", {"scale": [1e4] * 3}),
                       ("translate_1e5", {"translation": [1e5, -2e5, 3e5]})):
        g = Gltf()
        wall = g.add_material(emission=LE)
        mesh = g.add_mesh(cube_faces_inward(), wall)
        inner = [g.add_node({"mesh": mesh}, root=False),
                 g.add_perspective_camera({"translation": [0.1, -0.2, 0.3]}, yfov=1.2, root=False)]
        g.add_node({**node, "children": inner})
        g.write(out / f"box_furnace_{name}.gltf")


def point_light_spheres(out):
    """A point light of intensity I at the centre of a closed Lambertian sphere of radius R (albedo 0.5):
    the wall's irradiance is I / R^2 everywhere, and with all bounces L = rho I / (pi R^2 (1 - rho))."""
    for name, radius in (("", 1.0), ("_tiny", 1e-3), ("_huge", 1e3)):
        g = Gltf()
        wall = g.add_material(base=(0.5, 0.5, 0.5))
        g.add_node({"mesh": g.add_mesh(icosphere(4, radius, inward=True), wall)})
        g.add_light({"type": "point", "intensity": radius * radius}, {})  # I / R^2 = 1
        g.add_perspective_camera({"translation": [0.2 * radius, 0.1 * radius, 0.0]}, yfov=1.0)
        g.write(out / f"sphere_point_light{name}.gltf")


def grazing_planes(out):
    """A Lambertian plane (albedo RHO) lit by a directional light of irradiance 1 at angle theta from the
    normal: every pixel reads RHO cos(theta) / pi. Also translated to 1e4."""
    for angle in ("0", "60", "85", "89.5"):
        theta = math.radians(float(angle))
        for suffix, offset in (("", [0.0, 0.0, 0.0]), ("_far", [1e4, -1e4, 1e4])):
            g = Gltf()
            plane = g.add_mesh(quad(-5, -5, 5, 5, 0.0), g.add_material())
            # Light travels along (sin, 0, -cos): rotate the node's -Z by theta about the y axis.
            rotation = [0.0, math.sin(-theta / 2), 0.0, math.cos(-theta / 2)]
            children = [g.add_node({"mesh": plane}, root=False),
                        g.add_light({"type": "directional", "intensity": 1.0}, {"rotation": rotation}, root=False),
                        g.add_orthographic_camera({"translation": [0.0, 0.0, 2.0]}, 1.0, root=False)]
            g.add_node({"translation": offset, "children": children})
            g.write(out / f"grazing_{angle}{suffix}.gltf")


def small_far_lights(out):
    """A receiving plane (albedo 0.5) under a light giving irradiance 1 at the point seen by a tiny
    orthographic camera: every pixel reads 0.5 / pi."""
    def receiver(g):
        return g.add_node({"mesh": g.add_mesh(quad(-2, -2, 2, 2, 0.0), g.add_material(base=(0.5, 0.5, 0.5)))},
                          root=False)

    def camera(g):
        return g.add_orthographic_camera({"translation": [0.0, 0.0, 0.5]}, 1e-3, root=False)

    # Le 1e6 on a square of side 1e-3 at height 1: E = Le A / d^2 (1 - O(1e-6)) = 1.
    for suffix, offset in (("", [0, 0, 0]), ("_far", [1e4, 2e4, -1e4])):
        g = Gltf()
        light = g.add_mesh(quad(-5e-4, -5e-4, 5e-4, 5e-4, 1.0, facing_up=False),
                           g.add_material(base=(0, 0, 0), emission=1e6))
        g.add_node({"translation": offset, "children": [receiver(g), camera(g), g.add_node({"mesh": light}, root=False)]})
        g.write(out / f"small_bright_light{suffix}.gltf")
    # Le 1e4 on a square of side 1e3 at height 1e5: E = 1e4 * 1e6 / 1e10 = 1 (half-angle 0.005 rad: -2.5e-5).
    g = Gltf()
    light = g.add_mesh(quad(-500, -500, 500, 500, 1e5, facing_up=False), g.add_material(base=(0, 0, 0), emission=1e4))
    g.add_node({"children": [receiver(g), camera(g), g.add_node({"mesh": light}, root=False)]})
    g.write(out / "far_area_light.gltf")
    # A point light of intensity 1e10 at height 1e5: E = 1.
    g = Gltf()
    g.add_node({"children": [receiver(g), camera(g),
                             g.add_light({"type": "point", "intensity": 1e10}, {"translation": [0, 0, 1e5]}, root=False)]})
    g.write(out / "far_point_light.gltf")


def accumulation(out):
    """An emitter of radiance 0.1 filling an orthographic view."""
    g = Gltf()
    g.add_node({"mesh": g.add_mesh(quad(-2, -2, 2, 2, 0.0), g.add_material(base=(0, 0, 0), emission=0.1))})
    g.add_orthographic_camera({"translation": [0.0, 0.0, 1.0]}, 1.0)
    g.write(out / "accumulation.gltf")


def coplanar(out):
    """Twelve overlapping coplanar emitters of different colours (a fixed pseudo-random layout): where they
    overlap, the one first in the file must win, whatever the BVH (so leaf sizes 1, 4 and 13 agree)."""
    g = Gltf()
    state = 12345
    for k in range(12):
        state = (1103515245 * state + 12345) % 2**31
        x = (state % 1000) / 1000.0 - 0.9
        state = (1103515245 * state + 12345) % 2**31
        y = (state % 1000) / 1000.0 - 0.9
        colour = ((k * 37 % 12) / 11.0, (k * 5 % 12) / 11.0, (k * 7 % 12) / 11.0)
        material = g.add_material(base=(0, 0, 0), emission=1.0, emission_color=colour)
        g.add_node({"mesh": g.add_mesh(quad(x, y, x + 0.8, y + 0.8, 0.0), material)})
    g.add_orthographic_camera({"translation": [0.0, 0.0, 1.0]}, 1.0)
    g.write(out / "coplanar.gltf")


def degenerate(cornell, out):
    """The Cornell box without vertex normals, and the same box plus every kind of degenerate input inside
    the view: zero-area, collinear and repeated-vertex triangles (some emissive), NaN and Inf positions, and
    the walls' normals replaced by NaN and zero vectors. The loader drops or flattens all of it, so both
    scenes must render to identical bits."""
    base = json.loads(Path(cornell).read_text())
    for mesh in base["meshes"]:
        for prim in mesh["primitives"]:
            prim["attributes"].pop("NORMAL", None)
    (out / "cornell_flat.gltf").write_text(json.dumps(base) + "\n")

    doc = copy.deepcopy(base)
    blob = bytearray(base64.b64decode(doc["buffers"][0]["uri"].split(",", 1)[1]))

    def add_floats(values, count, kind="VEC3"):
        while len(blob) % 4:
            blob.append(0)
        doc["bufferViews"].append({"buffer": 0, "byteOffset": len(blob), "byteLength": 4 * len(values)})
        blob.extend(struct.pack(f"<{len(values)}f", *values))
        doc["accessors"].append({"bufferView": len(doc["bufferViews"]) - 1, "componentType": 5126,
                                 "count": count, "type": kind})
        return len(doc["accessors"]) - 1

    nan, inf = float("nan"), float("inf")
    bad = [(0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0),        # a point
           (-0.5, 0.0, 0.0), (0.0, 0.0, 0.0), (0.5, 0.0, 0.0),       # collinear
           (-0.25, 0.5, 0.0), (-0.25, 0.5, 0.0), (0.25, 0.25, 0.5),  # repeated vertex
           (-0.5, -0.5, 0.5), (0.0, 0.25, 0.25), (0.5, 1.0, 0.0),    # collinear, diagonal
           (nan, 0.0, 0.0), (0.5, 0.5, 0.0), (0.0, 0.5, 0.5),        # NaN position
           (0.0, -inf, 0.0), (0.5, 0.0, 0.2), (0.2, 0.5, 0.0),       # Inf position
           (-inf, 0.0, 0.0), (inf, 0.0, 0.0), (0.0, inf, 0.0)]       # all infinite
    positions = add_floats([c for p in bad for c in p], len(bad))
    for material in (0, 3):  # white and the emitter's material
        doc["meshes"].append({"primitives": [{"attributes": {"POSITION": positions}, "material": material}]})
        doc["nodes"].append({"mesh": len(doc["meshes"]) - 1})
        doc["scenes"][0]["nodes"].append(len(doc["nodes"]) - 1)
    # Walls with NaN, zero-length and Inf normals: the loader shades them flat, as the reference has no normals.
    for mesh_index, value in ((2, nan), (3, 0.0), (4, inf)):
        prim = doc["meshes"][mesh_index]["primitives"][0]
        count = doc["accessors"][prim["attributes"]["POSITION"]]["count"]
        prim["attributes"]["NORMAL"] = add_floats([value] * (3 * count), count)
    doc["buffers"] = [{"byteLength": len(blob),
                       "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}]
    # json.dumps writes NaN/Infinity, which tinygltf's JSON parser rejects; the bad values live in the buffer only.
    (out / "cornell_degenerate.gltf").write_text(json.dumps(doc, allow_nan=False) + "\n")


def shading_normal_furnace(out):
    """The closed furnace with a low-poly sphere (8 x 6 segments, smooth vertex normals) of the same
    material inside: without energy gain or loss every pixel still reads LE / (1 - RHO)."""
    g = Gltf()
    wall = g.add_material(emission=LE)
    g.add_node({"mesh": g.add_mesh(cube_faces_inward(), wall)})
    tris, normals = uv_sphere(8, 6, 0.5)
    g.add_node({"mesh": g.add_mesh(tris, wall, normals)})
    g.add_perspective_camera({"translation": [0.0, 0.0, 0.95]}, yfov=1.3)
    g.write(out / "shading_normals_furnace.gltf")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    cornell, out = sys.argv[1], Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    cornell_variants(cornell, out)
    box_furnaces(out)
    point_light_spheres(out)
    grazing_planes(out)
    small_far_lights(out)
    accumulation(out)
    coplanar(out)
    degenerate(cornell, out)
    shading_normal_furnace(out)


if __name__ == "__main__":
    main()
