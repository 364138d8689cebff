// Stage "advance" (one invocation): queue bookkeeping between shade and connect, so the host never reads
// a counter back. Reads: counters. Writes: counters (indirect sizes for connect and the next extend/shade,
// the consumed ray queue emptied, the shadow queue handed to connect).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/bindings.glsl"

layout(local_size_x = 1) in;

void main() {
    uint current = push.depth & 1u;
    uint next = current ^ 1u;
    counters.ray_count[current] = 0u;
    counters.extend_args.x = (counters.ray_count[next] + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    counters.shadow_count_active = counters.shadow_count;
    counters.connect_args.x = (counters.shadow_count + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    counters.shadow_count = 0u;
}
