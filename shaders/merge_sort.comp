// Stage "merge_sort" (`--integrator vcm`): each bucket's entries in ascending slot order (an insertion sort: buckets
// hold a few vertices), so that where merge_scatter's atomics put them does not change the sums merge.comp makes.
// Reads and writes: the grid's entries (reads its counts and starts).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/integrator/vertex_merging.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

void main() {
    uint bucket = gl_GlobalInvocationID.x;
    if (bucket >= params.merge_grid_cells) return;
    uint first = merge_grid_words[merge_start_word(bucket)];
    uint count = merge_grid_words[merge_count_word(bucket)];
    for (uint i = 1u; i < count; ++i) {
        uint slot = merge_grid_words[merge_entry_word(first + i)];
        uint j = i;
        for (; j > 0u; --j) {
            uint before = merge_grid_words[merge_entry_word(first + j - 1u)];
            if (before <= slot) break;
            merge_grid_words[merge_entry_word(first + j)] = before;
        }
        merge_grid_words[merge_entry_word(first + j)] = slot;
    }
}
