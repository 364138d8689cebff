#!/usr/bin/env python3
"""Renders real glTF assets with Fredholm and with Blender Cycles in the same scene, and compares them.

Run with the Python of the Cycles environment (tests/bench/README.md, "Setting up"; it also needs PyPI OpenEXR):

  /opt/refbench/cycles-venv/bin/python tests/bench/compare_assets.py --fredholm build/fredholm \\
      --models DamagedHelmet,VertexColorTest --env scenes/environments/courtyard.exr --out /tmp/assets

The same scene for both renderers:
- the model as Blender's own glTF importer reads it (io_scene_gltf2, shipped with bpy), and as Fredholm reads it;
- one camera, computed here from the model's bounds: perspective, 40 degrees vertical field of view, looking at
  the bounds' centre from the front, a little above and to the right (VIEW_DIRECTION), from far enough to see the
  bounding sphere; passed to Fredholm as
  --look-from/--look-at/--yfov, built in Blender from the same numbers (glTF (x, y, z) = Blender (x, -z, y));
- light only from the environment map (a model's KHR_lights_punctual lights are left out of both: Blender's importer
  converts their candela and lux to watts, Fredholm takes them as radiometric units; `--keep-punctual-lights` keeps
  them), Fredholm --env, Blender's world Environment Texture (equirectangular,
  strength 1); Fredholm's mapping is Blender's (shaders/lib/light/environment.glsl), so no rotation is needed;
- a box pixel filter one pixel wide, no denoising, clamping or adaptive sampling, Standard view transform, 64
  bounces in Cycles and unlimited depth (Russian roulette) in Fredholm; linear Rec.709 EXR from both.

Prints, per model, the luminance means of both over the whole image and over the model's pixels alone (Cycles'
alpha with a transparent film), their relative differences, and 16 x 16 block relative differences (median, 90th
percentile, worst), and writes a contact sheet (Fredholm | Cycles | difference x4,
tone-mapped with the sRGB curve) to OUT/contact_sheet.png.

To isolate a cause: `--only-nodes NAME[,NAME]` renders only those root nodes of a model (for example the vase of
GlassVaseFlowers without its flowers, `--only-nodes GlassTransmission`), `--white-furnace` lights the model by a
uniform environment of radiance 1 (a white, lossless model then reads 1 everywhere), and `--without LAYER` and
`--single-scattering` take a layer or Cycles' multiple-scattering GGX out of the comparison (`--fredholm-args
"--disable-effect glass-multiscatter"` does the same for Fredholm's rough glass).
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import OpenEXR
import bpy
import mathutils
import numpy as np

# From the target towards the eye: in front (+Z), a little above and to the right, so that flat models lying in
# a coordinate plane are still seen.
VIEW_DIRECTION = np.array([0.2, 0.3, 1.0]) / np.linalg.norm([0.2, 0.3, 1.0])
MODELS_DIR = Path(__file__).resolve().parents[2].parent / "shared" / "scenes-thirdparty"


def find_model(name):
    if name.endswith((".gltf", ".glb")) and Path(name).is_file():  # a file of one's own
        return Path(name).resolve()
    manifest = json.loads((MODELS_DIR / "manifest.json").read_text())
    for m in manifest["models"]:
        if m["name"] == name:
            return MODELS_DIR / m["file"]
    raise SystemExit(f"compare_assets: no model {name} in {MODELS_DIR / 'manifest.json'}")


def import_model(path, keep_lights=False):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=str(path))
    if not keep_lights:
        for obj in [o for o in bpy.context.scene.objects if o.type == "LIGHT"]:
            bpy.data.objects.remove(obj, do_unlink=True)
    lo = np.full(3, np.inf)
    hi = np.full(3, -np.inf)
    for obj in bpy.context.scene.objects:
        if obj.type != "MESH":
            continue
        world = np.array(obj.matrix_world)
        for v in obj.data.vertices:
            p = world @ np.array([*v.co, 1.0])
            lo = np.minimum(lo, p[:3])
            hi = np.maximum(hi, p[:3])
    # Blender (x, y, z) -> glTF (x, z, -y)
    to_gltf = lambda b: np.array([b[0], b[2], -b[1]])
    corners = [to_gltf(np.array([x, y, z])) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    return np.min(corners, axis=0), np.max(corners, axis=0)


def make_camera(lo, hi, yfov_deg):
    centre = 0.5 * (lo + hi)
    radius = 0.5 * float(np.linalg.norm(hi - lo))
    distance = radius / math.sin(math.radians(yfov_deg) / 2.0) * 1.05
    eye = centre + distance * VIEW_DIRECTION
    return eye, centre


def use_single_scattering():
    """Principled BSDFs with single-scattering GGX (Blender's importer leaves Cycles' default, multiscatter GGX,
    which adds the energy of the bounces between microfacets; the glTF BRDF is single-scattering)."""
    for material in bpy.data.materials:
        if material.node_tree is None:
            continue
        for node in material.node_tree.nodes:
            if node.type == "BSDF_PRINCIPLED":
                node.distribution = "GGX"


# --without LAYER: the Principled BSDF input that switches a layer off in Cycles (set to 0), beside Fredholm's
# --disable-effect.
# The Principled input that switches each layer off (0). Blender's importer does not read KHR_materials_iridescence,
# so its thin film is already 0 in Cycles: `--without iridescence` removes the film from Fredholm's render alone.
LAYER_WEIGHTS = {"sheen": "Sheen Weight", "clearcoat": "Coat Weight", "transmission": "Transmission Weight",
                 "anisotropy": "Anisotropic", "iridescence": "Thin Film Thickness"}


def remove_layer(layer):
    """Every Principled BSDF with the layer's weight 0 (and nothing linked to it)."""
    for material in bpy.data.materials:
        if material.node_tree is None:
            continue
        for node in material.node_tree.nodes:
            if node.type == "BSDF_PRINCIPLED":
                socket = node.inputs[LAYER_WEIGHTS[layer]]
                for link in list(socket.links):
                    material.node_tree.links.remove(link)
                socket.default_value = 0.0


def give_thin_films(model):
    """--cycles-thin-film: the KHR_materials_iridescence films that Cycles' Principled BSDF can reproduce (factor 1,
    no textures: its Thin Film has no factor, and the thickness is then iridescenceThicknessMaximum), set on the
    materials of the same name; prints the films it cannot give."""
    if not str(model).endswith(".gltf"):
        print(f"compare_assets: {model}: films are read from .gltf files only; none given to Cycles")
        return
    doc = json.loads(Path(model).read_text())
    for index, material in enumerate(doc.get("materials", [])):
        film = material.get("extensions", {}).get("KHR_materials_iridescence")
        if film is None:
            continue
        name = material.get("name", f"material {index}")
        if (film.get("iridescenceFactor", 0.0) != 1.0 or "iridescenceTexture" in film
                or "iridescenceThicknessTexture" in film or name not in bpy.data.materials):
            print(f"compare_assets: {name}: film not given to Cycles (factor other than 1, a texture, or no name)")
            continue
        for node in bpy.data.materials[name].node_tree.nodes:
            if node.type == "BSDF_PRINCIPLED":
                node.inputs["Thin Film Thickness"].default_value = film.get("iridescenceThicknessMaximum", 400.0)
                node.inputs["Thin Film IOR"].default_value = film.get("iridescenceIor", 1.3)


def setup_blender(eye, yfov_deg, env, size, spp, seed):
    scene = bpy.context.scene
    cam_data = bpy.data.cameras.new("compare")
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = math.radians(yfov_deg)
    cam_data.clip_start = 1e-3
    cam_data.clip_end = 1e6
    cam = bpy.data.objects.new("compare", cam_data)
    scene.collection.objects.link(cam)
    cam.location = (eye[0], -eye[2], eye[1])
    # Look at the target with glTF +Y (Blender +Z) up, as Fredholm's --look-at/--up do.
    forward = -VIEW_DIRECTION
    forward_b = mathutils.Vector((forward[0], -forward[2], forward[1]))
    cam.rotation_euler = forward_b.to_track_quat("-Z", "Y").to_euler()
    scene.camera = cam
    for obj in list(scene.objects):  # the model's own lights and cameras would differ from Fredholm's scene
        if obj.type == "LIGHT":
            bpy.data.objects.remove(obj)

    world = bpy.data.worlds.new("env")
    scene.world = world
    world.use_nodes = True
    nodes = world.node_tree.nodes
    nodes.clear()
    tex = nodes.new("ShaderNodeTexEnvironment")
    tex.image = bpy.data.images.load(str(env))
    tex.interpolation = "Closest"  # Fredholm's map is piecewise constant per texel
    background = nodes.new("ShaderNodeBackground")
    output = nodes.new("ShaderNodeOutputWorld")
    world.node_tree.links.new(tex.outputs["Color"], background.inputs["Color"])
    world.node_tree.links.new(background.outputs["Background"], output.inputs["Surface"])

    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = spp
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = seed
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = 64
    c.transparent_max_bounces = 64
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = c.caustics_refractive = True
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"


def keep_only_nodes(model, names, out):
    """A copy of the model (its directory, in OUT) whose scene keeps only the root nodes named in `names`, so that
    one part of an asset can be compared alone (a .gltf with its files beside it)."""
    if model.suffix != ".gltf":
        raise SystemExit(f"compare_assets: --only-nodes needs a .gltf, not {model}")
    copy = out / f"{model.stem}_nodes"
    shutil.rmtree(copy, ignore_errors=True)
    shutil.copytree(model.parent, copy)
    doc = json.loads(model.read_text())
    scene = doc["scenes"][doc.get("scene", 0)]
    kept = [i for i in scene["nodes"] if doc["nodes"][i].get("name") in names]
    if not kept:
        raise SystemExit(f"compare_assets: no root node of {model} is named {', '.join(sorted(names))}")
    scene["nodes"] = kept
    path = copy / model.name
    path.write_text(json.dumps(doc))
    return path


def write_white_environment(path):
    """A uniform environment of radiance 1: a lossless white model returns 1 in every pixel (a white furnace)."""
    pixels = np.ones((32, 64, 3), np.float32)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"RGB": pixels}) as f:
        f.write(str(path))
    return path


def read_exr(path):
    """R, G, B of an EXR as float64 rows top to bottom (PyPI OpenEXR: Blender cannot read Fredholm's extra
    film channels)."""
    with OpenEXR.File(str(path)) as f:
        channels = f.channels()
        rgb = channels["RGB"].pixels if "RGB" in channels else channels["RGBA"].pixels[..., :3]
        return np.array(rgb, dtype=np.float64)


def srgb(x):
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def luminance(img):
    return 0.2126 * img[..., 0] + 0.7152 * img[..., 1] + 0.0722 * img[..., 2]


def save_png(rows, path):
    """rows: list of lists of HxWx3 linear images; written as one sRGB PNG."""
    tiles = [np.concatenate(r, axis=1) for r in rows]
    sheet = np.concatenate(tiles, axis=0)
    h, w, _ = sheet.shape
    img = bpy.data.images.new("sheet", w, h, alpha=False)
    rgba = np.ones((h, w, 4))
    rgba[..., :3] = srgb(sheet)
    img.pixels = rgba[::-1].ravel().tolist()
    img.filepath_raw = str(path)
    img.file_format = "PNG"
    img.save()


def block_stats(test, ref, block=16):
    h, w, _ = test.shape
    rels = []
    for y in range(0, h, block):
        for x in range(0, w, block):
            t = luminance(test[y:y + block, x:x + block]).mean()
            r = luminance(ref[y:y + block, x:x + block]).mean()
            rels.append(abs(t - r) / max(r, 1e-2 * luminance(ref).mean()))
    rels = np.array(rels)
    return float(np.median(rels)), float(np.percentile(rels, 90)), float(rels.max())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fredholm", default="build/fredholm")
    ap.add_argument("--models", required=True, help="comma-separated names from the manifest, or .gltf/.glb paths")
    ap.add_argument("--env", default="scenes/environments/courtyard.exr")
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--cycles-spp", type=int, default=0, help="Cycles samples (default: --spp)")
    ap.add_argument("--yfov", type=float, default=40.0)
    ap.add_argument("--out", default="/tmp/compare_assets")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--single-scattering", action="store_true",
                    help="Cycles: single-scattering GGX in every Principled BSDF (as the glTF BRDF)")
    ap.add_argument("--without", choices=sorted(LAYER_WEIGHTS), action="append", default=[],
                    help="leave a layer out of both renders (Fredholm --disable-effect, Cycles' weight 0), to isolate "
                         "what it contributes to a difference; repeatable")
    ap.add_argument("--time", type=float,
                    help="pose animated models at this time, seconds: Fredholm --time T, Blender's frame T x fps "
                         "(Blender's glTF importer keys time t at frame t x fps)")
    ap.add_argument("--shutter", help="OPEN,CLOSE seconds relative to --time: Fredholm --shutter; Cycles' motion blur "
                                      "centred on frame (time + (OPEN + CLOSE) / 2) x fps over (CLOSE - OPEN) x fps "
                                      "frames, deformation blur off (Fredholm poses skins and morphs at the centre)")
    ap.add_argument("--keep-punctual-lights", action="store_true",
                    help="keep the models' KHR_lights_punctual lights (their units differ between the renderers)")
    ap.add_argument("--fredholm-args", default="", help="more arguments for fredholm render, as one string "
                                                         "(for example \"--disable-effect glass-multiscatter\")")
    ap.add_argument("--cycles-thin-film", action="store_true",
                    help="give Cycles the models' iridescence films of factor 1 without textures (Blender's importer "
                         "reads none): make_film_spheres.py writes such models")
    ap.add_argument("--only-nodes", help="comma-separated root node names: render only these nodes of each model")
    ap.add_argument("--white-furnace", action="store_true",
                    help="light by a uniform environment of radiance 1 instead of --env (energy conservation)")
    args = ap.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:])
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    env = write_white_environment(out / "white.exr") if args.white_furnace else Path(args.env).resolve()
    rows, results = [], []
    for entry in args.models.split(","):
        model = find_model(entry)
        name = Path(entry).stem if entry.endswith((".gltf", ".glb")) else entry
        if args.only_nodes:
            model = keep_only_nodes(model, set(args.only_nodes.split(",")), out)
        lo, hi = import_model(model, args.keep_punctual_lights)
        eye, target = make_camera(lo, hi, args.yfov)
        f_exr, c_exr = out / f"{name}_fredholm.exr", out / f"{name}_cycles.exr"
        cmd = [args.fredholm, "render", str(model), "-o", str(f_exr), "--width", str(args.size), "--height",
               str(args.size), "--spp", str(args.spp), "--env", str(env), "--seed", str(args.seed),
               "--look-from", ",".join(f"{v:.9g}" for v in eye), "--look-at", ",".join(f"{v:.9g}" for v in target),
               "--up", "0,1,0", "--yfov", str(args.yfov), "--stats", str(out / f"{name}_fredholm.json"), "--quiet"]
        if args.time is not None:
            cmd += ["--time", f"{args.time:.9g}"]
        shutter = [float(v) for v in args.shutter.split(",")] if args.shutter else None
        if shutter:
            cmd += ["--shutter", args.shutter]
        for layer in args.without:
            cmd += ["--disable-effect", layer]
        if not args.keep_punctual_lights:
            cmd += ["--disable-effect", "punctual-lights"]
        cmd += args.fredholm_args.split()
        done = subprocess.run(cmd, capture_output=True, text=True)
        warnings = [l for l in done.stderr.splitlines() if "warning" in l and "negative values" not in l]
        if done.returncode != 0:
            print(f"{name}: fredholm failed: {done.stderr.strip()}")
            continue
        setup_blender(eye, args.yfov, env, args.size, args.cycles_spp or args.spp, args.seed)
        if args.single_scattering:
            use_single_scattering()
        if args.cycles_thin_film:
            give_thin_films(model)
        for layer in args.without:
            remove_layer(layer)
        # The model's pixels: Cycles' alpha with a transparent film (4 samples), then the real render.
        scene = bpy.context.scene
        if args.time is not None or shutter:
            fps = scene.render.fps / scene.render.fps_base
            t = (args.time or 0.0) + (0.5 * (shutter[0] + shutter[1]) if shutter else 0.0)
            frame = t * fps  # as the importer keys it
            scene.frame_set(int(math.floor(frame)), subframe=frame - math.floor(frame))
        if shutter:
            scene.render.use_motion_blur = True
            scene.render.motion_blur_position = "CENTER"
            scene.render.motion_blur_shutter = (shutter[1] - shutter[0]) * fps
            for obj in scene.objects:
                obj.cycles.use_deform_motion = False
                obj.cycles.motion_steps = 3
        scene.render.film_transparent = True
        scene.cycles.samples = 4
        scene.render.filepath = str(out / f"{name}_mask.exr")
        bpy.ops.render.render(write_still=True)
        with OpenEXR.File(str(out / f"{name}_mask.exr")) as f:
            mask = np.array(f.channels()["RGBA"].pixels)[..., 3] > 0.5
        scene.render.film_transparent = False
        scene.cycles.samples = args.cycles_spp or args.spp
        scene.render.filepath = str(c_exr)
        bpy.ops.render.render(write_still=True)
        f_img, c_img = read_exr(f_exr), read_exr(c_exr)
        f_mean, c_mean = luminance(f_img).mean(), luminance(c_img).mean()
        rel = (f_mean - c_mean) / c_mean
        f_model = luminance(f_img)[mask].mean() if mask.any() else float("nan")
        c_model = luminance(c_img)[mask].mean() if mask.any() else float("nan")
        model_rel = (f_model - c_model) / c_model
        median, p90, worst = block_stats(f_img, c_img)
        stats = json.loads((out / f"{name}_fredholm.json").read_text())
        line = {"model": name, "fredholm_mean": f_mean, "cycles_mean": c_mean, "mean_rel": rel,
                "model_pixels": int(mask.sum()), "fredholm_model_mean": f_model, "cycles_model_mean": c_model,
                "model_mean_rel": model_rel,
                "block_rel_median": median, "block_rel_p90": p90, "block_rel_max": worst,
                "effects": stats.get("effects"), "fredholm_seconds": stats.get("render_seconds"),
                "fredholm_command": " ".join(cmd),
                "warnings": warnings}
        results.append(line)
        print(f"{name}: luminance mean fredholm {f_mean:.5f} cycles {c_mean:.5f} ({100 * rel:+.2f}%); model pixels "
              f"({int(mask.sum())}) fredholm {f_model:.5f} cycles {c_model:.5f} ({100 * model_rel:+.2f}%); 16x16 blocks "
              f"rel median {100 * median:.1f}% p90 {100 * p90:.1f}% max {100 * worst:.1f}%; effects {line['effects']}"
              + (f"; {len(warnings)} warning(s): " + " | ".join(warnings) if warnings else ""), flush=True)
        diff = np.abs(f_img - c_img) * 4.0
        rows.append([f_img, c_img, diff])
    if rows:
        save_png(rows, out / "contact_sheet.png")
        (out / "results.json").write_text(json.dumps(results, indent=1) + "\n")
        print(f"wrote {out / 'contact_sheet.png'} and {out / 'results.json'}")


if __name__ == "__main__":
    main()
