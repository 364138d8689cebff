// Buffer layouts, binding numbers and constants shared by the GLSL stages and the C++ host: the one place
// where a struct crossing the host/device boundary is defined (tests/unit/test_layout.cpp checks offsets).
//
// Rules that keep GLSL std430 and C++ in agreement without padding surprises:
// - structs hold only 32-bit scalars (float, uint, int) and vec4, with every vec4 before any scalar;
// - no vec3 in a buffer (std430 aligns it to 16 bytes);
// - fields are named for what they hold.
#ifndef FREDHOLM_SHARED_LAYOUT_H
#define FREDHOLM_SHARED_LAYOUT_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace fh::gpu {
using uint = std::uint32_t;
using vec4 = glm::vec4;
#define FH_CONST inline constexpr
#else
#define FH_CONST const
#endif

// ---- Dispatch shape -------------------------------------------------------------------------------------
FH_CONST uint WORKGROUP_SIZE = 64u;  // lavapipe: 8-lane subgroups, 64..256 per group measured best

// ---- Descriptor bindings (set 0, storage buffers but for the *_UNIFORM ones, shared by every stage) --------
FH_CONST uint BINDING_PARAMS = 0u;          // FrameParams, one element
FH_CONST uint BINDING_BVH_NODES = 1u;       // BvhPairNode[], depth-first, root at 0
FH_CONST uint BINDING_TRI_POSITIONS = 2u;   // TrianglePositions[], in BVH leaf order
FH_CONST uint BINDING_TRI_SHADING = 3u;     // TriangleShading[], same order
FH_CONST uint BINDING_MATERIALS = 4u;       // Material[]
FH_CONST uint BINDING_EMITTERS = 5u;        // Emitter[] (alias table over emissive triangles and punctual lights)
FH_CONST uint BINDING_COUNTERS = 6u;        // QueueCounters, one element (also the indirect-dispatch source)
FH_CONST uint BINDING_PATHS = 7u;           // PathState[wave capacity]
FH_CONST uint BINDING_RAYS = 8u;            // RayItem[2 * wave capacity]: two queues, by depth parity
FH_CONST uint BINDING_HITS = 9u;            // HitItem[wave capacity], aligned with the current ray queue
FH_CONST uint BINDING_SHADOW_RAYS = 10u;    // ShadowRayItem[wave capacity]
FH_CONST uint BINDING_FILM = 11u;           // FilmPixel[width * height]
// The first UNIFORM_BUFFER_BYTES of the scene buffers (bindings 1-5) again, as uniform buffers: lavapipe
// reads a uniform buffer with one unrolled gather per word, a storage buffer with a per-lane loop of
// branches and bounds checks (several times slower). The stages read them when every array fits.
FH_CONST uint BINDING_BVH_NODES_UNIFORM = 12u;
FH_CONST uint BINDING_TRI_POSITIONS_UNIFORM = 13u;
FH_CONST uint BINDING_TRI_SHADING_UNIFORM = 14u;
FH_CONST uint BINDING_MATERIALS_UNIFORM = 15u;
FH_CONST uint BINDING_EMITTERS_UNIFORM = 16u;
FH_CONST uint BINDING_GGX_ALBEDO_UNIFORM = 17u;  // the GGX albedo table (shaders/lib/ggx_albedo_table.glsl)
FH_CONST uint BINDING_PUNCTUAL_LIGHTS = 18u;    // PunctualLight[] (KHR_lights_punctual), read by NEE only
FH_CONST uint BINDING_COUNT = 19u;
FH_CONST uint UNIFORM_BUFFER_BYTES = 65536u;  // declared size of each; Vulkan guarantees only 16 KiB of
                                              // maxUniformBufferRange, so fits_uniform_buffers (pack.h) checks

// ---- Specialization constants (constant_id) -------------------------------------------------------------
FH_CONST uint SPEC_SCENE_IN_UNIFORM_BUFFERS = 0u;  // bool: every scene array fits its uniform binding
FH_CONST uint SPEC_HAS_PUNCTUAL_LIGHTS = 1u;       // bool: the scene has point/spot/directional lights
FH_CONST uint SPEC_DISABLED_TECHNIQUES = 2u;       // TECHNIQUE_* bits switched off (cost measurements only)

// ---- Robustness techniques (all on by default; `--disable-technique` turns one off to measure its cost and
// to show what goes wrong without it). README "Numerical stability" has the table.
FH_CONST uint TECHNIQUE_WATERTIGHT = 1u;        // Woop et al. 2013 triangle test (off: Moller-Trumbore 1997)
FH_CONST uint TECHNIQUE_CONSERVATIVE_BOX = 2u;  // padded slab test without 0 x inf (off: plain slab test)
FH_CONST uint TECHNIQUE_ERROR_OFFSETS = 4u;     // error-bound ray origins (off: fixed epsilon along the normal)
FH_CONST uint TECHNIQUE_FINITE_GUARD = 8u;      // non-finite samples dropped before the film (off: added)
FH_CONST uint TECHNIQUE_COMPENSATED_FILM = 16u; // Kahan-compensated film sums (off: plain float sums)
FH_CONST uint TECHNIQUE_TIE_BREAK = 32u;        // equal-t hits resolved by scene triangle index (off: visit order)
FH_CONST uint TECHNIQUE_REBASE = 64u;           // host: render space centred on the scene (off: world space)

// ---- Constants -----------------------------------------------------------------------------------------
FH_CONST uint INVALID_INDEX = 0xffffffffu;
FH_CONST uint CAMERA_PERSPECTIVE = 0u;
FH_CONST uint CAMERA_ORTHOGRAPHIC = 1u;
FH_CONST uint FILTER_BOX = 0u;             // one pixel wide
FH_CONST uint FILTER_GAUSSIAN = 1u;        // truncated Gaussian, importance sampled (weight 1)
FH_CONST uint MATERIAL_DOUBLE_SIDED = 1u;  // Material.flags
FH_CONST uint TRIANGLE_HAS_NORMALS = 1u;   // TriangleShading.flags: vertex normals present
FH_CONST uint RENDER_NEE = 1u;             // FrameParams.flags: next-event estimation
FH_CONST uint RENDER_MIS = 2u;             // combine NEE and BSDF sampling by MIS (else NEE only)
FH_CONST uint RENDER_RR = 4u;              // Russian roulette
FH_CONST uint BVH_LEAF_COUNT_BITS = 16u;   // BvhNode.count_and_axis: low bits count, high bits axis
FH_CONST uint PUNCTUAL_LIGHT_BIT = 0x80000000u;  // Emitter.light: set = PunctualLight index, clear = triangle
FH_CONST uint LIGHT_POINT = 0u;            // PunctualLight.type
FH_CONST uint LIGHT_SPOT = 1u;
FH_CONST uint LIGHT_DIRECTIONAL = 2u;

FH_CONST uint UNIFORM_NODE_CAPACITY = UNIFORM_BUFFER_BYTES / 64u;      // BvhPairNode
FH_CONST uint UNIFORM_TRIANGLE_CAPACITY = UNIFORM_BUFFER_BYTES / 48u;  // TrianglePositions, TriangleShading
FH_CONST uint UNIFORM_MATERIAL_CAPACITY = UNIFORM_BUFFER_BYTES / 80u;  // Material
FH_CONST uint UNIFORM_EMITTER_CAPACITY = UNIFORM_BUFFER_BYTES / 16u;   // Emitter

// ---- Scene ---------------------------------------------------------------------------------------------
// One node of the linear BVH (pbrt-v4 LinearBVHNode, 32 bytes). Interior nodes: first child is the next
// node, `child_or_first` is the second child; leaves: `child_or_first` is the first triangle.
struct BvhNode {
    float min_x, min_y, min_z;
    uint child_or_first;
    float max_x, max_y, max_z;
    uint count_and_axis;  // triangle count (0 = interior) | split axis << BVH_LEAF_COUNT_BITS
};

// What the GPU traverses: one node per interior node of the BVH above, holding the bounds of both children,
// so one visit tests two boxes and descends into the nearer (Aila & Laine 2009, "Understanding the
// Efficiency of Ray Traversal on GPUs"). A child is another pair node (count 0, index = its BvhPairNode) or
// a leaf (index = first triangle, count triangles); index INVALID_INDEX: no child (a BVH that is one leaf).
struct BvhPairNode {
    float a_min_x, a_min_y, a_min_z;
    uint a_index;
    float a_max_x, a_max_y, a_max_z;
    uint a_count;
    float b_min_x, b_min_y, b_min_z;
    uint b_index;
    float b_max_x, b_max_y, b_max_z;
    uint b_count;
};

// World-space vertex positions of one triangle; only these are read during traversal (9 words). Padded to
// 48 bytes so that std140 (uniform buffers) and std430 give the same array stride.
struct TrianglePositions {
    float p0_x, p0_y, p0_z;
    float p1_x, p1_y, p1_z;
    float p2_x, p2_y, p2_z;
    uint source_index;  // the triangle's index in scene order: equal-t hits go to the lowest (BVH-independent)
    float pad1, pad2;
};

// What the shade stage needs of a hit triangle besides its positions.
struct TriangleShading {
    float n0_x, n0_y, n0_z;  // world-space vertex normals (valid when flags & TRIANGLE_HAS_NORMALS)
    float n1_x, n1_y, n1_z;
    float n2_x, n2_y, n2_z;
    uint material;
    uint flags;
    float light_pdf_area;  // probability of picking this triangle as a light / its area (0: not an emitter)
};

// glTF 2.0 metallic-roughness material, factors only (texture slots reserved: INVALID_INDEX for now).
struct Material {
    vec4 base_color;        // rgb linear, a = alpha (unused)
    vec4 emission;          // rgb radiance = emissiveFactor * emissiveStrength, a unused
    vec4 specular_color;    // KHR_materials_specular: rgb = specularColorFactor, a = specularFactor
    float metallic;
    float roughness;        // perceptual; alpha = roughness^2
    float ior;              // KHR_materials_ior (1.5 by default)
    uint flags;             // MATERIAL_DOUBLE_SIDED
    uint base_color_texture;
    uint metallic_roughness_texture;
    uint normal_texture;
    uint emissive_texture;
};

// One entry of the alias table over every light: emissive triangles and punctual lights (Walker 1977;
// Vose 1991).
struct Emitter {
    uint light;             // triangle index (TrianglePositions order), or PUNCTUAL_LIGHT_BIT | PunctualLight index
    float alias_threshold;  // keep this entry if u < threshold, else take `alias`
    uint alias;
    float pick_pdf;         // probability of picking this light (power / total power)
};

// A KHR_lights_punctual light placed in world space. Intensities are taken as the scene's radiometric units:
// point and spot lights give radiant intensity (radiance-units x m^2), directional lights irradiance.
struct PunctualLight {
    vec4 position;          // xyz (point, spot)
    vec4 direction;         // xyz: unit direction the light travels (spot axis; directional light)
    vec4 intensity;         // rgb = color * intensity
    uint type;              // LIGHT_POINT / LIGHT_SPOT / LIGHT_DIRECTIONAL
    float cos_inner;        // spot: full intensity inside this cone
    float cos_outer;        // spot: none outside this cone
    float pad;
};

// ---- Per-render parameters (uploaded once per render) ----------------------------------------------------
struct FrameParams {
    vec4 camera_origin;     // xyz world position
    vec4 camera_right;      // xyz: world right, scaled so that NDC x = 1 maps to it (at unit distance)
    vec4 camera_up;         // xyz: world up, scaled likewise for NDC y = 1
    vec4 camera_forward;    // xyz: world view direction (unit)
    vec4 scene_min;         // xyz: scene bounds (for offsets and diagnostics)
    vec4 scene_max;
    uint width;
    uint height;
    uint max_depth;         // segments after the camera; 0 = unlimited
    uint seed;
    uint camera_type;       // CAMERA_PERSPECTIVE / CAMERA_ORTHOGRAPHIC
    uint filter_type;       // FILTER_BOX / FILTER_GAUSSIAN
    float filter_radius;    // pixels (Gaussian: truncation radius; sigma = radius / 3)
    uint flags;             // RENDER_NEE | RENDER_MIS | RENDER_RR
    uint emitter_count;
    uint rr_start_depth;    // Russian roulette starts at this segment count
    uint wave_capacity;     // paths per wave = length of PathState, HitItem, ShadowRayItem; half of RayItem
    uint triangle_count;
};

// Push constants: what changes per wave and per depth.
struct StagePush {
    uint depth;             // segments traced so far (0 while tracing camera rays)
    uint pixel_begin;       // the wave covers pixels [pixel_begin, pixel_begin + pixel_count)
    uint pixel_count;
    uint sample_begin;      // and sample indices [sample_begin, sample_begin + sample_count)
    uint sample_count;
    uint pad0, pad1, pad2;
};

// ---- Wavefront state -------------------------------------------------------------------------------------
struct DispatchArgs {
    uint x, y, z;
};

// Queue lengths, indirect dispatch sizes and device-side diagnostic counters.
struct QueueCounters {
    uint ray_count[2];          // rays in queue [depth & 1]
    uint shadow_count;          // shadow rays pushed by the current shade
    uint shadow_count_active;   // shadow rays the current connect consumes
    DispatchArgs extend_args;   // indirect dispatch for extend and shade of the next depth
    DispatchArgs connect_args;  // indirect dispatch for connect
    // Diagnostics for the current wave (zeroed by generate, read by the host after each wave).
    uint nonfinite_samples;     // samples whose radiance was NaN/Inf (counted before the guard)
    uint escaped_rays;          // extension rays that left the scene
    uint traced_rays;           // closest-hit rays traced
    uint traced_shadow_rays;    // shadow rays traced
};

// Per-path state, 8 words; index = path id within the wave.
struct PathState {
    float throughput_r, throughput_g, throughput_b;
    float bsdf_pdf;             // solid-angle pdf of the last sampled direction (0: camera or delta)
    float radiance_r, radiance_g, radiance_b;
    uint rng;
};

// A ray waiting for its closest hit.
struct RayItem {
    float origin_x, origin_y, origin_z;
    uint path;
    float dir_x, dir_y, dir_z;
    uint origin_triangle;       // the triangle it leaves (INVALID_INDEX: camera ray); see traverse.glsl
};

// Result of the extend stage for the ray at the same queue index.
struct HitItem {
    float t;
    uint triangle;              // INVALID_INDEX: the ray escaped
    float b1, b2;               // barycentrics of p1 and p2
};

// A shadow ray and the contribution it carries if unoccluded (next-event estimation).
struct ShadowRayItem {
    float origin_x, origin_y, origin_z;
    uint path;
    float dir_x, dir_y, dir_z;
    float t_max;
    float contrib_r, contrib_g, contrib_b;
    uint origin_triangle;       // the triangle it leaves
};

// Accumulated film pixel: Kahan-compensated sum of sample radiance (Kahan 1965).
struct FilmPixel {
    float sum_r, sum_g, sum_b;
    float sample_count;
    float comp_r, comp_g, comp_b;
    float pad;
};

#ifdef __cplusplus
}  // namespace fh::gpu
#endif
#undef FH_CONST
#endif
