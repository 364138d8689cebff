// Stage "extend": finds the closest hit of every ray in the current queue.
// Takes the queue in the order push.ray_order says (lib/core/ray_order.glsl): as queued, or sorted by bin_rays ..
// scatter_rays.
// Reads: rays[queue depth & 1], counters.ray_count, the sorted order, BVH nodes, triangle positions (with EFFECT_ALPHA also
// paths[].rng, materials and textures; with EFFECT_MOTION_BLUR the path's time and the instances' motion).
// Writes: hits[i] for ray i; with StagePush.count_escaped_rays counters.escaped_rays (advance counts the traced rays).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/core/queue.glsl"
#include "lib/geometry/traverse.glsl"
#include "lib/core/ray_order.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

void main() {
    uint parity = push.depth & 1u;
    if (gl_GlobalInvocationID.x >= counters.ray_count[parity]) return;
    uint i = select_ray_index(gl_GlobalInvocationID.x);  // the queue index of the ray this invocation traces
    RayItem ray = load_ray_item(ray_slot(parity, i));
    // Stochastic alpha keys on the path's RNG state, which differs for every path, sample and depth.
    uint alpha_seed = effect_on(EFFECT_ALPHA) ? pcg_hash(load_path_state(ray.path).rng ^ 0x0a1fa0e5u) : 0u;
    TraceHit hit = trace_ray(vec3(ray.origin_x, ray.origin_y, ray.origin_z), vec3(ray.dir_x, ray.dir_y, ray.dir_z),
                             uintBitsToFloat(0x7f800000u), false, ray.origin_triangle, alpha_seed,
                             load_path_time(ray.path));
    HitItem item;
    item.t = hit.t;
    item.triangle = hit.triangle;
    item.b1 = hit.b1;
    item.b2 = hit.b2;
    item.instance = hit.instance;
    item.pad0 = item.pad1 = item.pad2 = 0u;
    // Shade reads the instance only where the scene has instances: otherwise the first texel alone is stored.
    if (scene_has_instances)
        store_hit_item(i, item);
    else
        store_hit_head(i, item);
    // A render's shade and light_shade count the escaped rays with their queues' atomics (lib/core/queue.glsl).
    if (push.count_escaped_rays != 0u) COUNT_TRUE_IN_SUBGROUP(counters.escaped_rays, hit.triangle == INVALID_INDEX);
}
