#!/usr/bin/env python3
"""Writes the GLSL that reads structs from uniform texel buffers, and stores the wave's structs, from layout.h.

usage: make_texel_loaders.py LAYOUT_H OUT_GLSL

The scene's read-only arrays, and the wave's arrays for the stages that read what an earlier dispatch wrote, are
bound as RGBA32UI uniform texel buffers (layout.h, "Descriptor bindings"): on lavapipe a texel fetch is one gather
for all lanes, where a storage-buffer load instruction loops over the lanes with a bounds check. A struct of 4n words is n texels; its fields (vec4s first, then 32-bit scalars: layout.h's rules) are
the texels' words in order. This script turns each struct listed in TEXEL_STRUCTS into a sampler declaration and a
load function (each struct in STORE_STRUCTS into a uvec4 store function, each in STORAGE_LOAD_STRUCTS into a uvec4
load function from its storage buffer), so layout.h stays the one definition (a change there rebuilds the shaders through this file).
Standard library only.
"""
import re
import sys

# struct, load function, its parameter, binding constant, sampler name
TEXEL_STRUCTS = [
    ("BvhWideNode", "load_bvh_node", "index", "BINDING_BVH_NODES", "node_texels"),
    ("TrianglePositions", "load_triangle_positions", "triangle", "BINDING_TRI_POSITIONS", "tri_position_texels"),
    ("TriangleShading", "load_triangle_shading", "triangle", "BINDING_TRI_SHADING", "tri_shading_texels"),
    ("Material", "load_material", "material", "BINDING_MATERIALS", "material_texels"),
    ("Emitter", "load_emitter", "entry", "BINDING_EMITTERS", "emitter_texels"),
    ("PunctualLight", "load_punctual_light", "light", "BINDING_PUNCTUAL_LIGHTS", "punctual_light_texels"),
    ("LightTreeNode", "load_light_tree_node", "node", "BINDING_LIGHT_TREE", "light_tree_texels"),
    ("TriangleAttributes", "load_triangle_attributes", "triangle", "BINDING_TRI_ATTRIBUTES", "tri_attribute_texels"),
    ("Instance", "load_instance", "instance", "BINDING_INSTANCES", "instance_texels"),
    ("MaterialLayers", "load_material_layers", "material", "BINDING_MATERIAL_LAYERS", "material_layer_texels"),
    ("TextureSlot", "load_texture_slot", "slot", "BINDING_TEXTURE_SLOTS", "texture_slot_texels"),
    ("TextureImage", "load_texture_image", "image", "BINDING_TEXTURE_IMAGES", "texture_image_texels"),
    # The wave's arrays, read by the stages after the one that wrote them (layout.h BINDING_PATH_TEXELS ...).
    ("PathState", "load_path_state", "path", "BINDING_PATH_TEXELS", "path_texels"),
    ("RayItem", "load_ray_item", "slot", "BINDING_RAY_TEXELS", "ray_texels"),
    ("HitItem", "load_hit_item", "index", "BINDING_HIT_TEXELS", "hit_texels"),
    ("ShadowRayItem", "load_shadow_ray", "index", "BINDING_SHADOW_RAY_TEXELS", "shadow_ray_texels"),
]

# Stores of the wave's arrays: struct, store function, its index parameter, binding constant, the storage-buffer array
# lib/core/bindings.glsl declares, and which of the struct's texels the function stores (None: all). Each texel is one
# uvec4 store: on lavapipe every storage-buffer store instruction runs a loop over the 8 lanes, and one loop stores all
# the components of a vector, so a uvec4 takes one loop where four 32-bit words take four (tests/bench/RESULTS.md "Speed"). With
# FH_STRUCT_STORES (the stage `shade_struct_stores`, `--wide-stores off`, kept to measure this) the fields are stored
# one by one. Either way the memory holds the same bytes.
STORE_STRUCTS = [
    ("PathState", "store_path_state", "path", "BINDING_PATHS", "paths", None),
    ("PathState", "store_path_radiance", "path", "BINDING_PATHS", "paths", (1, 1)),  # radiance_r, _g, _b, rng
    ("RayItem", "store_ray_item", "slot", "BINDING_RAYS", "rays", None),
    ("ShadowRayItem", "store_shadow_ray", "index", "BINDING_SHADOW_RAYS", "shadow_rays", None),
    ("HitItem", "store_hit_item", "index", "BINDING_HITS", "hits", None),
    ("HitItem", "store_hit_head", "index", "BINDING_HITS", "hits", (0, 1)),  # t, triangle, b1, b2
    ("PathMis", "store_path_mis", "path", "BINDING_PATH_MIS", "path_mis", None),
    ("LightVertex", "store_light_vertex", "slot", "BINDING_LIGHT_VERTICES", "light_vertices", None),
]

# Loads from storage buffers a dispatch may also write (no texel view): struct, load function, its parameter, binding
# constant, the storage-buffer array. One uvec4 load per texel, one per-lane loop each on lavapipe (as for stores).
STORAGE_LOAD_STRUCTS = [
    ("PathMis", "load_path_mis", "path", "BINDING_PATH_MIS", "path_mis"),
    ("LightVertex", "load_light_vertex", "slot", "BINDING_LIGHT_VERTICES", "light_vertices"),
]


def struct_fields(source, name):
    match = re.search(r"struct %s \{(.*?)\n\};" % name, source, re.S)
    if not match:
        raise SystemExit(f"make_texel_loaders: no struct {name} in layout.h")
    fields = []
    for line in match.group(1).split("\n"):
        line = line.split("//")[0].strip()
        if not line:
            continue
        typed = re.fullmatch(r"(vec4|float|uint|int)\s+(.*);", line)
        if not typed:
            raise SystemExit(f"make_texel_loaders: {name}: cannot read '{line}' (only vec4, float, uint, int)")
        fields += [(typed.group(1), field.strip()) for field in typed.group(2).split(",")]
    return fields


def loader(source, struct, function, parameter, binding, sampler):
    fields = struct_fields(source, struct)
    words = sum(4 if kind == "vec4" else 1 for kind, _ in fields)
    if words % 4:
        raise SystemExit(f"make_texel_loaders: {struct} is {words} words, not whole texels")
    texels = words // 4
    lines = [f"layout(binding = {binding}) uniform usamplerBuffer {sampler};",
             f"{struct} {function}(uint {parameter}) {{",
             f"    int first = int({texels}u * {parameter});"]
    lines += [f"    uvec4 t{k} = texelFetch({sampler}, first + {k});" for k in range(texels)]
    lines.append(f"    {struct} v;")
    word = 0
    for kind, field in fields:
        if kind == "vec4":
            if word % 4:
                raise SystemExit(f"make_texel_loaders: {struct}.{field}: a vec4 after a scalar")
            lines.append(f"    v.{field} = uintBitsToFloat(t{word // 4});")
            word += 4
            continue
        lines.append(f"    v.{field} = {word_value(kind, word)};")
        word += 1
    lines += ["    return v;", "}"]
    return f"// {struct}: {texels} texels.\n" + "\n".join(lines) + "\n"


def word_value(kind, word):
    """A 32-bit field from word `word` of the texels t0, t1, ... a load function has read."""
    value = f"t{word // 4}.{'xyzw'[word % 4]}"
    return {"float": f"uintBitsToFloat({value})", "uint": value, "int": f"int({value})"}[kind]


def word_bits(kind, value):
    return {"float": f"floatBitsToUint({value})", "uint": value, "int": f"uint({value})"}[kind]


def storer(source, struct, function, parameter, binding, array, texel_range):
    fields = struct_fields(source, struct)
    if any(kind == "vec4" for kind, _ in fields):
        raise SystemExit(f"make_texel_loaders: {struct}: stores take 32-bit fields only")
    if len(fields) % 4:
        raise SystemExit(f"make_texel_loaders: {struct} is {len(fields)} words, not whole texels")
    texels = len(fields) // 4
    first, count = texel_range if texel_range else (0, texels)
    if first + count > texels:
        raise SystemExit(f"make_texel_loaders: {function}: texels {first} + {count} past {struct}'s {texels}")
    lines = ["#ifndef FH_STRUCT_STORES",
             f"void {function}(uint {parameter}, {struct} v) {{",
             f"    uint first = {texels}u * {parameter};"]
    for k in range(first, first + count):
        words = ", ".join(word_bits(kind, "v." + name) for kind, name in fields[4 * k:4 * k + 4])
        lines.append(f"    {array}_texels_out[first + {k}u] = uvec4({words});")
    lines += ["}", "#else"]
    if count == texels:
        lines.append(f"void {function}(uint {parameter}, {struct} v) {{ {array}[{parameter}] = v; }}")
    else:
        lines.append(f"void {function}(uint {parameter}, {struct} v) {{")
        lines += [f"    {array}[{parameter}].{name} = v.{name};" for _, name in fields[4 * first:4 * (first + count)]]
        lines.append("}")
    lines.append("#endif")
    what = "all" if count == texels else f"texel {first}" if count == 1 else f"texels {first} to {first + count - 1}"
    return (f"// {struct}, {what} of its {texels} texels: one uvec4 store each (or field by field, FH_STRUCT_STORES).\n"
            + "\n".join(lines) + "\n")


def storage_loader(source, struct, function, parameter, binding, array):
    fields = struct_fields(source, struct)
    if len(fields) % 4 or any(kind == "vec4" for kind, _ in fields):
        raise SystemExit(f"make_texel_loaders: {struct}: storage loads take whole texels of 32-bit fields")
    texels = len(fields) // 4
    lines = [f"layout(std430, binding = {binding}) readonly buffer {struct}TexelsIn {{ uvec4 {array}_texels_in[]; }};",
             f"{struct} {function}(uint {parameter}) {{",
             f"    uint first = {texels}u * {parameter};"]
    lines += [f"    uvec4 t{k} = {array}_texels_in[first + {k}u];" for k in range(texels)]
    lines.append(f"    {struct} v;")
    lines += [f"    v.{name} = {word_value(kind, word)};" for word, (kind, name) in enumerate(fields)]
    lines += ["    return v;", "}"]
    return f"// {struct}: {texels} uvec4 loads from its storage buffer.\n" + "\n".join(lines) + "\n"


def store_views(source):
    """One writeonly uvec4 view per storage buffer the store functions write (the struct arrays alias it)."""
    lines = ["#ifndef FH_STRUCT_STORES"]
    seen = set()
    for struct, _, _, binding, array, _ in STORE_STRUCTS:
        if binding not in seen:
            seen.add(binding)
            lines.append(f"layout(std430, binding = {binding}) writeonly buffer {struct}Texels {{ "
                         f"uvec4 {array}_texels_out[]; }};")
    lines.append("#endif")
    return "\n".join(lines) + "\n"


def main():
    if len(sys.argv) != 3:
        raise SystemExit("usage: make_texel_loaders.py LAYOUT_H OUT_GLSL")
    source = open(sys.argv[1]).read()
    parts = ["// GENERATED by shaders/shared/make_texel_loaders.py from shaders/shared/layout.h: do not edit.\n"
             "// The scene's read-only structs and the wave's arrays from RGBA32UI uniform texel buffers (see the script).\n"
             "#ifndef FH_SCENE_TEXELS_GLSL\n#define FH_SCENE_TEXELS_GLSL\n"]
    parts += [loader(source, *entry) for entry in TEXEL_STRUCTS]
    parts.append(store_views(source))
    parts += [storer(source, *entry) for entry in STORE_STRUCTS]
    parts += [storage_loader(source, *entry) for entry in STORAGE_LOAD_STRUCTS]
    parts.append("#endif\n")
    text = "\n".join(parts)
    with open(sys.argv[2], "w") as out:
        out.write(text)


if __name__ == "__main__":
    main()
