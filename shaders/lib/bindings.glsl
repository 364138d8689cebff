// Declares every storage buffer of the wavefront renderer (bindings from shared/layout.h) for the stages.
#ifndef FH_BINDINGS_GLSL
#define FH_BINDINGS_GLSL
#include "../shared/layout.h"

layout(std430, binding = BINDING_PARAMS) readonly buffer ParamsBuffer { FrameParams params; };
layout(std430, binding = BINDING_BVH_NODES) readonly buffer NodeBuffer { BvhPairNode nodes[]; };
layout(std430, binding = BINDING_TRI_POSITIONS) readonly buffer PositionBuffer { TrianglePositions tri_positions[]; };
layout(std430, binding = BINDING_TRI_SHADING) readonly buffer ShadingBuffer { TriangleShading tri_shading[]; };
layout(std430, binding = BINDING_MATERIALS) readonly buffer MaterialBuffer { Material materials[]; };
layout(std430, binding = BINDING_EMITTERS) readonly buffer EmitterBuffer { Emitter emitters[]; };
layout(std430, binding = BINDING_COUNTERS) coherent buffer CounterBuffer { QueueCounters counters; };
layout(std430, binding = BINDING_PATHS) buffer PathBuffer { PathState paths[]; };
layout(std430, binding = BINDING_RAYS) buffer RayBuffer { RayItem rays[]; };
layout(std430, binding = BINDING_HITS) buffer HitBuffer { HitItem hits[]; };
layout(std430, binding = BINDING_SHADOW_RAYS) buffer ShadowBuffer { ShadowRayItem shadow_rays[]; };
layout(std430, binding = BINDING_FILM) buffer FilmBuffer { FilmPixel film[]; };
layout(std430, binding = BINDING_PUNCTUAL_LIGHTS) readonly buffer PunctualLightBuffer { PunctualLight punctual_lights[]; };
layout(std430, binding = BINDING_INSTANCES) readonly buffer InstanceBuffer { Instance instances[]; };
layout(std430, binding = BINDING_MATERIAL_LAYERS) readonly buffer MaterialLayerBuffer { MaterialLayers material_layers[]; };
layout(std430, binding = BINDING_PATH_MEDIA) buffer PathMediaBuffer { uint path_media[]; };
layout(std430, binding = BINDING_PATH_SPECTRA) buffer PathSpectrumBuffer { PathSpectrum path_spectra[]; };
layout(std430, binding = BINDING_GLASS_ALBEDO) readonly buffer GlassAlbedoBuffer { float glass_albedo_words[]; };

layout(std140, binding = BINDING_BVH_NODES_UNIFORM) uniform NodeUniforms {
    BvhPairNode uniform_nodes[UNIFORM_NODE_CAPACITY];
};
layout(std140, binding = BINDING_TRI_POSITIONS_UNIFORM) uniform PositionUniforms {
    TrianglePositions uniform_tri_positions[UNIFORM_TRIANGLE_CAPACITY];
};
layout(std140, binding = BINDING_TRI_SHADING_UNIFORM) uniform ShadingUniforms {
    TriangleShading uniform_tri_shading[UNIFORM_TRIANGLE_CAPACITY];
};
layout(std140, binding = BINDING_MATERIALS_UNIFORM) uniform MaterialUniforms {
    Material uniform_materials[UNIFORM_MATERIAL_CAPACITY];
};
layout(std140, binding = BINDING_EMITTERS_UNIFORM) uniform EmitterUniforms { Emitter uniform_emitters[UNIFORM_EMITTER_CAPACITY]; };
// Set by the host when every scene array lies whole in its uniform binding; the branches below are then
// resolved when the pipeline is compiled.
layout(constant_id = SPEC_SCENE_IN_UNIFORM_BUFFERS) const bool scene_in_uniform_buffers = false;
// Set by the host for a two-level BVH (meshes drawn by several nodes); without it the instance code is not
// compiled into traversal or shading.
layout(constant_id = SPEC_HAS_INSTANCES) const bool scene_has_instances = false;

layout(binding = BINDING_BVH_NODE_TEXELS) uniform usamplerBuffer node_texels;

BvhPairNode load_bvh_node(uint index) {
    if (scene_in_uniform_buffers) return uniform_nodes[index];
    int first = int(4u * index);
    uvec4 w0 = texelFetch(node_texels, first);
    uvec4 w1 = texelFetch(node_texels, first + 1);
    uvec4 w2 = texelFetch(node_texels, first + 2);
    uvec4 w3 = texelFetch(node_texels, first + 3);
    BvhPairNode n;
    n.a_min_x = uintBitsToFloat(w0.x);
    n.a_min_y = uintBitsToFloat(w0.y);
    n.a_min_z = uintBitsToFloat(w0.z);
    n.a_index = w0.w;
    n.a_max_x = uintBitsToFloat(w1.x);
    n.a_max_y = uintBitsToFloat(w1.y);
    n.a_max_z = uintBitsToFloat(w1.z);
    n.a_count = w1.w;
    n.b_min_x = uintBitsToFloat(w2.x);
    n.b_min_y = uintBitsToFloat(w2.y);
    n.b_min_z = uintBitsToFloat(w2.z);
    n.b_index = w2.w;
    n.b_max_x = uintBitsToFloat(w3.x);
    n.b_max_y = uintBitsToFloat(w3.y);
    n.b_max_z = uintBitsToFloat(w3.z);
    n.b_count = w3.w;
    return n;
}

layout(binding = BINDING_TRI_POSITION_TEXELS) uniform usamplerBuffer tri_position_texels;

TrianglePositions load_triangle_positions(uint triangle) {
    if (scene_in_uniform_buffers) return uniform_tri_positions[triangle];
    int first = int(3u * triangle);
    uvec4 w0 = texelFetch(tri_position_texels, first);
    uvec4 w1 = texelFetch(tri_position_texels, first + 1);
    uvec4 w2 = texelFetch(tri_position_texels, first + 2);
    TrianglePositions t;
    t.p0_x = uintBitsToFloat(w0.x);
    t.p0_y = uintBitsToFloat(w0.y);
    t.p0_z = uintBitsToFloat(w0.z);
    t.p1_x = uintBitsToFloat(w0.w);
    t.p1_y = uintBitsToFloat(w1.x);
    t.p1_z = uintBitsToFloat(w1.y);
    t.p2_x = uintBitsToFloat(w1.z);
    t.p2_y = uintBitsToFloat(w1.w);
    t.p2_z = uintBitsToFloat(w2.x);
    t.source_index = w2.y;
    t.pad1 = 0.0f;
    t.pad2 = 0.0f;
    return t;
}

TriangleShading load_triangle_shading(uint triangle) {
    if (scene_in_uniform_buffers) return uniform_tri_shading[triangle];
    return tri_shading[triangle];
}

Material load_material(uint material) {
    if (scene_in_uniform_buffers) return uniform_materials[material];
    return materials[material];
}

Emitter load_emitter(uint entry) {
    if (scene_in_uniform_buffers) return uniform_emitters[entry];
    return emitters[entry];
}

#include "ggx_albedo_table.glsl"
#include "sheen_albedo_table.glsl"
#include "spectral_table.glsl"
// The BSDF's albedo tables: GGX's, then the sheen lobe's; then the spectral path's table (spectrum.glsl).
layout(std140, binding = BINDING_GGX_ALBEDO_UNIFORM) uniform GgxAlbedoTable {
    vec4 ggx_albedo_words[(GGX_ALBEDO_TABLE_SIZE + SHEEN_ALBEDO_TABLE_SIZE + SPECTRAL_TABLE_SIZE) / 4];
};
float ggx_albedo_entry(int i) { return ggx_albedo_words[i >> 2][i & 3]; }
float sheen_albedo_entry(int i) { return ggx_albedo_entry(GGX_ALBEDO_TABLE_SIZE + i); }
float glass_albedo_entry(int i) { return glass_albedo_words[i]; }  // glass_albedo_table.glsl's order
vec4 spectral_table_vec4(int i) { return ggx_albedo_words[(GGX_ALBEDO_TABLE_SIZE + SHEEN_ALBEDO_TABLE_SIZE) / 4 + i]; }

layout(push_constant) uniform PushBlock { StagePush push; };

vec3 load_triangle_vertex(uint triangle, uint corner) {
    TrianglePositions t = load_triangle_positions(triangle);
    if (corner == 0u) return vec3(t.p0_x, t.p0_y, t.p0_z);
    if (corner == 1u) return vec3(t.p1_x, t.p1_y, t.p1_z);
    return vec3(t.p2_x, t.p2_y, t.p2_z);
}

// Index of a ray in the queue of the given depth parity (two queues share one buffer).
uint ray_slot(uint parity, uint index) { return parity * params.wave_capacity + index; }

#endif
