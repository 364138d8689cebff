// Stage "scatter_rays", the last of the ray sort: each queued ray's place in key order, its key's start plus its rank
// (no atomics: one per ray costs as much as the rest of the sort on lavapipe). Within a key the order is that of
// bin_rays' atomics (not fixed), which changes no image: extend writes each ray's hit at its own queue index.
// Reads: the ray-sort buffer's keys, ranks and offsets, counters.ray_count. Writes: its order.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/core/ray_order.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= counters.ray_count[push.depth & 1u]) return;
    uint key = ray_sort_words[ray_sort_key_word(i)];
    ray_sort_words[ray_sort_order_word(ray_sort_words[RAY_SORT_OFFSETS + key] + ray_sort_words[ray_sort_rank_word(i)])] = i;
}
