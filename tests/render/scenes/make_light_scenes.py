#!/usr/bin/env python3
"""Writes the scenes of the light-tracing tests (standard library only; shaders/lib/integrator/README.md "Light tracing").

lamp_room.gltf   a closed room (Lambertian walls of three colours) lit by a small ceiling quad, with three low-poly
                 spheres whose interpolated normals differ from their facets by up to 30 degrees: a clear coat over a
                 red base (a BSDF that is not symmetric), rough gold, and a sheen over blue. A perspective camera in the
                 room. Light tracing must agree with path tracing: the adjoint BSDF and the shading-normal correction
                 are wrong there first.
door_gap.gltf    (shipped in scenes/) two rooms joined by a door ajar by 20 cm; the lamp is in the far one, the camera in
                 the near one: everything it sees is lit through the gap (shaders/lib/integrator/README.md "Light tracing", the hard scenes).
lamp_shade.gltf  (shipped in scenes/) a room lit only by a small lamp inside a closed-top cylindrical shade, open
                 below: the camera sees the room lit by the pool of light under the shade.
glass_room.gltf  the lamp room with four spheres that light passes through: smooth glass and rough glass (both volumes,
                 ior 1.5, smooth normals), thin-walled glass and a diffuse transmitter: light and camera subpaths must
                 cross surfaces, keep their volumes' indices and agree with the path tracer.
glass_caustic.gltf (shipped in scenes/) a smooth glass sphere hanging over the floor of the room under a small lamp,
                 which it focuses to a caustic on the floor (shaders/lib/integrator/README.md "Bidirectional path tracing").
water_glass.gltf (shipped in scenes/) a sealed glass jar of water on a table under a small lamp: the jar (ior 1.5)
                 holds a cylinder of water (ior 1.33, nested in the glass's volume) and focuses the lamp into a caustic
                 on the table beside and behind it, which the camera sees directly and through the jar: the caustic
                 seen through its own glass is a specular-diffuse-specular path, which only vertex merging samples
                 well (shaders/lib/integrator/README.md "Vertex connection and merging").
glass_bulb.gltf  the room without its ceiling lamp, lit only by a small lamp (an emissive icosphere) inside a closed
                 rough absorbing glass sphere (a volume): light subpaths start inside the glass's volume, so they must
                 know it (refraction by its index on the way out, absorption from the first segment).
unlit_room.gltf  the lamp room with an unlit sphere (KHR_materials_unlit, base colour (0.9, 0.5, 0.1)): the camera sees
                 its colour, every other ray finds it black (light subpaths end there).
moving_room.gltf the lamp room with a grey sphere sliding along x (0.6 units over 1 s) and the camera sliding the other
                 way (0.3 units), keyed at t = 0 and 1 (render at --time 0.5 --shutter -0.5,0.5): light and camera
                 subpaths of a sample must share its time, and splats land where the moving camera saw them.
moving_furnace.gltf a closed furnace (the cube [-1,1]^3, Lambertian walls of albedo 0.8 emitting 0.5: 2.5 everywhere)
                 round a white Lambertian block (albedo 1, no emission: 2.5 on it too) that slides 0.4 units along x,
                 towards the still camera's view (keyed at t = 0 and 1): every pixel reads 2.5 at any time, but a
                 merge with light vertices of another time finds the block's face elsewhere (vertex merging must share
                 a sample's time across its wave).
smooth_room.gltf the same room with one large Lambertian sphere of 6 x 4 facets: the shading normals alone (light subpaths must also
                 propose directions below the shading normal's hemisphere, where the path tracer's BSDF falls back to
                 the facet's frame; without that, 0.5% of the red channel went missing).
"""
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "stability" / "render"))
sys.path.insert(0, str(Path(__file__).resolve().parent))
from make_stability_scenes import Gltf, icosphere, quad, uv_sphere  # noqa: E402
from make_test_scenes import cube_faces_inward  # noqa: E402


def placed(tris, scale, offset):
    return [tuple(tuple(s * c + o for c, s, o in zip(p, scale, offset)) for p in t) for t in tris]


def room(lamp=True):
    """The closed room [-2,2] x [-2,2] x [0,3] (a red and a green side wall) and its small ceiling lamp; the camera
    looks along +y from near the front wall, slightly down."""
    g = Gltf()
    walls = cube_faces_inward()  # 12 triangles, two per face, in face order -x, +x, -y, +y, -z, +z
    colours = [(0.7, 0.15, 0.1), (0.15, 0.6, 0.15), (0.7, 0.7, 0.7), (0.7, 0.7, 0.7), (0.7, 0.7, 0.7),
               (0.7, 0.7, 0.7)]
    for face in range(6):
        material = g.add_material(base=colours[face])
        g.add_node({"mesh": g.add_mesh(placed(walls[2 * face:2 * face + 2], (2.0, 2.0, 1.5), (0.0, 0.0, 1.5)),
                                       material)})
    if lamp:
        material = g.add_material(base=(0.0, 0.0, 0.0), emission=15.0)
        g.add_node({"mesh": g.add_mesh(quad(-0.4, -0.4, 0.4, 0.4, 2.95, facing_up=False), material)})
    return g


def room_camera(g):
    g.add_perspective_camera({"translation": [0.0, -1.5, 1.2], "rotation": [0.6755902, 0.0, 0.0, 0.7372773]}, 1.1)


def add_spheres(g, materials, centres, radius, segments, rings):
    """Low-poly smooth spheres of `radius`, one per (material, centre); each material is appended to the document."""
    sphere, normals = uv_sphere(segments, rings, 1.0)
    for material, centre in zip(materials, centres):
        g.doc["materials"].append(material)
        mesh = g.add_mesh(placed(sphere, (radius, radius, radius), centre), len(g.doc["materials"]) - 1, normals)
        g.add_node({"mesh": mesh})


def lamp_room():
    g = room()
    g.doc["extensionsUsed"] += ["KHR_materials_clearcoat", "KHR_materials_sheen"]
    room_camera(g)
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
    add_spheres(g, materials, [(-0.9, 0.3, 0.6), (0.0, 0.8, 0.6), (0.9, 0.3, 0.6)], 0.6, 8, 4)
    return g


def smooth_room():
    g = room()
    room_camera(g)
    sphere, normals = uv_sphere(6, 4, 1.0)
    material = g.add_material(base=(0.8, 0.8, 0.8))
    g.add_node({"mesh": g.add_mesh(placed(sphere, (1.0, 1.0, 1.0), (0.0, 0.6, 1.0)), material, normals)})
    return g


def glass_material(roughness, volume=True, ior=1.5):
    m = {"pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0,
                                  "roughnessFactor": roughness},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": ior}}}
    if volume:
        m["extensions"]["KHR_materials_volume"] = {"thicknessFactor": 1.0}
    return m


def use_transmission_extensions(g):
    g.doc["extensionsUsed"] += ["KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume",
                                "KHR_materials_diffuse_transmission"]


def glass_room():
    g = room()
    use_transmission_extensions(g)
    room_camera(g)
    materials = [
        glass_material(0.0),
        glass_material(0.4),
        glass_material(0.2, volume=False),
        {"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.8, 0.3, 1.0], "metallicFactor": 0.0,
                                  "roughnessFactor": 0.7},
         "extensions": {"KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 0.6}}},
    ]
    centres = [(-1.05, 0.3, 0.5), (-0.35, 0.9, 0.5), (0.35, 0.9, 0.5), (1.05, 0.3, 0.5)]
    add_spheres(g, materials, centres, 0.45, 12, 6)
    return g


def glass_bulb():
    g = room(lamp=False)
    use_transmission_extensions(g)
    room_camera(g)
    bulb = glass_material(0.3)
    bulb["extensions"]["KHR_materials_volume"].update({"attenuationColor": [0.4, 0.6, 0.9], "attenuationDistance": 0.5})
    add_spheres(g, [bulb], [(0.0, 0.6, 1.4)], 0.5, 16, 8)
    lamp = g.add_material(base=(0.0, 0.0, 0.0), emission=40.0)
    g.add_node({"mesh": g.add_mesh(placed(icosphere(1), (0.08, 0.08, 0.08), (0.0, 0.6, 1.4)), lamp)})
    return g


def unlit_room():
    g = room()
    g.doc["extensionsUsed"] += ["KHR_materials_unlit"]
    room_camera(g)
    # Not metallic (glTF's default), so that a BSDF, were it evaluated there, would reflect (a metal's would be black
    # here: the scene has no specular lobe compiled in).
    unlit = {"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.5, 0.1, 1.0], "metallicFactor": 0.0},
             "extensions": {"KHR_materials_unlit": {}}}
    add_spheres(g, [unlit], [(0.3, 0.6, 0.6)], 0.6, 12, 6)
    return g


def glass_caustic():
    """The room without its ceiling lamp: a smooth glass sphere (radius 0.4, ior 1.5, smooth normals) hangs with its
    centre 0.9 over the floor, under a small lamp (0.2 x 0.2) 2 higher; the sphere focuses the lamp near the floor."""
    g = room(lamp=False)
    use_transmission_extensions(g)
    sphere, normals = uv_sphere(48, 24, 1.0)
    g.doc["materials"].append(glass_material(0.0))
    g.add_node({"mesh": g.add_mesh(placed(sphere, (0.4, 0.4, 0.4), (0.0, 0.5, 0.9)), len(g.doc["materials"]) - 1,
                                   normals)})
    lamp = g.add_material(base=(0.0, 0.0, 0.0), emission=200.0)
    g.add_node({"mesh": g.add_mesh(quad(-0.1, 0.4, 0.1, 0.6, 2.9, facing_up=False), lamp)})
    g.add_perspective_camera(look_at((0.0, -1.7, 1.9), (0.0, 0.5, 0.3)), 1.0)
    return g


def cylinder(radius, z0, z1, segments=48):
    """A closed cylinder about the z axis from z0 to z1, wound to face outwards: smooth normals on its side, flat caps.
    Triangles and per-corner normals."""
    tris, normals = [], []
    for i in range(segments):
        a0, a1 = 2.0 * math.pi * i / segments, 2.0 * math.pi * (i + 1) / segments
        n0, n1 = (math.cos(a0), math.sin(a0), 0.0), (math.cos(a1), math.sin(a1), 0.0)
        p00, p10 = (radius * n0[0], radius * n0[1], z0), (radius * n1[0], radius * n1[1], z0)
        p01, p11 = (radius * n0[0], radius * n0[1], z1), (radius * n1[0], radius * n1[1], z1)
        tris += [(p00, p10, p11), (p00, p11, p01)]
        normals += [n0, n1, n1, n0, n1, n0]
        tris += [((0.0, 0.0, z1), p01, p11), ((0.0, 0.0, z0), p10, p00)]
        normals += [(0.0, 0.0, 1.0)] * 3 + [(0.0, 0.0, -1.0)] * 3
    return tris, normals


def water_glass():
    """The room without its ceiling lamp: a table (a 1.6 x 1.2 top 0.7 above the floor) with a sealed glass jar (radius
    0.25, 0.5 high, 0.03 thick walls, ior 1.5) of water (ior 1.33) on it, under a small lamp (0.15 x 0.15) up and to
    the front left, so its caustic falls behind the jar; the camera looks down at the jar from the front left."""
    g = room(lamp=False)
    use_transmission_extensions(g)
    table = g.add_material(base=(0.75, 0.7, 0.6))
    top = quad(-0.8, -0.1, 0.8, 1.1, 0.7) + quad(-0.8, -0.1, 0.8, 1.1, 0.66, facing_up=False)
    g.add_node({"mesh": g.add_mesh(top, table)})
    jar, jar_normals = cylinder(0.25, 0.705, 1.2)  # 5 mm above the table: no coincident faces
    g.doc["materials"].append(glass_material(0.0))
    g.add_node({"mesh": g.add_mesh(placed(jar, (1.0, 1.0, 1.0), (0.0, 0.5, 0.0)), len(g.doc["materials"]) - 1,
                                   jar_normals)})
    water, water_normals = cylinder(0.22, 0.735, 1.1)
    g.doc["materials"].append(glass_material(0.0, ior=1.33))
    g.add_node({"mesh": g.add_mesh(placed(water, (1.0, 1.0, 1.0), (0.0, 0.5, 0.0)), len(g.doc["materials"]) - 1,
                                   water_normals)})
    lamp = g.add_material(base=(0.0, 0.0, 0.0), emission=300.0)
    g.add_node({"mesh": g.add_mesh(quad(-0.45, 0.0, -0.3, 0.15, 2.9, facing_up=False), lamp)})
    g.add_perspective_camera(look_at((-0.9, -1.2, 1.7), (0.0, 0.5, 0.85)), 0.8)
    return g


def look_at(eye, target, up=(0.0, 0.0, 1.0)):
    """The glTF node (translation, rotation) of a camera at eye looking at target (glTF cameras look down -Z, +Y up)."""
    def norm(v):
        n = math.sqrt(sum(c * c for c in v))
        return tuple(c / n for c in v)

    def cross(a, b):
        return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])

    back = norm(tuple(e - t for e, t in zip(eye, target)))
    right = norm(cross(up, back))
    true_up = cross(back, right)
    m = [[right[i], true_up[i], back[i]] for i in range(3)]  # columns: the camera's x, y, z in world space
    trace = m[0][0] + m[1][1] + m[2][2]
    if trace > 0.0:
        w = math.sqrt(1.0 + trace) / 2.0
        q = ((m[2][1] - m[1][2]) / (4 * w), (m[0][2] - m[2][0]) / (4 * w), (m[1][0] - m[0][1]) / (4 * w), w)
    else:
        i = max(range(3), key=lambda k: m[k][k])
        j, k = (i + 1) % 3, (i + 2) % 3
        r = math.sqrt(1.0 + m[i][i] - m[j][j] - m[k][k])
        q = [0.0, 0.0, 0.0, (m[k][j] - m[j][k]) / (2 * r)]
        q[i] = r / 2.0
        q[j] = (m[j][i] + m[i][j]) / (2 * r)
        q[k] = (m[k][i] + m[i][k]) / (2 * r)
        q = tuple(q)
    return {"translation": list(eye), "rotation": [round(c, 7) for c in q]}


def wall_x(x, y0, y1, z0, z1):
    """Two triangles of the rectangle [y0,y1]x[z0,z1] in the plane at x (front face -x)."""
    a, b, c, d = (x, y0, z0), (x, y1, z0), (x, y1, z1), (x, y0, z1)
    return [(a, c, b), (a, d, c)]


def door_gap():
    """Rooms [-2,2] and [2,4] along x (y in [-2,2], z in [0,3]); the wall between them has a door 0.2 wide and 2 high
    near its corner (y in [1.4, 1.6]); the lamp hangs in the far room under its ceiling, away from the door."""
    g = Gltf()
    walls = cube_faces_inward()
    colours = [(0.7, 0.7, 0.7), (0.7, 0.7, 0.7), (0.6, 0.3, 0.2), (0.7, 0.7, 0.7), (0.5, 0.5, 0.55), (0.8, 0.8, 0.8)]
    for face in range(6):
        material = g.add_material(base=colours[face])
        g.add_node({"mesh": g.add_mesh(placed(walls[2 * face:2 * face + 2], (3.0, 2.0, 1.5), (1.0, 0.0, 1.5)),
                                       material)})
    wall = g.add_material(base=(0.75, 0.75, 0.75), double_sided=True)
    gap0, gap1 = 1.4, 1.6
    pieces = wall_x(2.0, -2.0, gap0, 0.0, 3.0) + wall_x(2.0, gap1, 2.0, 0.0, 3.0) + wall_x(2.0, gap0, gap1, 2.0, 3.0)
    g.add_node({"mesh": g.add_mesh(pieces, wall)})
    lamp = g.add_material(base=(0.0, 0.0, 0.0), emission=300.0)
    g.add_node({"mesh": g.add_mesh(quad(3.3, 0.2, 3.7, 0.6, 2.95, facing_up=False), lamp)})
    # In the near room, looking along +x at the wall with the door, slightly down.
    g.add_perspective_camera(look_at((-1.8, -1.6, 1.6), (2.0, 1.2, 0.8)), 1.2)
    return g


def lamp_shade():
    """The lamp room without its ceiling lamp: a small downward emitter inside a shade (a cylinder of radius 0.35 from
    z = 1.7 to 2.3 with a closed top), hanging over a floor of the room; a grey box on the floor beside it."""
    g = room(lamp=False)
    shade = g.add_material(base=(0.8, 0.8, 0.8), double_sided=True)
    r, z0, z1, n = 0.35, 1.7, 2.3, 16
    ring = [(r * math.cos(2 * math.pi * i / n), r * math.sin(2 * math.pi * i / n) + 0.3) for i in range(n)]
    tris = []
    for i in range(n):
        (xa, ya), (xb, yb) = ring[i], ring[(i + 1) % n]
        a, b, c, d = (xa, ya, z0), (xb, yb, z0), (xb, yb, z1), (xa, ya, z1)
        tris += [(a, b, c), (a, c, d), ((0.0, 0.3, z1), d, c)]
    g.add_node({"mesh": g.add_mesh(tris, shade)})
    lamp = g.add_material(base=(0.0, 0.0, 0.0), emission=60.0)
    g.add_node({"mesh": g.add_mesh(quad(-0.1, 0.2, 0.1, 0.4, 2.2, facing_up=False), lamp)})
    box = g.add_material(base=(0.5, 0.5, 0.5))
    g.add_node({"mesh": g.add_mesh(placed(cube_faces_inward(), (0.3, 0.3, 0.3), (0.9, 0.6, 0.3)), box)})
    g.add_perspective_camera(look_at((0.0, -1.8, 1.5), (0.0, 0.6, 0.9)), 1.2)
    return g


def moving_room():
    g = room()
    add_spheres(g, [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0,
                                               "roughnessFactor": 1.0}}], [(0.0, 0.0, 0.0)], 0.5, 12, 6)
    sphere = len(g.doc["nodes"]) - 1
    g.doc["nodes"][sphere]["translation"] = [-0.3, 0.6, 0.6]
    camera = g.add_perspective_camera({"translation": [0.15, -1.5, 1.2], "rotation": [0.6755902, 0.0, 0.0, 0.7372773]},
                                      1.1)
    times = g.add_floats([0.0, 1.0], "SCALAR", 2)
    g.doc["animations"] = [{"name": "slide", "samplers": [
        {"input": times, "output": g.add_floats([-0.3, 0.6, 0.6, 0.3, 0.6, 0.6])},
        {"input": times, "output": g.add_floats([0.15, -1.5, 1.2, -0.15, -1.5, 1.2])}], "channels": [
        {"sampler": 0, "target": {"node": sphere, "path": "translation"}},
        {"sampler": 1, "target": {"node": camera, "path": "translation"}}]}]
    return g


def moving_furnace():
    g = Gltf()
    wall = g.add_material(base=(0.8, 0.8, 0.8), emission=0.5)
    g.add_node({"mesh": g.add_mesh(cube_faces_inward(), wall)})
    white = g.add_material(base=(1.0, 1.0, 1.0))
    outward = [(a, c, b) for a, b, c in cube_faces_inward()]
    block = g.add_node({"mesh": g.add_mesh(placed(outward, (0.3, 0.3, 0.3), (0.0, 0.0, 0.0)), white),
                        "translation": [0.2, 0.0, 0.0]})
    g.add_perspective_camera(look_at((-0.8, 0.0, 0.0), (1.0, 0.0, 0.0)), 1.0)
    times = g.add_floats([0.0, 1.0], "SCALAR", 2)
    g.doc["animations"] = [{"name": "slide", "samplers": [
        {"input": times, "output": g.add_floats([0.2, 0.0, 0.0, 0.6, 0.0, 0.0])}], "channels": [
        {"sampler": 0, "target": {"node": block, "path": "translation"}}]}]
    return g


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    out.mkdir(parents=True, exist_ok=True)
    lamp_room().write(out / "lamp_room.gltf")
    smooth_room().write(out / "smooth_room.gltf")
    glass_room().write(out / "glass_room.gltf")
    unlit_room().write(out / "unlit_room.gltf")
    glass_caustic().write(out / "glass_caustic.gltf")
    door_gap().write(out / "door_gap.gltf")
    lamp_shade().write(out / "lamp_shade.gltf")
    moving_room().write(out / "moving_room.gltf")
    moving_furnace().write(out / "moving_furnace.gltf")
    glass_bulb().write(out / "glass_bulb.gltf")
    water_glass().write(out / "water_glass.gltf")


if __name__ == "__main__":
    main()
