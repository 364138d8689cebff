#!/usr/bin/env python3
"""Measures the directional albedo of one Principled BSDF layer in Blender Cycles, to explain differences between
Fredholm and Cycles by cause: a large quad of that material under a white environment of radiance 1, seen
orthographically at a given angle, with nothing else in the scene, so each pixel is the albedo for that view
direction. The base has no specular (Specular IOR Level 0) and is black, so only the layer reflects, or with
--white-base a white Lambert, to see what the layer takes from the base (1 - the result is what is lost).

  /opt/refbench/cycles-venv/bin/python tests/bench/cycles_layer_albedo.py --layer sheen --roughness 0.8 --degrees 0

Prints the mean over the image; compare with Fredholm's lobe (for the sheen: tests/unit/bsdf/test_bsdf_sheen prints
the reference albedo of the glTF lobe, `[furnace] white sheen ...`).
"""
import argparse
import math
import tempfile
from pathlib import Path

import OpenEXR
import bpy
import numpy as np


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--layer", choices=["sheen", "coat"], default="sheen")
    ap.add_argument("--white-base", action="store_true", help="a white Lambert base instead of black")
    ap.add_argument("--roughness", type=float, action="append", required=True)
    ap.add_argument("--degrees", type=float, action="append", required=True, help="view angle from the normal")
    ap.add_argument("--spp", type=int, default=1024)
    args = ap.parse_args()
    for roughness in args.roughness:
        for degrees in args.degrees:
            bpy.ops.wm.read_factory_settings(use_empty=True)
            scene = bpy.context.scene
            scene.render.engine = "CYCLES"
            scene.cycles.device = "CPU"
            scene.cycles.samples = args.spp
            scene.cycles.use_adaptive_sampling = False
            scene.cycles.use_denoising = False
            scene.cycles.max_bounces = 64
            scene.render.resolution_x = scene.render.resolution_y = 32
            scene.render.image_settings.file_format = "OPEN_EXR"
            scene.view_settings.view_transform = "Standard"
            world = bpy.data.worlds.new("white")
            world.use_nodes = True
            world.node_tree.nodes["Background"].inputs["Color"].default_value = (1, 1, 1, 1)
            world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
            scene.world = world
            bpy.ops.mesh.primitive_plane_add(size=1000.0)
            plane = bpy.context.object
            material = bpy.data.materials.new("layer")
            material.use_nodes = True
            bsdf = material.node_tree.nodes["Principled BSDF"]
            base = 1.0 if args.white_base else 0.0
            bsdf.inputs["Base Color"].default_value = (base, base, base, 1)
            bsdf.inputs["Specular IOR Level"].default_value = 0.0
            if args.layer == "sheen":
                bsdf.inputs["Sheen Weight"].default_value = 1.0
                bsdf.inputs["Sheen Tint"].default_value = (1, 1, 1, 1)
                bsdf.inputs["Sheen Roughness"].default_value = roughness
            else:  # as Blender's glTF importer sets a clearcoat: weight, roughness, IOR 1.5, no tint
                bsdf.inputs["Coat Weight"].default_value = 1.0
                bsdf.inputs["Coat Roughness"].default_value = roughness
                bsdf.inputs["Coat IOR"].default_value = 1.5
            plane.data.materials.append(material)
            t = math.radians(degrees)
            camera = bpy.data.cameras.new("camera")
            camera.type = "ORTHO"
            camera.ortho_scale = 1.0
            eye = bpy.data.objects.new("camera", camera)
            eye.location = (0.0, -10.0 * math.sin(t), 10.0 * math.cos(t))
            eye.rotation_euler = (t, 0.0, 0.0)
            scene.collection.objects.link(eye)
            scene.camera = eye
            with tempfile.TemporaryDirectory() as tmp:
                path = Path(tmp) / "albedo.exr"
                scene.render.filepath = str(path)
                bpy.ops.render.render(write_still=True)
                with OpenEXR.File(str(path)) as f:
                    channels = f.channels()
                    rgba = channels["RGBA"].pixels if "RGBA" in channels else channels["RGB"].pixels
            mean = float(np.asarray(rgba)[..., :3].mean())
            print(f"cycles {args.layer} roughness {roughness:.2f} over {'white' if args.white_base else 'black'} at "
                  f"{degrees:4.1f} deg: albedo {mean:.4f}", flush=True)


if __name__ == "__main__":
    main()
