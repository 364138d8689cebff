// Stage "scan_ray_bins" (one workgroup), the second of the ray sort: where each key's rays start in the sorted order
// (an exclusive prefix sum of the counts), and the counts set back to zero for the next depth's bin_rays.
// Reads and writes: the ray-sort buffer's counts and offsets.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/bindings.glsl"
#include "lib/ray_order.glsl"

const uint SCAN_LANES = 128u;  // the least maxComputeWorkGroupInvocations Vulkan guarantees
const uint BINS_PER_LANE = RAY_SORT_BINS / SCAN_LANES;
layout(local_size_x = SCAN_LANES) in;

shared uint lane_start[SCAN_LANES];

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint first = lane * BINS_PER_LANE;
    uint sum = 0u;
    for (uint k = 0u; k < BINS_PER_LANE; ++k) sum += ray_sort_words[RAY_SORT_COUNTS + first + k];
    lane_start[lane] = sum;
    barrier();
    if (lane == 0u) {  // 128 sums: one lane's loop costs less than a tree of barriers here
        uint run = 0u;
        for (uint j = 0u; j < SCAN_LANES; ++j) {
            uint count = lane_start[j];
            lane_start[j] = run;
            run += count;
        }
    }
    barrier();
    uint run = lane_start[lane];
    for (uint k = 0u; k < BINS_PER_LANE; ++k) {
        uint count = ray_sort_words[RAY_SORT_COUNTS + first + k];
        ray_sort_words[RAY_SORT_OFFSETS + first + k] = run;
        ray_sort_words[RAY_SORT_COUNTS + first + k] = 0u;
        run += count;
    }
}
