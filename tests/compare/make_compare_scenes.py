#!/usr/bin/env python3
"""Writes the scenes of the `fredholm compare` tests (standard library only).

usage: make_compare_scenes.py OUT_DIR

  cornell_cube_4pct.gltf      scenes/cornell.gltf with the cube's albedo 4% lower (its own copy of the white material):
                              a change compare must detect at 256 spp.
  checker_room.gltf           a floor with an 8 x 8 checker texture (nearest) under a quad light, seen from above
                              (from between them: cameras block no light).
  checker_room_shifted.gltf   the same with the texture shifted by half a cell (KHR_texture_transform offset 1/16).
"""
import copy
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "render" / "scenes"))
from make_asset_scenes import AssetGltf, diffuse, quad, quad_uv  # noqa: E402

ALBEDO_CHANGE = 0.96


def cornell_cube_darker():
    doc = json.loads((ROOT / "scenes" / "cornell.gltf").read_text())
    cube = next(m for m in doc["meshes"] if m.get("name") == "cube")
    darker = copy.deepcopy(doc["materials"][cube["primitives"][0]["material"]])
    factor = darker["pbrMetallicRoughness"]["baseColorFactor"]
    darker["pbrMetallicRoughness"]["baseColorFactor"] = [c * ALBEDO_CHANGE for c in factor[:3]] + factor[3:]
    darker["name"] = "white_4pct_darker"
    doc["materials"].append(darker)
    for p in cube["primitives"]:
        p["material"] = len(doc["materials"]) - 1
    return doc


def checker_room(shifted):
    g = AssetGltf()
    texels = [(230, 230, 230, 255) if (x + y) % 2 == 0 else (40, 40, 40, 255) for y in range(8) for x in range(8)]
    texture = g.add_texture(8, 8, texels)
    floor = diffuse((1.0, 1.0, 1.0, 1.0), texture)
    if shifted:
        floor["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
            "KHR_texture_transform": {"offset": [1.0 / 16.0, 0.0]}}
        g.doc["extensionsUsed"].append("KHR_texture_transform")
    material = g.add_raw_material(floor)
    emitter = g.add_raw_material({"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
                                  "emissiveFactor": [1.0, 1.0, 1.0],
                                  "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}})
    g.add_node({"mesh": g.add_uv_mesh(quad(-1, -1, 1, 1, 0.0), quad_uv(), material)})
    g.add_node({"mesh": g.add_uv_mesh(quad(-0.5, -0.5, 0.5, 0.5, 2.0, facing_up=False), quad_uv(), emitter)})
    g.add_perspective_camera({"translation": [0.0, 0.0, 1.0]}, 1.0)  # looks down -z, under the light
    return g


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    (out / "cornell_cube_4pct.gltf").write_text(json.dumps(cornell_cube_darker()))
    checker_room(False).write(out / "checker_room.gltf")
    checker_room(True).write(out / "checker_room_shifted.gltf")


if __name__ == "__main__":
    main()
