#!/usr/bin/env python3
"""Writes four UV spheres with KHR_materials_pbrSpecularGlossiness materials, for comparing Fredholm's mapping of the
archived extension with Blender's importer and Cycles (`compare_assets.py --models DIR/SpecGlossSpheres.gltf`): no
Khronos model in ../shared uses it.

usage: make_specular_glossiness_spheres.py OUT_DIR

Bottom row: red diffuse with a grey 0.04 specular, glossiness 0.3; dark diffuse with a coloured specular (0.9, 0.6,
0.3), glossiness 0.7. Top row: grey diffuse and specular 0.5, glossiness 0.9; textured: an 8 x 8 red/blue checker as
diffuseTexture and a specularGlossinessTexture whose rows alternate white and dark grey specular with glossiness
rising (white rows) or falling (grey rows) across the sphere.
"""
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "render" / "scenes"))
from make_asset_scenes import AssetGltf  # noqa: E402
from make_material_scenes import specular_glossiness  # noqa: E402


def uv_sphere(cx, cy, radius, rings=24, segments=48):
    """Triangles, their texture coordinates and vertex normals of a latitude-longitude sphere."""
    def point(i, j):
        theta, phi = math.pi * i / rings, 2.0 * math.pi * j / segments
        d = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
        return (cx + radius * d[0], cy + radius * d[1], radius * d[2]), d, (j / segments, i / rings)

    triangles, uvs, normals = [], [], []
    for i in range(rings):
        for j in range(segments):
            a, b, c, d = point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1)
            for t in ((a, c, b), (a, d, c)):
                triangles.append(tuple(p[0] for p in t))
                uvs.append(tuple(p[2] for p in t))
                normals.extend(p[1] for p in t)
    return triangles, uvs, normals


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    g = AssetGltf()
    checker = [(200, 60, 40, 255) if (x + y) % 2 else (40, 90, 200, 255) for y in range(8) for x in range(8)]
    diffuse_texture = g.add_texture(8, 8, checker)
    gloss = [(255, 255, 255, int(255 * x / 7)) if y % 2 else (60, 60, 60, int(255 * (1 - x / 7)))
             for y in range(8) for x in range(8)]
    gloss_texture = g.add_texture(8, 8, gloss)
    spheres = [((0.8, 0.1, 0.1), (0.04, 0.04, 0.04), 0.3, False), ((0.1, 0.1, 0.1), (0.9, 0.6, 0.3), 0.7, False),
               ((0.5, 0.5, 0.5), (0.5, 0.5, 0.5), 0.9, False), ((1.0, 1.0, 1.0), (1.0, 1.0, 1.0), 1.0, True)]
    for k, (diffuse, specular, glossiness, textured) in enumerate(spheres):
        material = specular_glossiness(g, specular, glossiness)
        extension = g.doc["materials"][material]["extensions"]["KHR_materials_pbrSpecularGlossiness"]
        extension["diffuseFactor"] = [*diffuse, 1.0]
        if textured:
            extension["diffuseTexture"] = {"index": diffuse_texture}
            extension["specularGlossinessTexture"] = {"index": gloss_texture}
        triangles, uvs, normals = uv_sphere(2.2 * (k % 2) - 1.1, 2.2 * (k // 2) - 1.1, 1.0)
        mesh = g.add_uv_mesh(triangles, uvs, material)
        g.doc["meshes"][mesh]["primitives"][0]["attributes"]["NORMAL"] = g.add_floats([c for n in normals for c in n])
        g.add_node({"mesh": mesh})
    g.write(out / "SpecGlossSpheres.gltf")


if __name__ == "__main__":
    main()
