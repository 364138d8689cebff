// Stage "merge_scan" (`--integrator vcm`): where each hash-grid bucket's entries start (the exclusive prefix sum of the
// counts), and the counts back to zero for merge_scatter's places. One workgroup: each lane sums a run of buckets,
// the lanes' sums are scanned in shared memory, then each lane writes its run's starts.
// Reads and writes: the grid's counts and starts.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/integrator/vertex_merging.glsl"

const uint LANES = 128u;  // the least maxComputeWorkGroupInvocations Vulkan guarantees
layout(local_size_x = LANES) in;

shared uint lane_sums[LANES];

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint run = (params.merge_grid_cells + LANES - 1u) / LANES;
    uint first = min(lane * run, params.merge_grid_cells);
    uint last = min(first + run, params.merge_grid_cells);
    uint sum = 0u;
    for (uint b = first; b < last; ++b) sum += merge_grid_words[merge_count_word(b)];
    lane_sums[lane] = sum;
    barrier();
    if (lane == 0u) {
        uint total = 0u;
        for (uint l = 0u; l < LANES; ++l) {
            uint s = lane_sums[l];
            lane_sums[l] = total;
            total += s;
        }
    }
    barrier();
    uint start = lane_sums[lane];
    for (uint b = first; b < last; ++b) {
        uint count = merge_grid_words[merge_count_word(b)];
        merge_grid_words[merge_start_word(b)] = start;
        merge_grid_words[merge_count_word(b)] = 0u;
        start += count;
    }
}
