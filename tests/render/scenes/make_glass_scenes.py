#!/usr/bin/env python3
"""Writes the render-test scenes for KHR_materials_transmission and KHR_materials_volume (standard library only).

usage: make_glass_scenes.py OUT_DIR

Each has an analytic criterion, stated beside its test in tests/render/CMakeLists.txt. An orthographic camera
looks straight down (-Z) at a white emitter of radiance 1 on the plane z = 0 through:
  glass_slab.gltf            a smooth glass slab (ior 1.5, closed box, KHR_materials_volume) 1 unit thick: every
                             pixel reads (1 - F)^2 / (1 - F^2) = 0.9230769 (F = 0.04; all internal reflections).
  glass_slab_absorbing.gltf  the same slab with attenuationColor 0.5 at attenuationDistance 1: with tau = 0.5,
                             (1 - F)^2 tau / (1 - F^2 tau^2) = 0.4609844 (Beer-Lambert on every crossing).
  glass_thin.gltf            one smooth thin-walled glass quad (no volume): 1 - F = 0.96.
  glass_slab_dispersive.gltf the slab with KHR_materials_dispersion 1 (Abbe number 20), rendered spectrally: each
                             wavelength passes (1 - F)^2 / (1 - F^2) at its own index (1.486 to 1.538), 0.921 to
                             0.924 in each channel (the hero wavelength alone after the first surface).
  glass_furnace_dispersive.gltf  a smooth glass sphere of dispersion 1 in perspective: under --background 1,1,1
                             white in every pixel (a spectral path that splits light by wavelength loses none).
  glass_furnace_dispersive_r50.gltf  the sphere rough (0.5): BDPT joins vertices inside it where both subpaths
                             dispersed (each weighted its hero wavelength by 4; the path takes it once).
  glass_prism.gltf           a 60-degree prism of dispersion 1 in front of a white emissive slit, seen by a
                             perspective camera: the slit's image is spread into a spectrum (shaders/lib/bsdf/README.md "Dispersion").
  glass_prism_wall.gltf      the same prism and a short bright slit, turned round: the slit's light passes through the
                             prism and throws a spectrum onto a white wall (z = 8) that the camera looks at from
                             between them (a black screen round the prism keeps the slit's direct light off it); light subpaths carry the dispersion (shaders/lib/integrator/README.md "Dispersion").
  glass_furnace_rNN.gltf     a glass sphere of ior 1.5 and roughness 0.NN (0, 0.3, 1), seen in perspective: under
                             --background 1,1,1 white in every pixel, rough or not (the multiple-scattering lobe gives
                             back what single scattering loses; without it roughness 1 reads 0.64, shaders/lib/bsdf/README.md "Glass").
  glass_furnace_thin_r100.gltf  the same sphere thin-walled (no volume), roughness 1: white too.
  glass_furnace_absorbing.gltf  the sphere at roughness 0.5, absorbing (attenuationColor 0.5 at distance 1): not
                             white; BDPT must agree with path tracing (light subpaths absorbed inside it).
  glass_furnace_tube.gltf    a smooth glass tube with walls 0.05 thick and flat rims, its vertex normals smooth around
                             it and bent 45 degrees at the rims (as modelled glassware): white too, although light
                             guided along the walls by total internal reflection meets bent normals at every bounce
                             (shaders/lib/bsdf/README.md "Glass", "Interpolated normals on glass").
  glass_furnace_open.gltf    a glass box without its top face, seen from below (an open mesh, as modelled assets have
                             them): white too, although light leaves the volume through the hole (shaders/lib/bsdf/README.md "Open meshes").
  glass_camera_inside.gltf   the camera at z = 3 inside a glass block (ior 1.5, attenuationColor 0.5 at distance 1)
                             from z = 0.5 to 5: the emitter is seen through 2.5 units of glass and one interface,
                             where radiance gains ior^2 (radiance / n^2 is what a ray conserves):
                             0.5^2.5 x 2.25 x 0.96 / (1 - 0.04^2 x 0.5^9) = 0.3818389 (the series: round trips
                             between floor and top). Paths that started outside every volume would read 2.1635.
  glass_nested.gltf          clear water (ior 1.33) from z = 1 to 2 inside that absorbing glass, now from z = 0.5 to
                             2.5: the interfaces are air/glass, glass/water, water/glass, glass/air, and the ray
                             crosses 1 unit of glass: 0.4577985 with every interreflection (NESTED_EXPECTED; run
                             this file with --expected). Treating water as if in air, and the glass below it as air
                             (no nesting), gives 0.628.
  glass_camera_nested.gltf   the same with the camera in the water (z = 1.5): its paths start in the water inside the
                             glass, and see the emitter through water | glass, 0.5 units of glass and glass | air,
                             times 1.33^2: NESTED_CAMERA_EXPECTED (--expected).
"""
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "stability" / "render"))
from make_stability_scenes import Gltf, icosphere, quad, uv_sphere  # noqa: E402

IOR = 1.5


def box(x0, y0, z0, x1, y1, z1):
    """The 12 triangles of an axis-aligned box, wound to face outwards."""
    tris = quad(x0, y0, x1, y1, z1, True) + quad(x0, y0, x1, y1, z0, False)
    a, b, c, d = (x0, y0), (x1, y0), (x1, y1), (x0, y1)
    for (p, q) in ((a, b), (b, c), (c, d), (d, a)):  # sides, counter-clockwise seen from above: outward
        lo_p, lo_q, hi_p, hi_q = (*p, z0), (*q, z0), (*p, z1), (*q, z1)
        tris += [(lo_p, lo_q, hi_q), (lo_p, hi_q, hi_p)]
    return tris


def glass(roughness=0.0, volume=True, attenuation=None, dispersion=None, ior=IOR):
    m = {"pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0,
                                  "roughnessFactor": roughness},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                        "KHR_materials_ior": {"ior": ior}}}
    if volume:
        m["extensions"]["KHR_materials_volume"] = {"thicknessFactor": 1.0}
        if attenuation is not None:
            color, distance = attenuation
            m["extensions"]["KHR_materials_volume"].update(
                {"attenuationColor": [color] * 3, "attenuationDistance": distance})
    if dispersion is not None:
        m["extensions"]["KHR_materials_dispersion"] = {"dispersion": dispersion}
    return m


def use_glass_extensions(g):
    g.doc["extensionsUsed"] += ["KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume",
                                "KHR_materials_dispersion"]


def prism(x0, x1):
    """A 60-degree prism along x from x0 to x1: its cross-section is an equilateral triangle of side 2 with its apex
    up at (y, z) = (1, 0) and its base at y = 1 - sqrt(3), so that its two upper faces look towards +z and -z."""
    h = 3.0 ** 0.5
    a, b, c = (1.0, 0.0), (1.0 - h, 1.0), (1.0 - h, -1.0)  # (y, z): apex, base front (+z), base back
    p = lambda x, yz: (x, yz[0], yz[1])
    tris = [(p(x0, a), p(x0, c), p(x0, b)), (p(x1, a), p(x1, b), p(x1, c))]  # end caps, facing -x and +x
    for (u, v) in ((a, b), (b, c), (c, a)):  # sides, facing outwards
        tris += [(p(x0, u), p(x0, v), p(x1, v)), (p(x0, u), p(x1, v), p(x1, u))]
    return tris


def slit_and_prism(slit_half_width, emission):
    """A white slit at z = -8, 37 degrees below the horizontal as seen from the prism's far side (its minimum deviation
    at index 1.5), and the prism of dispersion 1."""
    g = Gltf()
    use_glass_extensions(g)
    slit = g.add_material(base=(0.0, 0.0, 0.0), emission=emission)
    g.add_node({"mesh": g.add_mesh(quad(-slit_half_width, -5.6, slit_half_width, -5.4, -8.0), slit)})
    g.doc["materials"].append(glass(dispersion=1.0))
    g.add_node({"mesh": g.add_mesh(prism(-2.0, 2.0), len(g.doc["materials"]) - 1)})
    return g


def prism_scene():
    """The camera looks along -z through the prism at the slit 8 units behind it, outside the camera's view but
    through the prism: the slit's image is spread vertically into a spectrum, violet highest, red lowest (least
    deviated)."""
    g = slit_and_prism(10.0, 4.0)
    g.add_perspective_camera({"translation": [0.0, 0.2, 8.0]}, 0.5)
    return g


def prism_wall_scene():
    g = slit_and_prism(0.5, 200.0)
    wall = g.add_material(base=(0.8, 0.8, 0.8))
    g.add_node({"mesh": g.add_mesh(quad(-4.0, -4.0, 4.0, 4.0, 8.0, facing_up=False), wall)})
    # A black screen behind the prism (z = -1.2) with a window the prism fills: the wall sees the slit through it only.
    screen = g.add_material(base=(0.0, 0.0, 0.0))
    panels = quad(-6.0, -6.0, 6.0, -0.75, -1.2) + quad(-6.0, 1.0, 6.0, 6.0, -1.2)
    panels += quad(-6.0, -0.75, -2.0, 1.0, -1.2) + quad(2.0, -0.75, 6.0, 1.0, -1.2)
    g.add_node({"mesh": g.add_mesh(panels, screen)})
    g.add_perspective_camera({"translation": [0.0, 0.2, 3.0], "rotation": [0.0, 1.0, 0.0, 0.0]}, 0.9)
    return g


def over_emitter(material, shape, camera_z=3.0):
    g = Gltf()
    use_glass_extensions(g)
    emitter = g.add_material(base=(0.0, 0.0, 0.0), emission=1.0)
    g.add_node({"mesh": g.add_mesh(quad(-20, -20, 20, 20, 0.0), emitter)})
    g.doc["materials"].append(material)
    g.add_node({"mesh": g.add_mesh(shape, len(g.doc["materials"]) - 1)})
    g.add_orthographic_camera({"translation": [0.0, 0.0, camera_z]}, 1.0)
    return g


def stack_of_layers(layers):
    """Normal-incidence (R front, T front, R back, T back) of a stack of incoherent layers, listed front (top) to back,
    by the adding method: an interface between indices n1, n2 has R = ((n1 - n2) / (n1 + n2))^2 both ways and a slab
    of transmittance tau has R = 0, T = tau. Every interreflection counts."""
    def combine(a, b):
        d = 1.0 - a[2] * b[0]
        return (a[0] + a[1] * a[3] * b[0] / d, a[1] * b[1] / d, b[2] + b[3] * b[1] * a[2] / d, b[3] * a[3] / d)
    total = (0.0, 1.0, 0.0, 1.0)
    for layer in layers:
        if layer[0] == "interface":
            r = ((layer[1] - layer[2]) / (layer[1] + layer[2])) ** 2
            layer = (r, 1.0 - r, r, 1.0 - r)
        else:
            layer = (0.0, layer[1], 0.0, layer[1])
        total = combine(total, layer)
    return total


def transmittance_of_layers(layers):
    return stack_of_layers(layers)[1]


def nested_scene(camera_z=3.0):
    """Water (ior 1.33, clear) from z = 1 to 2 inside an absorbing glass block (ior 1.5, attenuationColor 0.5 at
    distance 1) from z = 0.5 to 2.5, over the emitter; the camera at camera_z looks straight down."""
    g = over_emitter(glass(attenuation=(0.5, 1.0)), box(-10, -10, 0.5, 10, 10, 2.5), camera_z)
    g.doc["materials"].append(glass(ior=1.33))
    g.add_node({"mesh": g.add_mesh(box(-8, -8, 1.0, 8, 8, 2.0), len(g.doc["materials"]) - 1)})
    return g


NESTED_EXPECTED = transmittance_of_layers([("interface", 1.0, 1.5), ("slab", 0.5 ** 0.5), ("interface", 1.5, 1.33),
                                           ("slab", 1.0), ("interface", 1.33, 1.5), ("slab", 0.5 ** 0.5),
                                           ("interface", 1.5, 1.0)])


# The camera in the water (z = 1.5): it sees, below it, water | glass, 0.5 units of glass, glass | air and the emitter;
# light reflected back up by that stack returns off the one above it (water | glass, glass, glass | air, then black).
# Radiance in the water is the emitter's times 1.33^2 (radiance / n^2 is what a ray conserves).
_BELOW = stack_of_layers([("interface", 1.33, 1.5), ("slab", 0.5 ** 0.5), ("interface", 1.5, 1.0)])
_ABOVE = stack_of_layers([("interface", 1.0, 1.5), ("slab", 0.5 ** 0.5), ("interface", 1.5, 1.33)])
NESTED_CAMERA_EXPECTED = 1.33 ** 2 * _BELOW[1] / (1.0 - _BELOW[0] * _ABOVE[2])


def furnace(roughness, dispersion=None, volume=True, attenuation=None):
    g = Gltf()
    use_glass_extensions(g)
    g.doc["materials"].append(glass(roughness=roughness, volume=volume, dispersion=dispersion,
                                    attenuation=attenuation))
    g.add_node({"mesh": g.add_mesh(icosphere(4), 0)})
    g.add_perspective_camera({"translation": [0.0, 0.0, 3.0]}, 0.8)
    return g


def rimmed_tube():
    """A glass tube (outer radius 1, inner 0.95, height 2, 12 sides) closed at both ends by flat rims: one closed
    volume whose vertex normals are smooth around the tube and, on the four rings at the rims, halfway between the
    wall and the rim (45 degrees from either face), as modelled glassware has them. Triangles and per-corner normals."""
    segments, heights = 12, (0.0, 0.1, 1.9, 2.0)

    def unit(v):
        n = math.sqrt(sum(c * c for c in v))
        return tuple(c / n for c in v)

    def corner(radius, h, i, outward):
        a = 2.0 * math.pi * (i % segments) / segments
        radial = (math.cos(a), 0.0, math.sin(a))
        s = 1.0 if outward else -1.0
        up = 1.0 if h == heights[-1] else (-1.0 if h == heights[0] else 0.0)
        return (radius * radial[0], h - 1.0, radius * radial[2]), unit((s * radial[0], up, s * radial[2]))

    tris, normals = [], []

    def add(*corners):  # corners (position, normal), counter-clockwise seen from outside the glass
        tris.append(tuple(p for p, _ in corners))
        normals.extend(n for _, n in corners)

    for i in range(segments):
        for h0, h1 in zip(heights, heights[1:]):
            a, b, c, d = (corner(1.0, h0, i, True), corner(1.0, h0, i + 1, True), corner(1.0, h1, i + 1, True),
                          corner(1.0, h1, i, True))
            add(a, c, b)
            add(a, d, c)
            a, b, c, d = (corner(0.95, h0, i, False), corner(0.95, h0, i + 1, False),
                          corner(0.95, h1, i + 1, False), corner(0.95, h1, i, False))
            add(a, b, c)
            add(a, c, d)
        for h in (heights[0], heights[-1]):
            a, b, c, d = (corner(0.95, h, i, False), corner(0.95, h, i + 1, False), corner(1.0, h, i + 1, True),
                          corner(1.0, h, i, True))
            if h == heights[-1]:
                add(a, b, c)
                add(a, c, d)
            else:
                add(a, c, b)
                add(a, d, c)
    return tris, normals


def tube_furnace():
    """rimmed_tube() seen from above and in front, to be rendered in a white furnace."""
    g = Gltf()
    use_glass_extensions(g)
    g.doc["materials"].append(glass())
    tris, normals = rimmed_tube()
    g.add_node({"mesh": g.add_mesh(tris, 0, normals)})
    # 30 degrees down (a rotation about x), from above the rim: the rims, both walls and the inside are seen.
    g.add_perspective_camera({"translation": [0.0, 1.6, 3.2], "rotation": [-0.258819, 0.0, 0.0, 0.9659258]}, 0.9)
    return g


def open_box_furnace():
    """A box of glass (ior 1.5, from -1 to 1) without its top face, seen from below: light enters through the bottom
    and leaves through the open top without crossing a surface."""
    g = Gltf()
    use_glass_extensions(g)
    g.doc["materials"].append(glass())
    g.add_node({"mesh": g.add_mesh(box(-1, -1, -1, 1, 1, 1)[2:], 0)})  # box()'s first two triangles: the top
    g.add_perspective_camera({"translation": [0.0, 0.0, -3.0], "rotation": [1.0, 0.0, 0.0, 0.0]}, 0.8)  # looking up +z
    return g


def main():
    if sys.argv[1:] == ["--expected"]:
        print(f"glass_nested {NESTED_EXPECTED:.7f}")
        print(f"glass_camera_nested {NESTED_CAMERA_EXPECTED:.7f}")
        return
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    slab = box(-10, -10, 0.5, 10, 10, 1.5)
    scenes = {
        "glass_slab": over_emitter(glass(), slab),
        "glass_slab_absorbing": over_emitter(glass(attenuation=(0.5, 1.0)), slab),
        "glass_thin": over_emitter(glass(volume=False), quad(-10, -10, 10, 10, 1.0)),
        "glass_slab_dispersive": over_emitter(glass(dispersion=1.0), slab),
        "glass_furnace_dispersive": furnace(0.0, dispersion=1.0),
        "glass_furnace_dispersive_r50": furnace(0.5, dispersion=1.0),
        "glass_prism": prism_scene(),
        "glass_prism_wall": prism_wall_scene(),
        "glass_furnace_r0": furnace(0.0),
        "glass_furnace_r30": furnace(0.3),
        "glass_furnace_r100": furnace(1.0),
        "glass_furnace_thin_r100": furnace(1.0, volume=False),
        "glass_furnace_absorbing": furnace(0.5, attenuation=(0.5, 1.0)),
        "glass_furnace_tube": tube_furnace(),
        "glass_furnace_open": open_box_furnace(),
        # The camera (z = 3) inside an absorbing glass block from z = 0.5 to 5 (see the docstring).
        "glass_camera_inside": over_emitter(glass(attenuation=(0.5, 1.0)), box(-10, -10, 0.5, 10, 10, 5)),
        "glass_nested": nested_scene(),
        "glass_camera_nested": nested_scene(camera_z=1.5),
    }
    for name, g in scenes.items():
        g.write(out / f"{name}.gltf")


if __name__ == "__main__":
    main()
