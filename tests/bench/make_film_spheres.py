#!/usr/bin/env python3
"""Writes two smooth spheres under a KHR_materials_iridescence film of constant thickness (no textures), for
comparing Fredholm's thin film with Cycles' (`compare_assets.py --models DIR/film_dark.gltf,DIR/film_gold.gltf
--cycles-thin-film`): the only films Cycles can be given the same, since its Principled BSDF has no film factor and
compare_assets.py passes no thickness texture.

usage: make_film_spheres.py OUT_DIR

  film_dark.gltf  a black dielectric (ior 1.5, roughness 0.2) under a film of index 1.3, 400 nm thick: what is seen
                  is the film's reflectance alone.
  film_gold.gltf  a gold-coloured metal (base colour (1, 0.78, 0.34), roughness 0.2) under the same film.
"""
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "stability" / "render"))
from make_stability_scenes import Gltf, icosphere  # noqa: E402


def film_sphere(base, metallic):
    g = Gltf()
    g.doc["extensionsUsed"] += ["KHR_materials_iridescence"]
    g.doc["materials"].append({"name": "film", "pbrMetallicRoughness": {
        "baseColorFactor": [*base, 1.0], "metallicFactor": metallic, "roughnessFactor": 0.2},
        "extensions": {"KHR_materials_iridescence": {"iridescenceFactor": 1.0, "iridescenceIor": 1.3,
                                                     "iridescenceThicknessMaximum": 400.0}}})
    triangles = icosphere(5)
    normals = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for t in triangles for p in t]
    g.add_node({"mesh": g.add_mesh(triangles, 0, normals=normals)})
    return g


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    film_sphere((0.0, 0.0, 0.0), 0.0).write(out / "film_dark.gltf")
    film_sphere((1.0, 0.78, 0.34), 1.0).write(out / "film_gold.gltf")


if __name__ == "__main__":
    main()
