// Stage "merge_scatter" (`--integrator vcm`): each stored light vertex's slot written into its bucket's range, at a
// place taken by an atomic on the bucket's count (merge_scan left it at zero); merge_sort then orders each range.
// Reads: merge_points, path_mis, the grid's starts. Writes: the grid's counts and entries.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/integrator/vertex_merging.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

void main() {
    uint slot = gl_GlobalInvocationID.x;
    if (slot >= merge_slot_count() || !merge_slot_stored(slot)) return;
    uint bucket = merge_bucket_of_slot(slot);
    uint place = atomicAdd(merge_grid_words[merge_count_word(bucket)], 1u);
    merge_grid_words[merge_entry_word(merge_grid_words[merge_start_word(bucket)] + place)] = slot;
}
