#!/usr/bin/env python3
"""Writes the malformed glTF files of tests/robustness/bad/ (run it from anywhere; the files are committed).

Each file is one triangle scene broken in one way; tests/robustness/CMakeLists.txt lists what fredholm must say.
"""
import base64
import copy
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))

TRIANGLE = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)]


def pack_floats(points):
    return b"".join(struct.pack("<3f", *p) for p in points)


def triangle_scene(points=TRIANGLE, indices=(0, 1, 2), uri=None):
    """A valid scene: one node, one mesh, positions + uint16 indices in one buffer."""
    pos = pack_floats(points)
    idx = struct.pack("<%dH" % len(indices), *indices)
    while len(idx) % 4:
        idx += b"\0"
    data = pos + idx
    buffer = {"byteLength": len(data),
              "uri": uri or "data:application/octet-stream;base64," + base64.b64encode(data).decode()}
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [buffer],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
                        {"buffer": 0, "byteOffset": len(pos), "byteLength": 2 * len(indices)}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(points), "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": len(indices), "type": "SCALAR"},
        ],
    }
    return doc, data


def animated_by_pointer(doc, pointer):
    """`doc` with one KHR_animation_pointer channel on `pointer`: two keys (t = 0, 1) of one VEC4 each, in a second
    buffer."""
    d = copy.deepcopy(doc)
    data = struct.pack("<2f", 0.0, 1.0) + struct.pack("<8f", *([0.0] * 4 + [1.0] * 4))
    d["buffers"].append({"byteLength": len(data),
                         "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()})
    buffer = len(d["buffers"]) - 1
    d["bufferViews"] += [{"buffer": buffer, "byteOffset": 0, "byteLength": 8},
                         {"buffer": buffer, "byteOffset": 8, "byteLength": 32}]
    views = len(d["bufferViews"])
    d["accessors"] += [{"bufferView": views - 2, "componentType": 5126, "count": 2, "type": "SCALAR",
                        "min": [0.0], "max": [1.0]},
                       {"bufferView": views - 1, "componentType": 5126, "count": 2, "type": "VEC4"}]
    accessors = len(d["accessors"])
    d["extensionsUsed"] = d.get("extensionsUsed", []) + ["KHR_animation_pointer"]
    d["animations"] = [{"samplers": [{"input": accessors - 2, "output": accessors - 1}],
                        "channels": [{"sampler": 0, "target": {
                            "path": "pointer", "extensions": {"KHR_animation_pointer": {"pointer": pointer}}}}]}]
    return d


def png_1x1():
    """A valid 1x1 RGBA PNG."""
    import zlib

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 1, 1, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(b"\x00\xff\x80\x40\xff")) + chunk(b"IEND", b""))


def png_black(width, height):
    """A black opaque RGBA PNG of any size (compresses to almost nothing)."""
    import zlib

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)
    row = b"\x00" + b"\x00\x00\x00\xff" * width
    raw = zlib.compress(row * height, 9)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", raw) + chunk(b"IEND", b""))


def textured_scene(image_uri, texcoords=True):
    """The triangle with a baseColorTexture from `image_uri` (and TEXCOORD_0 unless told otherwise)."""
    doc, data = triangle_scene()
    doc = copy.deepcopy(doc)
    doc["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
    doc["meshes"][0]["primitives"][0]["material"] = 0
    doc["textures"] = [{"source": 0}]
    doc["images"] = [{"uri": image_uri}]
    if texcoords:
        uv = struct.pack("<6f", 0, 0, 1, 0, 0, 1)
        data = data + uv
        doc["buffers"][0] = {"byteLength": len(data),
                             "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}
        doc["bufferViews"].append({"buffer": 0, "byteOffset": len(data) - len(uv), "byteLength": len(uv)})
        doc["accessors"].append({"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"})
        doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2
    return doc


def data_uri(mime, payload):
    return "data:" + mime + ";base64," + base64.b64encode(payload).decode()


def write(name, doc):
    with open(os.path.join(HERE, name), "w") as f:
        if isinstance(doc, str):
            f.write(doc)
        else:
            json.dump(doc, f, indent=1, allow_nan=True)
            f.write("\n")


def main():
    doc, data = triangle_scene()
    text = json.dumps(doc)
    write("invalid_json.gltf", text[: len(text) // 2])
    write("not_json.gltf", "this is not a glTF file\n")

    d = copy.deepcopy(doc)
    d["accessors"][0]["count"] = "three"
    write("wrong_type_count.gltf", d)
    d = copy.deepcopy(doc)
    d["nodes"] = {"mesh": 0}
    write("wrong_type_nodes.gltf", d)
    d = copy.deepcopy(doc)
    d["nodes"][0]["mesh"] = "zero"
    write("wrong_type_mesh_index.gltf", d)

    d, _ = triangle_scene(uri="missing_file.bin")
    write("missing_bin.gltf", d)
    d, _ = triangle_scene(uri="truncated.bin")
    write("truncated_bin.gltf", d)
    with open(os.path.join(HERE, "truncated.bin"), "wb") as f:
        f.write(data[:20])
    d = copy.deepcopy(doc)
    d["buffers"][0]["uri"] = "data:application/octet-stream;base64,@@not base64!!"
    write("bad_data_uri.gltf", d)

    d = copy.deepcopy(doc)
    d["accessors"][0]["count"] = 4
    write("accessor_past_view.gltf", d)
    d = copy.deepcopy(doc)
    d["bufferViews"][0]["byteLength"] = 4096
    write("view_past_buffer.gltf", d)
    d = copy.deepcopy(doc)
    d["accessors"][0]["byteOffset"] = 2**62
    write("accessor_offset_overflow.gltf", d)
    d, _ = triangle_scene(indices=(0, 1, 7))
    write("index_out_of_range.gltf", d)
    d = copy.deepcopy(doc)
    d["accessors"][0]["count"] = 2**40
    write("count_too_large.gltf", d)
    d = copy.deepcopy(doc)  # sparse-only accessor: no bufferView, so no buffer bounds its count
    d["accessors"][0] = {"componentType": 5126, "count": 2**36, "type": "VEC3",
                         "sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5123},
                                    "values": {"bufferView": 0}}}
    write("sparse_count_too_large.gltf", d)

    d = copy.deepcopy(doc)
    d["nodes"] = [{"mesh": 0, "children": [1]}, {"children": [0]}]
    write("node_cycle.gltf", d)
    d = copy.deepcopy(doc)
    d["nodes"] = [{"children": [0]}]
    d["nodes"][0]["mesh"] = 0
    write("node_own_child.gltf", d)
    d = copy.deepcopy(doc)  # each node has the next one as both of its children: 2^40 paths to the mesh
    d["nodes"] = [{"children": [i + 1, i + 1]} for i in range(40)] + [{"mesh": 0}]
    write("node_dag_explosion.gltf", d)
    d = copy.deepcopy(doc)
    d["nodes"][0]["children"] = [5]
    write("node_child_missing.gltf", d)

    d = copy.deepcopy(doc)  # finite numbers whose product overflows: the world transform is infinite
    d["nodes"] = [{"scale": [1e200, 1e200, 1e200], "children": [1]}, {"scale": [1e200, 1e200, 1e200], "mesh": 0}]
    write("transform_overflow.gltf", d)
    d = copy.deepcopy(doc)
    d["nodes"][0]["translation"] = [0, 0, 0]
    write("infinite_translation.gltf", json.dumps(d).replace('"translation": [0, 0, 0]', '"translation": [0, -1e999, 0]'))
    d, _ = triangle_scene(points=[(float("nan"), 0, 0), (1, 0, 0), (0, 1, 0)])
    write("nan_positions_only.gltf", json.dumps(d))
    # Finite, but beyond the coordinates the GPU's box tests hold for (layout.h MAX_RENDER_COORDINATE = 1e29): the
    # triangle drawn twice, 1e31 apart (render space is centred between them, so each is 5e30 from its origin; the
    # test stores the mesh once, with --instancing on), and a camera 1e30 from the triangle.
    d = copy.deepcopy(doc)
    d["scenes"] = [{"nodes": [0, 1]}]
    d["nodes"].append({"mesh": 0, "translation": [1e31, 0, 0]})
    write("geometry_too_far.gltf", d)
    d = copy.deepcopy(doc)
    d["scene"] = 0
    d["scenes"] = [{"nodes": [0, 1]}]
    d["nodes"].append({"camera": 0, "translation": [0, 0, 1e30]})
    d["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.01}}]
    write("camera_too_far.gltf", d)

    d = copy.deepcopy(doc)
    d["extensionsUsed"] = ["EXT_fredholm_never_supported"]
    d["extensionsRequired"] = ["EXT_fredholm_never_supported"]
    write("required_extension.gltf", d)
    d = copy.deepcopy(doc)
    d["extensionsUsed"] = ["KHR_node_visibility"]
    d["nodes"][0]["extensions"] = {"KHR_node_visibility": {"visible": 2}}
    write("visibility_not_boolean.gltf", d)
    d = copy.deepcopy(doc)
    d["extensionsUsed"] = ["KHR_materials_pbrSpecularGlossiness"]
    d["materials"] = [{"extensions": {"KHR_materials_pbrSpecularGlossiness": {"specularGlossinessTexture": 3}}}]
    d["meshes"][0]["primitives"][0]["material"] = 0
    write("specular_glossiness_texture_not_an_object.gltf", d)
    d = animated_by_pointer(doc, "/materials/4/pbrMetallicRoughness/baseColorFactor")
    write("animation_pointer_missing_material.gltf", d)
    d = copy.deepcopy(doc)
    d["nodes"] = []
    d["scenes"] = [{"nodes": []}]
    write("empty_scene.gltf", d)
    d = copy.deepcopy(doc)
    d["scene"] = 3
    write("default_scene_missing.gltf", d)
    d = copy.deepcopy(doc)
    d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 9
    write("position_accessor_missing.gltf", d)
    d = copy.deepcopy(doc)
    d["meshes"][0]["primitives"][0]["material"] = 4
    write("material_missing.gltf", d)

    # Textures: missing, corrupt and unsupported images, broken references, attributes that are not there.
    write("image_missing.gltf", textured_scene("missing_image.png"))
    write("image_corrupt.gltf", textured_scene(data_uri("image/png", png_1x1()[:40])))
    # Headers that declare 30,000 x 30,000 texels (3.4 GiB decoded): refused with the size and the limit before decoding.
    big_png = png_1x1()
    big_png = big_png[:16] + struct.pack(">II", 30000, 30000) + big_png[24:]
    write("image_too_large_png.gltf", textured_scene(data_uri("image/png", big_png)))
    big_jpeg = b"\xff\xd8" + b"\xff\xe0" + struct.pack(">H", 16) + b"JFIF\0\1\1\0\0\1\0\1\0\0" + \
        b"\xff\xc0" + struct.pack(">HBHHB", 11, 8, 30000, 30000, 1) + b"\x01\x11\x00" + b"\xff\xd9"
    write("image_too_large_jpeg.gltf", textured_scene(data_uri("image/jpeg", big_jpeg)))
    write("image_unsupported.gltf", textured_scene(data_uri("image/gif", b"GIF89a\x01\x00\x01\x00\x00\x00\x00;")))
    d = textured_scene(data_uri("image/png", png_1x1()))
    d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 5
    write("texture_missing.gltf", d)
    d = textured_scene(data_uri("image/png", png_1x1()))
    d["textures"][0]["source"] = 3
    write("texture_image_missing.gltf", d)
    write("texcoord_missing.gltf", textured_scene(data_uri("image/png", png_1x1()), texcoords=False))
    d = textured_scene(data_uri("image/png", png_1x1()))
    d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 1
    write("texcoord1_missing.gltf", d)
    d = textured_scene(data_uri("image/png", png_1x1()))
    d["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = 0  # the VEC3 positions
    write("tangent_wrong_type.gltf", d)

    # EXT_mesh_gpu_instancing: attributes of different lengths; more instances than the scene allows.
    d, _ = triangle_scene()
    d["accessors"].append({"bufferView": 0, "componentType": 5126, "count": 2, "type": "VEC3"})
    d["extensionsUsed"] = ["EXT_mesh_gpu_instancing"]
    d["nodes"][0]["extensions"] = {"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": 0, "SCALE": 2}}}
    write("instancing_count_mismatch.gltf", d)
    d, _ = triangle_scene()
    d["accessors"].append({"componentType": 5126, "count": 5000000, "type": "VEC3",  # zeros but for element 0
                           "sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5123},
                                      "values": {"bufferView": 0}}})
    d["extensionsUsed"] = ["EXT_mesh_gpu_instancing"]
    d["nodes"][0]["extensions"] = {"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": 2}}}
    write("instancing_too_many.gltf", d)

    # 6144 x 6144 texels: 144 MiB as RGBA8, more than lavapipe's 128 MiB storage buffers; a texel buffer holds it
    # (not a bad scene: tests/robustness/CMakeLists.txt renders it).
    with open(os.path.join(HERE, "texture_144mib.png"), "wb") as f:
        f.write(png_black(6144, 6144))
    write("texture_144mib.gltf", textured_scene("texture_144mib.png"))

    # GLB: a valid header promising more bytes than the file has.
    json_chunk = json.dumps(triangle_scene(uri="x")[0]).encode()
    glb = struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(json_chunk) + 1000) + struct.pack("<II", len(json_chunk), 0x4E4F534A) + json_chunk
    with open(os.path.join(HERE, "truncated.glb"), "wb") as f:
        f.write(glb[: len(glb) - 10])
    with open(os.path.join(HERE, "empty_file.gltf"), "wb") as f:
        pass

    # Hostile nesting: 30,000 arrays inside `extras` overflowed the stack of a recursive parser (60 KB of text).
    d = copy.deepcopy(doc)
    d["extras"] = "NESTED"
    deep_text = json.dumps(d).replace('"NESTED"', "[" * 30000 + "]" * 30000)
    write("deep_nesting.gltf", deep_text)
    deep_doc, deep_bin = triangle_scene()
    del deep_doc["buffers"][0]["uri"]  # the BIN chunk holds it: the file is whole but for its nesting
    deep_chunk = json.dumps(deep_doc).replace('"asset"', '"extras": ' + "[" * 30000 + "]" * 30000 + ', "asset"', 1).encode()
    deep_chunk += b" " * (-len(deep_chunk) % 4)
    deep_bin += b"\0" * (-len(deep_bin) % 4)
    with open(os.path.join(HERE, "deep_nesting.glb"), "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(deep_chunk) + 8 + len(deep_bin)) +
                struct.pack("<II", len(deep_chunk), 0x4E4F534A) + deep_chunk +
                struct.pack("<II", len(deep_bin), 0x004E4942) + deep_bin)

    # Images whose headers declare 100,000 x 50,000 texels (56 GiB as float RGB) and hold no pixels: an environment map
    # (OpenEXR and Radiance .hdr) and an EXR given to compare or resume. Refused from the header, before any allocation.
    with open(os.path.join(HERE, "image_too_large.exr"), "wb") as f:
        f.write(exr_header(100000, 50000))
    with open(os.path.join(HERE, "image_too_large.hdr"), "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 50000 +X 100000\n")


def exr_header(width, height):
    """An OpenEXR scanline header (R, G, B as FLOAT, no compression) for width x height pixels, and nothing after it."""
    def attribute(name, kind, value):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(value)) + value
    channels = b"".join(c + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in (b"B", b"G", b"R")) + b"\0"
    window = struct.pack("<iiii", 0, 0, width - 1, height - 1)
    return (b"\x76\x2f\x31\x01" + struct.pack("<i", 2) +
            attribute("channels", "chlist", channels) + attribute("compression", "compression", b"\0") +
            attribute("dataWindow", "box2i", window) + attribute("displayWindow", "box2i", window) +
            attribute("lineOrder", "lineOrder", b"\0") + attribute("pixelAspectRatio", "float", struct.pack("<f", 1)) +
            attribute("screenWindowCenter", "v2f", struct.pack("<ff", 0, 0)) +
            attribute("screenWindowWidth", "float", struct.pack("<f", 1)) + b"\0")


if __name__ == "__main__":
    main()
