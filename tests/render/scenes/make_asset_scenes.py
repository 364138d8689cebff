#!/usr/bin/env python3
"""Writes the render-test scenes for textures, alpha and the environment light (standard library only).

usage: make_asset_scenes.py OUT_DIR

Each scene has an analytic or comparative criterion, stated beside its test in tests/render/CMakeLists.txt:
  env_plane.gltf           diffuse plane of albedo RHO (no specular), seen from above: under --background 1,1,1
                           every pixel reads RHO (the plane sees only the environment above it).
  env_plane_textured.gltf  the same with a baseColorTexture of constant sRGB byte TEXEL: reads decode(TEXEL).
  env_plane_cutouts.gltf   env_plane.gltf under three planes that MASK cuts out entirely: the same bits.
  furnace_textured.gltf    the closed furnace with its albedo from a constant texture: LE / (1 - decode(TEXEL)).
  mask_shadow.gltf         a 2x2 checker MASK quad between a directional light and a floor; the camera sees the
                           shadow on the floor only. mask_shadow_geometry.gltf has the opaque cells as geometry:
                           direct light (--max-depth 2) must match it.
  blend_shadow.gltf        the same quad as BLEND with alpha BLEND_ALPHA: the floor in its shadow receives
                           (1 - BLEND_ALPHA) of the light of the unshadowed floor_lit.gltf.
  minified_checker.gltf    an emissive checker texture of 512 x 512 one-texel cells (sRGB 255 and 0, nearest) seen
                           16 texels to a pixel: each pixel converges to the cells' mean 0.5 (no mip-map, no bias).
  textured_emitter.gltf    a ceiling quad whose emissive texture is black but for one texel of 8x8, over a floor:
                           light sampling (picks by textured power) must agree with BSDF sampling alone.
  quad_light_floor.gltf    a floor [-1, 1]^2 of albedo QUAD_FLOOR_RHO under a quad light [-QUAD_LIGHT_HALF,
                           QUAD_LIGHT_HALF]^2 at height QUAD_LIGHT_HEIGHT facing down (radiance QUAD_LIGHT_RADIANCE,
                           two triangles), seen from between them by an orthographic camera of half extent 1: with
                           --max-depth 2 a point reads RHO x L x its form factor to the rectangle (analytic;
                           tests/converge/test_light_pick_error.cpp).
  aov_glass_over_plane.gltf  env_plane.gltf under a smooth thin glass sheet at z = 1: `--aov` looks through the glass
                           (tests/render/test_aovs.cpp).
"""
import base64
import json
import math
import struct
import sys
import zlib
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "stability" / "render"))
from make_stability_scenes import Gltf, quad  # noqa: E402
from make_test_scenes import cube_faces_inward  # noqa: E402

RHO = 0.8
TEXEL = 200           # sRGB byte of the constant textures: linear 0.577580...
BLEND_ALPHA = 0.3
LIGHT_LUX = 3.0       # directional light irradiance (normal to the light)


def png_rgba(width, height, texels):
    """PNG bytes of RGBA8 texels (rows top to bottom, each an (r, g, b, a) tuple)."""
    raw = b"".join(b"\x00" + bytes(c for t in texels[y * width:(y + 1) * width] for c in t) for y in range(height))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)

    header = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


class AssetGltf(Gltf):
    """Gltf with texture coordinates and embedded PNG textures."""

    def add_texture(self, width, height, texels, nearest=True):
        self.doc.setdefault("images", []).append(
            {"uri": "data:image/png;base64," + base64.b64encode(png_rgba(width, height, texels)).decode()})
        self.doc.setdefault("samplers", []).append(
            {"magFilter": 9728 if nearest else 9729, "wrapS": 33071, "wrapT": 33071})
        self.doc.setdefault("textures", []).append(
            {"source": len(self.doc["images"]) - 1, "sampler": len(self.doc["samplers"]) - 1})
        return len(self.doc["textures"]) - 1

    def add_uv_mesh(self, triangles, uvs, material):
        positions = [c for t in triangles for p in t for c in p]
        flat_uv = [c for t in uvs for uv in t for c in uv]
        attributes = {"POSITION": self.add_floats(positions),
                      "TEXCOORD_0": self.add_floats(flat_uv, kind="VEC2", count=len(flat_uv) // 2)}
        self.doc["meshes"].append({"primitives": [{"attributes": attributes, "material": material}]})
        return len(self.doc["meshes"]) - 1

    def add_raw_material(self, material):
        self.doc["materials"].append(material)
        return len(self.doc["materials"]) - 1


def quad_uv():
    """UVs matching quad(): (x0, y0) -> (0, 1) bottom left, (x1, y1) -> (1, 0) top right (glTF: v down)."""
    a, b, c, d = (0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)
    return [(a, b, c), (a, c, d)]


def diffuse(base=(RHO, RHO, RHO, 1.0), texture=None, **extra):
    m = {"pbrMetallicRoughness": {"baseColorFactor": list(base), "metallicFactor": 0.0, "roughnessFactor": 1.0},
         "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}
    if texture is not None:
        m["pbrMetallicRoughness"]["baseColorTexture"] = {"index": texture}
    m.update(extra)
    return m


def env_plane(textured, cutouts=0):
    g = AssetGltf()
    texture = g.add_texture(1, 1, [(TEXEL, TEXEL, TEXEL, 255)]) if textured else None
    material = g.add_raw_material(diffuse((1.0, 1.0, 1.0, 1.0) if textured else (RHO, RHO, RHO, 1.0), texture))
    # Planes over the floor that MASK cuts out entirely (alpha 0 < cutoff 0.5), as if not there. Written before the
    # floor, so that a leaf holding them all lists the floor after them.
    if cutouts:
        hole = g.add_raw_material(diffuse((RHO, RHO, RHO, 0.0), alphaMode="MASK", alphaCutoff=0.5))
        for k in range(cutouts):
            g.add_node({"mesh": g.add_uv_mesh(quad(-10, -10, 10, 10, 0.4 * (k + 1)), quad_uv(), hole)})
    g.add_node({"mesh": g.add_uv_mesh(quad(-10, -10, 10, 10, 0.0), quad_uv(), material)})
    g.add_orthographic_camera({"translation": [0.0, 0.0, 2.0]}, 1.0)
    return g


def furnace_textured():
    g = AssetGltf()
    texture = g.add_texture(1, 1, [(TEXEL, TEXEL, TEXEL, 255)])
    material = g.add_raw_material(diffuse((1.0, 1.0, 1.0, 1.0), texture, emissiveFactor=[1.0, 1.0, 1.0]))
    g.doc["materials"][material]["extensions"]["KHR_materials_emissive_strength"] = {"emissiveStrength": 0.5}
    tris = cube_faces_inward()
    uvs = [((0.1, 0.2), (0.7, 0.4), (0.3, 0.9))] * len(tris)
    g.add_node({"mesh": g.add_uv_mesh(tris, uvs, material)})
    g.add_perspective_camera({"translation": [0.1, -0.2, 0.3]}, 1.2)
    return g


def shadow_scene(kind):
    """Floor z = 0; occluder over [-1, 1]^2 at z = 1; light travelling along (-2, 0, -1): the shadow lies over
    x in [-3, -1]. Camera: orthographic from above over [-3, -1] x [-1, 1]."""
    g = AssetGltf()
    floor = g.add_raw_material(diffuse((0.5, 0.5, 0.5, 1.0)))
    g.add_node({"mesh": g.add_uv_mesh(quad(-6, -4, 4, 4, 0.0), quad_uv(), floor)})
    if kind == "mask":
        checker = [(255, 255, 255, 255), (255, 255, 255, 0), (255, 255, 255, 0), (255, 255, 255, 255)]
        texture = g.add_texture(2, 2, checker)
        occluder = g.add_raw_material(diffuse((0.5, 0.5, 0.5, 1.0), texture, alphaMode="MASK", alphaCutoff=0.5,
                                              doubleSided=True))
        g.add_node({"mesh": g.add_uv_mesh(quad(-1, -1, 1, 1, 1.0), quad_uv(), occluder)})
    elif kind == "mask_geometry":  # the opaque cells of the checker: texel (0, 0) top left, (1, 1) bottom right
        occluder = g.add_raw_material(diffuse((0.5, 0.5, 0.5, 1.0), doubleSided=True))
        cells = quad(-1, 0, 0, 1, 1.0) + quad(0, -1, 1, 0, 1.0)
        g.add_node({"mesh": g.add_uv_mesh(cells, quad_uv() * 2, occluder)})
    elif kind == "blend":
        occluder = g.add_raw_material(diffuse((0.5, 0.5, 0.5, BLEND_ALPHA), alphaMode="BLEND", doubleSided=True))
        g.add_node({"mesh": g.add_uv_mesh(quad(-1, -1, 1, 1, 1.0), quad_uv(), occluder)})
    # Directional light: the node's -Z turned to (-2, 0, -1) / sqrt(5) (rotation about +Y by atan2(2, 1)).
    angle = math.atan2(2.0, 1.0)
    rotation = [0.0, math.sin(angle / 2), 0.0, math.cos(angle / 2)]
    g.add_light({"type": "directional", "intensity": LIGHT_LUX}, {"rotation": rotation})
    g.add_orthographic_camera({"translation": [-2.0, 0.0, 3.0]}, 1.0)
    return g


def minified_checker():
    g = AssetGltf()
    texels = [(255, 255, 255, 255) if (x + y) % 2 == 0 else (0, 0, 0, 255) for y in range(512) for x in range(512)]
    texture = g.add_texture(512, 512, texels)
    emitter = g.add_raw_material({"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
                                  "emissiveFactor": [1.0, 1.0, 1.0], "emissiveTexture": {"index": texture}})
    g.add_node({"mesh": g.add_uv_mesh(quad(-1, -1, 1, 1, 0.0), quad_uv(), emitter)})
    g.add_orthographic_camera({"translation": [0.0, 0.0, 1.0]}, 1.0)
    return g


def textured_emitter():
    g = AssetGltf()
    texels = [(0, 0, 0, 255)] * 64
    texels[8 * 2 + 5] = (255, 230, 200, 255)
    texture = g.add_texture(8, 8, texels)
    emitter = g.add_raw_material({"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
                                  "emissiveFactor": [1.0, 1.0, 1.0], "emissiveTexture": {"index": texture},
                                  "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 40.0}}})
    floor = g.add_raw_material(diffuse((0.7, 0.7, 0.7, 1.0)))
    g.add_node({"mesh": g.add_uv_mesh(quad(-2, -2, 2, 2, 0.0), quad_uv(), floor)})
    g.add_node({"mesh": g.add_uv_mesh(quad(-1, -1, 1, 1, 1.0, facing_up=False), quad_uv(), emitter)})
    g.add_perspective_camera({"translation": [0.0, -2.5, 1.2], "rotation": [0.5, 0.0, 0.0, 0.8660254]}, 1.0)
    return g


def glass_over_plane():
    """env_plane.gltf under a smooth, thin glass sheet of base colour 0.5 at z = 1: the AOVs look through the glass
    (the albedo is the plane's RHO but for the share the glass reflects; the first hit is the glass, 1 away)."""
    g = AssetGltf()
    g.doc["extensionsUsed"].append("KHR_materials_transmission")
    plane = g.add_raw_material(diffuse((RHO, RHO, RHO, 1.0)))
    glass = g.add_raw_material({"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 0.0,
                                                         "roughnessFactor": 0.0},
                                "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}}})
    g.add_node({"mesh": g.add_uv_mesh(quad(-10, -10, 10, 10, 0.0), quad_uv(), plane)})
    g.add_node({"mesh": g.add_uv_mesh(quad(-10, -10, 10, 10, 1.0), quad_uv(), glass)})
    g.add_orthographic_camera({"translation": [0.0, 0.0, 2.0]}, 1.0)
    return g


QUAD_FLOOR_RHO = 0.5
QUAD_LIGHT_HALF = 0.5
QUAD_LIGHT_HEIGHT = 0.5
QUAD_LIGHT_RADIANCE = 4.0


def quad_light_floor():
    g = AssetGltf()
    floor = g.add_raw_material(diffuse((QUAD_FLOOR_RHO, QUAD_FLOOR_RHO, QUAD_FLOOR_RHO, 1.0)))
    emitter = g.add_raw_material({"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
                                  "emissiveFactor": [1.0, 1.0, 1.0],
                                  "extensions": {"KHR_materials_emissive_strength":
                                                 {"emissiveStrength": QUAD_LIGHT_RADIANCE}}})
    g.add_node({"mesh": g.add_uv_mesh(quad(-1, -1, 1, 1, 0.0), quad_uv(), floor)})
    h = QUAD_LIGHT_HALF
    g.add_node({"mesh": g.add_uv_mesh(quad(-h, -h, h, h, QUAD_LIGHT_HEIGHT, facing_up=False), quad_uv(), emitter)})
    g.add_orthographic_camera({"translation": [0.0, 0.0, 0.5 * QUAD_LIGHT_HEIGHT]}, 1.0)
    return g


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    env_plane(False).write(out / "env_plane.gltf")
    env_plane(True).write(out / "env_plane_textured.gltf")
    env_plane(False, cutouts=3).write(out / "env_plane_cutouts.gltf")
    furnace_textured().write(out / "furnace_textured.gltf")
    for kind in ("mask", "mask_geometry", "blend", "lit"):
        shadow_scene(kind).write(out / ("floor_lit.gltf" if kind == "lit" else kind + "_shadow.gltf"))
    textured_emitter().write(out / "textured_emitter.gltf")
    minified_checker().write(out / "minified_checker.gltf")
    quad_light_floor().write(out / "quad_light_floor.gltf")
    glass_over_plane().write(out / "aov_glass_over_plane.gltf")


if __name__ == "__main__":
    main()
