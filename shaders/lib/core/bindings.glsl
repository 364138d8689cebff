// Declares every storage buffer of the wavefront renderer (bindings from shared/layout.h) for the stages.
#ifndef FH_BINDINGS_GLSL
#define FH_BINDINGS_GLSL
#include "shared/layout.h"

// A uniform buffer: on lavapipe a storage-buffer word is loaded lane by lane even where every lane reads the same
// address, a uniform one once for all (tests/bench/RESULTS.md "Speed"). FrameParams has no arrays, so std140 lays it out as std430.
layout(std140, binding = BINDING_PARAMS) uniform ParamsBuffer { FrameParams params; };
layout(std430, binding = BINDING_COUNTERS) coherent buffer CounterBuffer { QueueCounters counters; };
layout(std430, binding = BINDING_PATHS) buffer PathBuffer { PathState paths[]; };
layout(std430, binding = BINDING_RAYS) buffer RayBuffer { RayItem rays[]; };
layout(std430, binding = BINDING_HITS) buffer HitBuffer { HitItem hits[]; };
layout(std430, binding = BINDING_SHADOW_RAYS) buffer ShadowBuffer { ShadowRayItem shadow_rays[]; };
layout(std430, binding = BINDING_FILM) buffer FilmBuffer { FilmPixel film[]; };
layout(std430, binding = BINDING_PATH_MEDIA) buffer PathMediaBuffer { uvec4 path_media[]; };
layout(std430, binding = BINDING_LIGHT_MEDIA) readonly buffer LightMediaBuffer { uvec4 light_media[]; };
layout(std430, binding = BINDING_PATH_SPECTRA) buffer PathSpectrumBuffer { PathSpectrum path_spectra[]; };
layout(std430, binding = BINDING_PATH_TIMES) buffer PathTimeBuffer { float path_times[]; };
layout(std430, binding = BINDING_GLASS_ALBEDO) readonly buffer GlassAlbedoBuffer { float glass_albedo_words[]; };
layout(std430, binding = BINDING_ANISOTROPIC_ALBEDO) readonly buffer AnisotropicAlbedoBuffer {
    float anisotropic_albedo_words[];
};
layout(std430, binding = BINDING_LIGHT_VERTICES) buffer LightVertexBuffer { LightVertex light_vertices[]; };
layout(std430, binding = BINDING_PATH_MIS) buffer PathMisBuffer { PathMis path_mis[]; };
layout(std430, binding = BINDING_MERGE_POINTS) buffer MergePointBuffer { vec4 merge_points[]; };
layout(std430, binding = BINDING_PATH_DVM) buffer PathDvmBuffer { float path_dvm[]; };
layout(std430, binding = BINDING_MERGE_GRID) buffer MergeGridBuffer { uint merge_grid_words[]; };
layout(std430, binding = BINDING_RAY_SORT) buffer RaySortBuffer { uint ray_sort_words[]; };  // lib/core/ray_order.glsl
layout(std430, binding = BINDING_PATH_LIGHT_POINTS) buffer PathLightPointBuffer { uvec4 path_light_points[]; };
// Two uvec4 per path (layout.h PathAov): stored a texel at a time, not word by word (lib/core/aov.glsl).
layout(std430, binding = BINDING_PATH_AOVS) buffer PathAovBuffer { uvec4 path_aov_words[]; };
layout(std430, binding = BINDING_AOV_FILM) buffer AovFilmBuffer { AovPixel aov_film[]; };
layout(std430, binding = BINDING_PIXEL_LIST) readonly buffer PixelListBuffer { uint pixel_list[]; };
layout(std430, binding = BINDING_PATH_WORK) buffer PathWorkBuffer { uint path_work[]; };
layout(std430, binding = BINDING_PIXEL_WORK) buffer PixelWorkBuffer { uint pixel_work[]; };
// The scene's read-only structs (layout.h TEXELS bindings): load_bvh_node, load_triangle_positions,
// load_triangle_shading, load_material, load_emitter, load_punctual_light, load_triangle_attributes, load_instance,
// load_material_layers, load_light_tree_node, written at build time from layout.h.
#include "generated/scene_texels.glsl"
// Set by the host for a two-level BVH (meshes drawn by several nodes); without it the instance code is not
// compiled into traversal or shading.
layout(constant_id = SPEC_HAS_INSTANCES) const bool scene_has_instances = false;
// Which integrator the stage serves (INTEGRATOR_*), fixed when it is compiled: shaders/CMakeLists.txt builds one SPIR-V
// per integrator for the stages that differ (FH_INTEGRATOR). A stage compiled once cannot name these.
#ifdef FH_INTEGRATOR
const uint integrator = FH_INTEGRATOR;
// Vertex connection and merging runs every stage of bidirectional path tracing, its weights with the merges counted.
const bool vcm = integrator == INTEGRATOR_VCM;
const bool bdpt = integrator == INTEGRATOR_BDPT || vcm;
#endif

#include "lib/tables/ggx_albedo_table.glsl"
#include "lib/tables/sheen_albedo_table.glsl"
#include "lib/tables/spectral_table.glsl"
// The BSDF's albedo tables: GGX's, then the sheen lobe's; then the spectral path's table (spectrum.glsl).
layout(std140, binding = BINDING_GGX_ALBEDO_UNIFORM) uniform GgxAlbedoTable {
    vec4 ggx_albedo_words[(GGX_ALBEDO_TABLE_SIZE + SHEEN_ALBEDO_TABLE_SIZE + SPECTRAL_TABLE_SIZE) / 4];
};
float ggx_albedo_entry(int i) { return ggx_albedo_words[i >> 2][i & 3]; }
float sheen_albedo_entry(int i) { return ggx_albedo_entry(GGX_ALBEDO_TABLE_SIZE + i); }
float glass_albedo_entry(int i) { return glass_albedo_words[i]; }  // glass_albedo_table.glsl's order
float ggx_anisotropic_albedo_entry(int i) { return anisotropic_albedo_words[i]; }  // ggx_anisotropic_albedo_table.glsl's
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
