#!/usr/bin/env python3
"""Writes the scenes that light sampling is measured on (standard library only; scenes/README.md, issue 50).

usage: make_light_sampling_scenes.py OUT_DIR

studio.gltf     a grey Lambertian sphere (1,280 flat facets) on a floor under a large, dim canopy (6 x 6, radiance 1, 4 above the floor)
                and a small, bright key panel (0.15 x 0.15, radiance 400) 1.2 from the sphere, facing it: a ceiling
                panel and a lamp. The canopy has 7x the key's power, but at the sphere the key gives about as much
                light: picking lights by power sends 7 of 8 light samples to the canopy.
lamp_hall.gltf  a hall (floor, back wall) lit by 144 small ceiling lamps in a 12 x 12 grid whose radiance spans three
                decades (a street at night, a hall of bulbs), a spot and a point light, over three Lambertian boxes,
                and a dim directional light: at each point the nearby lamps matter, wherever the bright ones are.
sign_bulb.gltf  a textured emissive sign (2 x 1 on the back wall, a 16 x 8 pattern of lit and dark cells, radiance up to
                8) and a small bright bulb in front of it (an emissive icosahedron of radius 0.04, radiance 3000) over a
                floor with a box: the sign's power, by its texture, dwarfs the bulb's, which lights the floor.
"""
import math
import random
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "stability" / "render"))
sys.path.insert(0, str(Path(__file__).resolve().parent))
from make_stability_scenes import Gltf, icosphere, quad  # noqa: E402
from make_light_scenes import look_at  # noqa: E402
from make_asset_scenes import AssetGltf, diffuse, quad_uv  # noqa: E402


def panel(centre, half, normal_axis, facing_positive):
    """A square of half-size `half` centred at `centre`, normal along axis 0 (x) or 2 (z), front face +axis or -axis."""
    cx, cy, cz = centre
    if normal_axis == 2:
        return quad(cx - half, cy - half, cx + half, cy + half, cz, facing_up=facing_positive)
    # normal along x: the quad in the (y, z) plane, its +z front turned to face +x (or -x)
    tris = quad(cy - half, cz - half, cy + half, cz + half, 0.0, facing_up=True)
    out = []
    for t in tris:
        p = [(cx, y, z) for (y, z, _) in t]
        out.append((p[0], p[1], p[2]) if facing_positive else (p[0], p[2], p[1]))
    return out


def box(lo, hi):
    """The 12 outward triangles of the box [lo, hi]."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    c = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (1, 2, 6, 5), (3, 0, 4, 7)]
    return [t for a, b, cc, d in faces for t in ((c[a], c[b], c[cc]), (c[a], c[cc], c[d]))]


def studio():
    g = Gltf()
    floor = g.add_material(base=(0.5, 0.5, 0.5))
    g.add_node({"mesh": g.add_mesh(quad(-4.0, -4.0, 4.0, 4.0, 0.0), floor)})
    grey = g.add_material(base=(0.6, 0.6, 0.6))  # flat facets: the peers' scene readers (tests/bench) shade flat
    g.add_node({"mesh": g.add_mesh([tuple((x, y, z + 0.5) for x, y, z in t) for t in icosphere(3, 0.5)], grey)})
    canopy = g.add_material(base=(0.0, 0.0, 0.0), emission=1.0)
    g.add_node({"mesh": g.add_mesh(quad(-3.0, -3.0, 3.0, 3.0, 4.0, facing_up=False), canopy)})
    key = g.add_material(base=(0.0, 0.0, 0.0), emission=400.0, emission_color=(1.0, 0.9, 0.8))
    g.add_node({"mesh": g.add_mesh(panel((1.2, -0.4, 0.9), 0.075, 0, False), key)})
    g.add_perspective_camera(look_at((0.0, -3.2, 1.4), (0.0, 0.0, 0.5)), 0.8)
    return g


def lamp_hall():
    g = Gltf()
    grey = g.add_material(base=(0.6, 0.6, 0.6))
    g.add_node({"mesh": g.add_mesh(quad(-6.0, -6.0, 6.0, 6.0, 0.0), grey)})
    wall = [((-6.0, 6.0, 0.0), (6.0, 6.0, 4.0), (6.0, 6.0, 0.0)), ((-6.0, 6.0, 0.0), (-6.0, 6.0, 4.0), (6.0, 6.0, 4.0))]
    g.add_node({"mesh": g.add_mesh(wall, grey)})
    for lo, hi, colour in (((-2.5, -1.0, 0.0), (-1.5, 0.0, 1.0), (0.7, 0.3, 0.2)),
                           ((0.5, 1.0, 0.0), (1.5, 2.0, 2.0), (0.3, 0.6, 0.3)),
                           ((2.5, -2.0, 0.0), (3.2, -1.3, 0.5), (0.3, 0.3, 0.7))):
        g.add_node({"mesh": g.add_mesh(box(lo, hi), g.add_material(base=colour))})
    rng = random.Random(50)
    for i in range(12):
        for j in range(12):
            radiance = 10.0 ** rng.uniform(0.0, 3.0)  # three decades
            lamp = g.add_material(base=(0.0, 0.0, 0.0), emission=radiance)
            x, y = -5.5 + i, -5.5 + j
            g.add_node({"mesh": g.add_mesh(quad(x - 0.05, y - 0.05, x + 0.05, y + 0.05, 3.5, facing_up=False), lamp)})
    # Punctual lights in the tree too (a spot on the green box, a point by the blue one), and a dim directional
    # "moon" outside it, which NEE picks as often as the whole tree.
    spot = look_at((-1.0, -2.5, 3.0), (1.0, 1.5, 1.0))
    g.add_light({"type": "spot", "intensity": 30.0, "spot": {"innerConeAngle": 0.15, "outerConeAngle": 0.3}}, spot)
    g.add_light({"type": "point", "intensity": 2.0}, {"translation": [2.2, -2.6, 0.8]})
    g.add_light({"type": "directional", "intensity": 0.05}, look_at((1.0, -2.0, 3.0), (0.0, 0.0, 0.0)))
    g.add_perspective_camera(look_at((0.0, -7.5, 2.5), (0.0, 0.0, 0.8)), 1.0)
    return g


def sign_bulb():
    g = AssetGltf()
    texels = [((255, 140, 40, 255) if (x // 2 + y) % 3 else (20, 20, 30, 255)) for y in range(8) for x in range(16)]
    sign = g.add_raw_material({"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
                               "emissiveFactor": [1.0, 1.0, 1.0], "emissiveTexture": {"index": g.add_texture(16, 8, texels)},
                               "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 8.0}}})
    # The sign stands on the back wall (y = 2), facing -y: the quad in the (x, z) plane.
    wall = [((x, 2.0, z) for x, z in ((-1.0, 0.5), (1.0, 0.5), (1.0, 1.5))), ((x, 2.0, z) for x, z in ((-1.0, 0.5), (1.0, 1.5), (-1.0, 1.5)))]
    g.add_node({"mesh": g.add_uv_mesh([tuple(t) for t in wall], [((0.0, 1.0), (1.0, 1.0), (1.0, 0.0)),
                                                                ((0.0, 1.0), (1.0, 0.0), (0.0, 0.0))], sign)})
    floor = g.add_raw_material(diffuse((0.6, 0.6, 0.6, 1.0)))
    g.add_node({"mesh": g.add_uv_mesh(quad(-3.0, -3.0, 3.0, 3.0, 0.0), quad_uv(), floor)})
    grey = g.add_material(base=(0.5, 0.5, 0.5))
    g.add_node({"mesh": g.add_mesh(box((0.6, 0.2, 0.0), (1.1, 0.7, 0.5)), grey)})
    bulb = g.add_material(base=(0.0, 0.0, 0.0), emission=3000.0, emission_color=(1.0, 0.95, 0.85))
    g.add_node({"mesh": g.add_mesh([tuple((x, y + 0.8, z + 0.6) for x, y, z in t) for t in icosphere(1, 0.04)], bulb)})
    g.add_perspective_camera(look_at((0.0, -3.0, 1.6), (0.0, 0.8, 0.5)), 1.0)
    return g


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    out.mkdir(parents=True, exist_ok=True)
    studio().write(out / "studio.gltf")
    lamp_hall().write(out / "lamp_hall.gltf")
    sign_bulb().write(out / "sign_bulb.gltf")


if __name__ == "__main__":
    main()
