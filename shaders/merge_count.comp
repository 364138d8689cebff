// Stage "merge_count" (`--integrator vcm`): each stored light vertex of the wave counted in its hash-grid bucket
// (lib/integrator/vertex_merging.glsl). The counts start at zero (the host clears them).
// Reads: merge_points, path_mis. Writes: the grid's counts.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/integrator/vertex_merging.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

void main() {
    uint slot = gl_GlobalInvocationID.x;
    if (slot >= merge_slot_count() || !merge_slot_stored(slot)) return;
    atomicAdd(merge_grid_words[merge_count_word(merge_bucket_of_slot(slot))], 1u);
}
