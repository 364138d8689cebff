// Stage "scan_ray_bins" (RAY_SORT_BLOCKS workgroups), the second pass of the keys' prefix sum: where each key's rays
// start in the sorted order (its block's start, the sum of sum_ray_bins' totals of the blocks before it, plus an
// exclusive scan within the block), and the counts set back to zero for the next depth's binning.
// Reads and writes: the ray-sort buffer's counts and offsets; reads its block sums.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/core/ray_order.glsl"

layout(local_size_x = RAY_SORT_SCAN_LANES) in;

shared uint lane_starts[RAY_SORT_SCAN_LANES];

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint first = gl_WorkGroupID.x * RAY_SORT_BLOCK_BINS + lane * RAY_SORT_BINS_PER_LANE;
    uint counts[RAY_SORT_BINS_PER_LANE];
    uint sum = 0u;
    for (uint k = 0u; k < RAY_SORT_BINS_PER_LANE; ++k) {
        counts[k] = ray_sort_words[RAY_SORT_COUNTS + first + k];
        sum += counts[k];
    }
    lane_starts[lane] = sum;
    barrier();
    if (lane == 0u) {  // one lane's loops: on lavapipe a tree of barriers costs more (see sum_ray_bins)
        uint run = 0u;
        for (uint b = 0u; b < gl_WorkGroupID.x; ++b) run += ray_sort_words[RAY_SORT_BLOCK_SUMS + b];
        for (uint j = 0u; j < RAY_SORT_SCAN_LANES; ++j) {
            uint lane_sum = lane_starts[j];
            lane_starts[j] = run;
            run += lane_sum;
        }
    }
    barrier();
    uint run = lane_starts[lane];
    for (uint k = 0u; k < RAY_SORT_BINS_PER_LANE; ++k) {
        ray_sort_words[RAY_SORT_OFFSETS + first + k] = run;
        ray_sort_words[RAY_SORT_COUNTS + first + k] = 0u;
        run += counts[k];
    }
}
