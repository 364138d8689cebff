#!/usr/bin/env python3
"""Writes the scenes of the light-tracing tests (standard library only; README "Light tracing").

lamp_room.gltf   a closed room (Lambertian walls of three colours) lit by a small ceiling quad, with three low-poly
                 spheres whose interpolated normals differ from their facets by up to 30 degrees: a clear coat over a
                 red base (a BSDF that is not symmetric), rough gold, and a sheen over blue. A perspective camera in the
                 room. Light tracing must agree with path tracing: the adjoint BSDF and the shading-normal correction
                 are wrong there first.
smooth_room.gltf the same room with one large Lambertian sphere of 6 x 4 facets: the shading normals alone (light subpaths must also
                 propose directions below the shading normal's hemisphere, where the path tracer's BSDF falls back to
                 the facet's frame; without that, 0.5% of the red channel went missing).
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "stability" / "render"))
sys.path.insert(0, str(Path(__file__).resolve().parent))
from make_stability_scenes import Gltf, quad, uv_sphere  # noqa: E402
from make_test_scenes import cube_faces_inward  # noqa: E402


def placed(tris, scale, offset):
    return [tuple(tuple(s * c + o for c, s, o in zip(p, scale, offset)) for p in t) for t in tris]


def room():
    """The closed room and its ceiling lamp; the camera looks along +y from near the front wall, slightly down."""
    g = Gltf()
    g.doc["extensionsUsed"] += ["KHR_materials_clearcoat", "KHR_materials_sheen"]
    walls = cube_faces_inward()  # 12 triangles, two per face, in face order -x, +x, -y, +y, -z, +z
    colours = [(0.7, 0.15, 0.1), (0.15, 0.6, 0.15), (0.7, 0.7, 0.7), (0.7, 0.7, 0.7), (0.7, 0.7, 0.7),
               (0.7, 0.7, 0.7)]
    for face in range(6):
        material = g.add_material(base=colours[face])
        g.add_node({"mesh": g.add_mesh(placed(walls[2 * face:2 * face + 2], (2.0, 2.0, 1.5), (0.0, 0.0, 1.5)),
                                       material)})
    lamp = g.add_material(base=(0.0, 0.0, 0.0), emission=15.0)
    g.add_node({"mesh": g.add_mesh(quad(-0.4, -0.4, 0.4, 0.4, 2.95, facing_up=False), lamp)})
    g.add_perspective_camera({"translation": [0.0, -1.5, 1.2], "rotation": [0.6755902, 0.0, 0.0, 0.7372773]}, 1.1)
    return g


def lamp_room():
    g = room()
    sphere, normals = uv_sphere(8, 4, 1.0)
    materials = [
        {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1.0], "metallicFactor": 0.0,
                                  "roughnessFactor": 0.6},
         "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.3}}},
        {"pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.78, 0.34, 1.0], "metallicFactor": 1.0,
                                  "roughnessFactor": 0.4}},
        {"pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.2, 0.7, 1.0], "metallicFactor": 0.0,
                                  "roughnessFactor": 0.5},
         "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1.0, 1.0, 1.0], "sheenRoughnessFactor": 0.5}}},
    ]
    for material, centre in zip(materials, [(-0.9, 0.3, 0.6), (0.0, 0.8, 0.6), (0.9, 0.3, 0.6)]):
        g.doc["materials"].append(material)
        mesh = g.add_mesh(placed(sphere, (0.6, 0.6, 0.6), centre), len(g.doc["materials"]) - 1, normals)
        g.add_node({"mesh": mesh})
    return g


def smooth_room():
    g = room()
    sphere, normals = uv_sphere(6, 4, 1.0)
    material = g.add_material(base=(0.8, 0.8, 0.8))
    g.add_node({"mesh": g.add_mesh(placed(sphere, (1.0, 1.0, 1.0), (0.0, 0.6, 1.0)), material, normals)})
    return g


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    out.mkdir(parents=True, exist_ok=True)
    lamp_room().write(out / "lamp_room.gltf")
    smooth_room().write(out / "smooth_room.gltf")


if __name__ == "__main__":
    main()
