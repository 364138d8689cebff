// Stage "advance" (one invocation): queue bookkeeping between shade and connect, so the host never reads
// a counter back. Reads: counters. Writes: counters (indirect sizes for connect and the next extend/shade,
// the consumed ray queue emptied and counted as traced, the shadow queue handed to connect and, when connect
// follows, counted as traced). Counting here rather than with an atomic per SIMD group in extend and connect saves
// those stages the atomics on one cache line that both of lavapipe's threads write (tests/bench/RESULTS.md "Speed").
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"

layout(local_size_x = 1) in;

void main() {
    uint current = push.depth & 1u;
    uint next = current ^ 1u;
    counters.traced_rays += counters.ray_count[current];  // the queue extend has just traced
    counters.ray_count[current] = 0u;
    if (push.count_handed_shadow_rays != 0u) counters.traced_shadow_rays += counters.shadow_count;
    counters.extend_args.x = (counters.ray_count[next] + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    counters.shadow_count_active = counters.shadow_count;
    counters.connect_args.x = (counters.shadow_count + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    counters.shadow_count = 0u;
}
