#!/usr/bin/env python3
"""Time Mitsuba 3 or Blender Cycles rendering the same glTF scene fredholm renders.

Reads the glTF itself (json + base64 buffers, node TRS with quaternion rotations, one camera node),
builds the scene in the chosen renderer with the settings of /work/shared/references/README.md
(box filter one pixel wide, glTF camera yfov, emission = emissiveFactor x emissive_strength with no pi
factor, one-sided emitters, Lambertian surfaces, black background, no denoise/clamp/adaptive sampling)
and times ONLY the render call: one warm-up render that is not counted (JIT compilation for Mitsuba),
then the median of --repeats renders.

Prints one line:
    RENDERER seconds_median S runs S1,S2,S3 warmup_s W size N spp N max_depth N threads T version V ...
and, with --reference, one line comparing the mean of the (last timed) image with a reference image.

Run it with the renderer's own Python (see README.md beside this file):
    /opt/refbench/mitsuba-venv/bin/python tests/bench/compare_renderers.py --renderer mitsuba
    /opt/refbench/cycles-venv/bin/python  tests/bench/compare_renderers.py --renderer cycles
"""

import argparse
import base64
import json
import math
import os
import statistics
import sys
import tempfile
import time
import warnings

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEFAULT_SCENE = os.path.join(REPO, "scenes", "cornell.gltf")

# --------------------------------------------------------------------------------------------------
# glTF parsing
# --------------------------------------------------------------------------------------------------

_COMPONENT_DTYPES = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16,
                     5125: np.uint32, 5126: np.float32}
_TYPE_SIZES = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


def _load_buffers(doc, base_dir, glb_chunk=None):
    out = []
    for b in doc.get("buffers", []):
        uri = b.get("uri")
        if uri is None:
            if glb_chunk is None:
                raise ValueError("a buffer without a uri outside a .glb")
            out.append(glb_chunk)
            continue
        if uri.startswith("data:"):
            data = base64.b64decode(uri.split(",", 1)[1])
        else:
            with open(os.path.join(base_dir, uri), "rb") as f:
                data = f.read()
        out.append(data)
    return out


def _read_accessor(doc, buffers, index):
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    dtype = np.dtype(_COMPONENT_DTYPES[acc["componentType"]])
    ncomp = _TYPE_SIZES[acc["type"]]
    count = acc["count"]
    offset = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    stride = view.get("byteStride", 0) or dtype.itemsize * ncomp
    raw = buffers[view["buffer"]]
    if stride == dtype.itemsize * ncomp:
        arr = np.frombuffer(raw, dtype=dtype, count=count * ncomp, offset=offset)
    else:  # interleaved
        arr = np.stack([np.frombuffer(raw, dtype=dtype, count=ncomp, offset=offset + i * stride)
                        for i in range(count)])
    return arr.reshape(count, ncomp) if ncomp > 1 else arr.reshape(count)


def _quat_to_matrix(q):
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ], dtype=np.float64)


def _node_matrix(node):
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T  # glTF is column-major
    t = np.array(node.get("translation", [0.0, 0.0, 0.0]), dtype=np.float64)
    r = node.get("rotation", [0.0, 0.0, 0.0, 1.0])
    s = np.array(node.get("scale", [1.0, 1.0, 1.0]), dtype=np.float64)
    m = np.eye(4)
    m[:3, :3] = _quat_to_matrix(r) @ np.diag(s)
    m[:3, 3] = t
    return m


def _read_document(path):
    """The glTF JSON and, for a .glb, its binary chunk (glTF 2.0 section 4.4: 12-byte header, then chunks)."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] != b"glTF":
        return json.loads(data.decode("utf-8")), None
    offset, doc, chunk = 12, None, None
    while offset + 8 <= len(data):
        length, kind = int.from_bytes(data[offset:offset + 4], "little"), data[offset + 4:offset + 8]
        body = data[offset + 8:offset + 8 + length]
        if kind == b"JSON":
            doc = json.loads(body.decode("utf-8"))
        elif kind == b"BIN\0":
            chunk = body
        offset += 8 + length
    if doc is None:
        raise ValueError("%s: a .glb without a JSON chunk" % path)
    return doc, chunk


def load_gltf(path, need_camera=True):
    """Return {'meshes': [...], 'camera': {...}} with world-space triangle meshes (.gltf or .glb): every node of the
    default scene, its transform applied. The camera is the first camera node's; without one, a ValueError, or
    None when need_camera is False."""
    doc_check, _ = _read_document(path)
    for ext in ("KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_mesh_quantization"):
        if ext in doc_check.get("extensionsUsed", []):
            raise ValueError("%s: %s is not read here" % (path, ext))
    doc, chunk = _read_document(path)
    buffers = _load_buffers(doc, os.path.dirname(os.path.abspath(path)), chunk)
    materials = doc.get("materials", [])

    def material(idx):
        m = materials[idx] if idx is not None else {}
        pbr = m.get("pbrMetallicRoughness", {})
        ext = m.get("extensions", {})
        strength = ext.get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
        emission = np.array(m.get("emissiveFactor", [0.0, 0.0, 0.0]), dtype=np.float64) * strength
        return {
            "name": m.get("name", "default"),
            "base_color": [float(c) for c in pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0])[:3]],
            "emission": [float(c) for c in emission],
            "double_sided": bool(m.get("doubleSided", False)),
        }

    meshes, camera = [], None
    scene_index = doc.get("scene", 0)
    roots = doc["scenes"][scene_index]["nodes"] if doc.get("scenes") else range(len(doc["nodes"]))

    def visit(node_index, parent):
        nonlocal camera
        node = doc["nodes"][node_index]
        world = parent @ _node_matrix(node)
        name = node.get("name", "node%d" % node_index)
        if "mesh" in node:
            for pi, prim in enumerate(doc["meshes"][node["mesh"]]["primitives"]):
                if prim.get("mode", 4) != 4:
                    raise ValueError("only triangle primitives are supported (node %s)" % name)
                pos = _read_accessor(doc, buffers, prim["attributes"]["POSITION"]).astype(np.float64)
                if "indices" in prim:
                    idx = _read_accessor(doc, buffers, prim["indices"]).astype(np.uint32)
                else:
                    idx = np.arange(len(pos), dtype=np.uint32)
                pos_w = pos @ world[:3, :3].T + world[:3, 3]
                faces = idx.reshape(-1, 3)
                if np.linalg.det(world[:3, :3]) < 0:  # mirrored transform flips the winding
                    faces = faces[:, [0, 2, 1]]
                meshes.append({
                    "name": "%s_%d" % (name, pi),
                    "positions": np.ascontiguousarray(pos_w, dtype=np.float32),
                    "faces": np.ascontiguousarray(faces, dtype=np.uint32),
                    "material": material(prim.get("material")),
                })
        if "camera" in node and camera is None:
            cam = doc["cameras"][node["camera"]]
            if cam.get("type") != "perspective":
                raise ValueError("only perspective cameras are supported")
            p = cam["perspective"]
            rot = world[:3, :3] / np.linalg.norm(world[:3, :3], axis=0)  # drop any scale
            camera = {
                "world": world,
                "origin": world[:3, 3].copy(),
                "forward": rot @ np.array([0.0, 0.0, -1.0]),  # glTF cameras look down -Z, +Y up
                "up": rot @ np.array([0.0, 1.0, 0.0]),
                "yfov": float(p["yfov"]),
                "aspect": float(p.get("aspectRatio", 1.0)),
                "znear": float(p.get("znear", 0.01)),
                "zfar": float(p.get("zfar", 1e4)),
            }
        for child in node.get("children", []):
            visit(child, world)

    for r in roots:
        visit(r, np.eye(4))
    if camera is None and need_camera:
        raise ValueError("the scene has no camera node")
    return {"meshes": meshes, "camera": camera}


# --------------------------------------------------------------------------------------------------
# Mitsuba 3
# --------------------------------------------------------------------------------------------------

class MitsubaRenderer:
    name = "mitsuba"

    def __init__(self, scene, args):
        import drjit as dr
        import mitsuba as mi
        mi.set_variant(args.mitsuba_variant)
        if args.threads > 0:
            dr.set_thread_count(args.threads)
        self.dr, self.mi, self.args = dr, mi, args
        self.image = None

        objects = {"type": "scene"}
        cam = scene["camera"]
        target = cam["origin"] + cam["forward"]
        objects["camera"] = {
            "type": "perspective",
            "fov_axis": "y",
            "fov": math.degrees(cam["yfov"]),
            "near_clip": cam["znear"],
            "far_clip": cam["zfar"],
            "to_world": mi.ScalarTransform4f().look_at(origin=[float(v) for v in cam["origin"]],
                                                      target=[float(v) for v in target],
                                                      up=[float(v) for v in cam["up"]]),
            "film": {
                "type": "hdrfilm",
                "width": args.size,
                "height": args.size,
                "pixel_format": "rgb",
                "component_format": "float32",
                "rfilter": {"type": "box"},  # radius 0.5: one pixel wide
            },
            "sampler": {"type": args.mitsuba_sampler, "sample_count": args.spp},
        }
        objects["integrator"] = {"type": "path", "max_depth": args.max_depth, "hide_emitters": False}
        # no environment emitter: black background

        for i, m in enumerate(scene["meshes"]):
            mat = m["material"]
            props = mi.Properties()
            bsdf = mi.load_dict({"type": "diffuse",
                                 "reflectance": {"type": "rgb", "value": mat["base_color"]}})
            if mat["double_sided"]:
                bsdf = mi.load_dict({"type": "twosided", "bsdf": bsdf})
            props["bsdf"] = bsdf
            if any(c > 0.0 for c in mat["emission"]):
                # Mitsuba's area emitter is one-sided (front face, the glTF winding's normal side);
                # radiance is the value a directly seen emitter reads, no pi factor.
                props["emitter"] = mi.load_dict({"type": "area",
                                                 "radiance": {"type": "rgb", "value": mat["emission"]}})
            mesh = mi.Mesh(m["name"], len(m["positions"]), len(m["faces"]), props,
                           has_vertex_normals=False)  # flat shading
            params = mi.traverse(mesh)
            params["vertex_positions"] = mi.Float(m["positions"].ravel())
            params["faces"] = mi.UInt32(m["faces"].ravel())
            params.update()
            objects["mesh_%02d_%s" % (i, m["name"])] = mesh
        self.scene = mi.load_dict(objects)

    def render(self, seed):
        img = self.mi.render(self.scene, seed=seed, spp=self.args.spp)
        self.dr.eval(img)
        self.dr.sync_thread()  # wait for the kernels to finish
        self.image = img

    def result(self):
        return np.array(self.image, dtype=np.float32)[:, :, :3]  # top row first

    def finish(self):
        # Bitmap's EXR reading and writing deadlock in a one-thread Dr.Jit pool: give it the cores back
        if self.args.threads == 1:
            self.dr.set_thread_count(max(os.cpu_count() or 2, 2))

    def write(self, path):
        self.mi.Bitmap(self.image).write(path)

    def load(self, path):
        bmp = self.mi.Bitmap(path).convert(self.mi.Bitmap.PixelFormat.RGB,
                                           self.mi.Struct.Type.Float32, srgb_gamma=False)
        return np.array(bmp, dtype=np.float32)[:, :, :3]

    def info(self):
        import drjit as dr
        llvm = sorted({os.path.basename(l.split()[-1]) for l in open("/proc/self/maps")
                       if "LLVM" in l and "/" in l})
        return {"version": self.mi.__version__, "drjit": dr.__version__,
                "variant": self.args.mitsuba_variant, "sampler": self.args.mitsuba_sampler,
                "llvm": ",".join(llvm) or "none",
                "threads": self.args.threads or os.cpu_count()}


# --------------------------------------------------------------------------------------------------
# Blender Cycles (bpy)
# --------------------------------------------------------------------------------------------------

class CyclesRenderer:
    name = "cycles"

    def __init__(self, scene, args):
        import bpy
        warnings.filterwarnings("ignore", category=DeprecationWarning)  # use_nodes in Blender 5
        self.bpy, self.args = bpy, args
        bpy.ops.wm.read_factory_settings(use_empty=True)
        sc = bpy.context.scene
        self.sc = sc

        sc.render.engine = "CYCLES"
        prefs = bpy.context.preferences.addons["cycles"].preferences
        prefs.compute_device_type = "NONE"
        sc.cycles.device = "CPU"
        sc.render.resolution_x = args.size
        sc.render.resolution_y = args.size
        sc.render.resolution_percentage = 100
        sc.render.pixel_aspect_x = sc.render.pixel_aspect_y = 1.0
        sc.render.film_transparent = False
        sc.render.use_compositing = False
        sc.render.use_sequencer = False
        if args.threads > 0:
            sc.render.threads_mode = "FIXED"
            sc.render.threads = args.threads
        else:
            sc.render.threads_mode = "AUTO"

        cy = sc.cycles
        cy.samples = args.spp
        cy.use_adaptive_sampling = False
        cy.use_denoising = False
        cy.sample_clamp_direct = 0.0
        cy.sample_clamp_indirect = 0.0
        cy.pixel_filter_type = "BOX"
        sc.render.filter_size = 1.0  # box filter one pixel wide
        cy.filter_width = 1.0
        bounces = max(args.max_depth - 2, 0)  # Cycles counts indirect bounces only
        cy.max_bounces = bounces
        cy.diffuse_bounces = bounces
        cy.glossy_bounces = bounces
        cy.transmission_bounces = bounces
        cy.volume_bounces = 0
        cy.transparent_max_bounces = bounces
        cy.blur_glossy = 0.0
        cy.caustics_reflective = True
        cy.caustics_refractive = True
        cy.seed = 0
        cy.use_animated_seed = False
        sc.view_settings.view_transform = "Standard"
        sc.view_settings.look = "None"
        sc.view_settings.exposure = 0.0
        sc.view_settings.gamma = 1.0

        # black background
        world = bpy.data.worlds.new("black")
        world.use_nodes = True
        bg = world.node_tree.nodes.get("Background")
        if bg is None:
            bg = world.node_tree.nodes.new("ShaderNodeBackground")
        bg.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
        bg.inputs["Strength"].default_value = 0.0
        sc.world = world

        # camera: Blender cameras look down -Z with +Y up, like glTF's, so the node matrix is used as is
        c = scene["camera"]
        cam_data = bpy.data.cameras.new("camera")
        cam_data.type = "PERSP"
        cam_data.sensor_fit = "VERTICAL"
        cam_data.lens_unit = "FOV"
        cam_data.angle_y = c["yfov"]
        cam_data.clip_start = c["znear"]
        cam_data.clip_end = c["zfar"]
        cam_data.shift_x = cam_data.shift_y = 0.0
        cam_obj = bpy.data.objects.new("camera", cam_data)
        world_m = c["world"].copy()
        world_m[:3, :3] = world_m[:3, :3] / np.linalg.norm(world_m[:3, :3], axis=0)
        import mathutils
        cam_obj.matrix_world = mathutils.Matrix(world_m.tolist())
        sc.collection.objects.link(cam_obj)
        sc.camera = cam_obj

        mat_cache = {}
        for m in scene["meshes"]:
            mat = m["material"]
            key = json.dumps(mat, sort_keys=True)
            if key not in mat_cache:
                mat_cache[key] = self._material(mat)
            me = bpy.data.meshes.new(m["name"])
            me.from_pydata([tuple(map(float, p)) for p in m["positions"]], [],
                           [tuple(map(int, f)) for f in m["faces"]])
            me.update()
            for poly in me.polygons:
                poly.use_smooth = False  # flat shading
            me.materials.append(mat_cache[key])
            obj = bpy.data.objects.new(m["name"], me)  # positions are already in world space
            sc.collection.objects.link(obj)

        sc.render.image_settings.file_format = "OPEN_EXR"
        sc.render.image_settings.color_depth = "32"
        sc.render.image_settings.exr_codec = "ZIP"
        sc.render.image_settings.color_mode = "RGB"
        self.image_path = None

    def _material(self, mat):
        bpy = self.bpy
        bm = bpy.data.materials.new(mat["name"])
        bm.use_nodes = True
        nt = bm.node_tree
        nt.nodes.clear()
        out = nt.nodes.new("ShaderNodeOutputMaterial")
        diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")  # Lambertian (roughness 0 = Lambert)
        diffuse.inputs["Color"].default_value = tuple(mat["base_color"]) + (1.0,)
        diffuse.inputs["Roughness"].default_value = 0.0
        surface = diffuse.outputs["BSDF"]
        if any(c > 0.0 for c in mat["emission"]):
            emit = nt.nodes.new("ShaderNodeEmission")  # radiance = Color x Strength, no pi factor
            emit.inputs["Color"].default_value = tuple(mat["emission"]) + (1.0,)
            emit.inputs["Strength"].default_value = 1.0
            add = nt.nodes.new("ShaderNodeAddShader")
            nt.links.new(diffuse.outputs["BSDF"], add.inputs[0])
            nt.links.new(emit.outputs["Emission"], add.inputs[1])
            surface = add.outputs["Shader"]
            if not mat["double_sided"]:
                # one-sided emitter: front face only (glTF winding normal side)
                geo = nt.nodes.new("ShaderNodeNewGeometry")
                mix = nt.nodes.new("ShaderNodeMixShader")
                nt.links.new(geo.outputs["Backfacing"], mix.inputs["Fac"])
                nt.links.new(add.outputs["Shader"], mix.inputs[1])
                nt.links.new(diffuse.outputs["BSDF"], mix.inputs[2])
                surface = mix.outputs["Shader"]
                if hasattr(bm, "emission_sampling"):
                    bm.emission_sampling = "FRONT"
        nt.links.new(surface, out.inputs["Surface"])
        return bm

    def render(self, seed):
        self.sc.cycles.seed = seed
        self.bpy.ops.render.render(write_still=False)

    def _save(self, path):
        self.bpy.data.images["Render Result"].save_render(filepath=path, scene=self.sc)

    def result(self):
        fd, path = tempfile.mkstemp(suffix=".exr")
        os.close(fd)
        try:
            self._save(path)
            return self.load(path)
        finally:
            os.unlink(path)

    def finish(self):
        pass

    def write(self, path):
        self._save(path)

    def load(self, path):
        img = self.bpy.data.images.load(path, check_existing=False)
        try:
            w, h = img.size
            ch = img.channels
            px = np.empty(w * h * ch, dtype=np.float32)
            img.pixels.foreach_get(px)
            return px.reshape(h, w, ch)[::-1, :, :3].copy()  # Blender stores the bottom row first
        finally:
            self.bpy.data.images.remove(img)

    def info(self):
        return {"version": self.bpy.app.version_string, "device": self.sc.cycles.device,
                "max_bounces": self.sc.cycles.max_bounces,
                "filter": "%s/%g" % (self.sc.cycles.pixel_filter_type, self.sc.cycles.filter_width),
                "threads": self.args.threads or os.cpu_count()}


# --------------------------------------------------------------------------------------------------

def compare(img, ref, block=16):
    """Mean agreement of img with ref: per-channel mean ratios and 16x16 block-mean deviations."""
    if img.shape != ref.shape:
        raise ValueError("image %s and reference %s differ in size" % (img.shape, ref.shape))
    m, r = img.mean(axis=(0, 1)), ref.mean(axis=(0, 1))
    h, w = img.shape[0] // block, img.shape[1] // block
    bi = img[:h * block, :w * block].reshape(h, block, w, block, 3).mean(axis=(1, 3))
    br = ref[:h * block, :w * block].reshape(h, block, w, block, 3).mean(axis=(1, 3))
    rel = np.abs(bi.mean(axis=2) - br.mean(axis=2)) / np.maximum(br.mean(axis=2), 1e-3)
    return {
        "mean": float(img.mean()), "ref_mean": float(ref.mean()),
        "mean_rel_diff": float(img.mean() / ref.mean() - 1.0),
        "channel_rel_diff": [float(a / b - 1.0) for a, b in zip(m, r)],
        "block_rel_diff_median": float(np.median(rel)),
        "block_rel_diff_max": float(rel.max()),
        "mse": float(np.mean((img.astype(np.float64) - ref.astype(np.float64)) ** 2)),
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--renderer", required=True, choices=["mitsuba", "cycles"])
    ap.add_argument("--scene", default=DEFAULT_SCENE)
    ap.add_argument("--size", type=int, default=256, help="image width and height (default 256)")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--max-depth", type=int, default=10,
                    help="Mitsuba max_depth; Cycles gets max bounces = max_depth - 2 (default 10)")
    ap.add_argument("--repeats", type=int, default=3, help="timed renders; the median is reported")
    ap.add_argument("--warmup", type=int, default=1, help="untimed renders first (default 1)")
    ap.add_argument("--threads", type=int, default=0, help="render threads (0: all cores)")
    ap.add_argument("--seed", type=int, default=0,
                    help="seed of every render (the same seed lets Mitsuba reuse its compiled kernel)")
    ap.add_argument("--mitsuba-variant", default="llvm_ad_rgb")
    ap.add_argument("--mitsuba-sampler", default="independent",
                    help="Mitsuba's sampler: independent, stratified, multijitter, orthogonal, ldsampler")
    ap.add_argument("--output", help="write the last timed image here (.exr)")
    ap.add_argument("--reference", help="compare the last timed image's mean with this .exr")
    args = ap.parse_args(argv)
    if args.repeats < 1:
        ap.error("--repeats must be at least 1")

    scene = load_gltf(args.scene)
    cls = MitsubaRenderer if args.renderer == "mitsuba" else CyclesRenderer
    t0 = time.perf_counter()
    r = cls(scene, args)
    setup_s = time.perf_counter() - t0

    warm = []
    for _ in range(args.warmup):
        t0 = time.perf_counter()
        r.render(args.seed)
        warm.append(time.perf_counter() - t0)
    runs = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        r.render(args.seed)
        runs.append(time.perf_counter() - t0)

    fields = [args.renderer, "seconds_median", "%.4f" % statistics.median(runs),
              "runs", ",".join("%.4f" % s for s in runs),
              "warmup_s", ",".join("%.4f" % s for s in warm) or "none",
              "setup_s", "%.3f" % setup_s,
              "size", str(args.size), "spp", str(args.spp), "max_depth", str(args.max_depth)]
    for k, v in r.info().items():
        fields += [k, str(v)]
    print(" ".join(fields), flush=True)

    r.finish()
    if args.output:
        r.write(args.output)
    if args.reference:
        c = compare(r.result(), r.load(args.reference))
        print("%s compare reference %s mean %.6f ref_mean %.6f mean_rel_diff %+.4f%% "
              "channel_rel_diff %s block16_rel_diff median %.2f%% max %.2f%% mse %.4e efficiency %.4e" % (
                  args.renderer, os.path.basename(args.reference), c["mean"], c["ref_mean"],
                  100 * c["mean_rel_diff"],
                  ",".join("%+.4f%%" % (100 * x) for x in c["channel_rel_diff"]),
                  100 * c["block_rel_diff_median"], 100 * c["block_rel_diff_max"], c["mse"],
                  1.0 / (c["mse"] * statistics.median(runs))), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
