// Stage "sum_ray_bins" (RAY_SORT_BLOCKS workgroups), the first pass of the keys' prefix sum: each block's total count,
// for scan_ray_bins to start its block at.
// Reads: the ray-sort buffer's counts. Writes: its block sums.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/core/ray_order.glsl"

layout(local_size_x = RAY_SORT_SCAN_LANES) in;

shared uint lane_sums[RAY_SORT_SCAN_LANES];

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint first = gl_WorkGroupID.x * RAY_SORT_BLOCK_BINS + lane * RAY_SORT_BINS_PER_LANE;
    uint sum = 0u;
    for (uint k = 0u; k < RAY_SORT_BINS_PER_LANE; ++k) sum += ray_sort_words[RAY_SORT_COUNTS + first + k];
    lane_sums[lane] = sum;
    barrier();
    // One lane's loop. A first version summed with a shared atomic per lane here and scanned with a tree of 14 barriers
    // in scan_ray_bins: on lavapipe the two stages took 1.3 to 1.6x as long (tests/bench/RESULTS.md "Ray order").
    if (lane == 0u) {
        uint total = 0u;
        for (uint j = 0u; j < RAY_SORT_SCAN_LANES; ++j) total += lane_sums[j];
        ray_sort_words[RAY_SORT_BLOCK_SUMS + gl_WorkGroupID.x] = total;
    }
}
