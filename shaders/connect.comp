// Stage "connect": visibility of every shadow ray pushed by shade; unoccluded ones add their light
// contribution to their path. Reads: shadow_rays, counters.shadow_count_active, BVH (with EFFECT_MOTION_BLUR the
// path's time: a shadow ray is traced at its path's time). Writes: paths[].radiance (advance counts the traced rays).
// A path pushes at most one shadow ray per depth, so the read-modify-write needs no atomics, and its read can go
// through the texel view (the radiance was written by earlier dispatches; this one writes it only after reading).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/geometry/traverse.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= counters.shadow_count_active) return;
    ShadowRayItem s = load_shadow_ray(i);
    // A key other than extend's for the same path state: the shadow ray's alpha decisions are its own.
    uint alpha_seed = effect_on(EFFECT_ALPHA) ? pcg_hash(load_path_state(s.path).rng ^ 0x5ad0e11fu) : 0u;
    TraceHit hit = trace_ray(vec3(s.origin_x, s.origin_y, s.origin_z), vec3(s.dir_x, s.dir_y, s.dir_z), s.t_max, true,
                             s.origin_triangle, alpha_seed, load_path_time(s.path));
    if (hit.triangle != INVALID_INDEX) return;
    PathState state = load_path_state(s.path);
    state.radiance_r += s.contrib_r;
    state.radiance_g += s.contrib_g;
    state.radiance_b += s.contrib_b;
    store_path_radiance(s.path, state);  // one uvec4 store: the radiance and the rng as it was
}
