// Vertex merging (`--integrator vcm`): the hash grid over a wave's stored light vertices (BINDING_MERGE_GRID), built
// after the light subpaths by merge_count, merge_scan, merge_scatter and merge_sort, and searched by merge.comp.
// Cells are cubes of twice the merging radius, so the sphere of that radius about a point meets at most the 2 x 2 x 2
// cells nearest it. A cell's coordinates are hashed into FrameParams.merge_grid_cells buckets (cf. SmallVCM's
// HashGrid); distinct cells that share a bucket only cost a distance test each. The grid's words: the buckets' counts,
// then their first entries, then the vertices' slots (path x light_vertex_slots + k) bucket by bucket, each bucket's
// in ascending order (merge_sort), so a camera vertex sums its merges in one order every run.
#ifndef FH_VERTEX_MERGING_GLSL
#define FH_VERTEX_MERGING_GLSL

float merge_cell_size() { return 2.0f * push.merge_radius; }

// The cell coordinates of a point, from cell units (position / cell size); clamped so that a far point stays an int.
ivec3 merge_cell_of(vec3 cell_units) { return ivec3(floor(clamp(cell_units, vec3(-1.0e9f), vec3(1.0e9f)))); }

uint merge_bucket(ivec3 cell) {
    uvec3 c = uvec3(cell);
    return (c.x * 73856093u ^ c.y * 19349663u ^ c.z * 83492791u) & (params.merge_grid_cells - 1u);
}

uint merge_count_word(uint bucket) { return bucket; }
uint merge_start_word(uint bucket) { return params.merge_grid_cells + bucket; }
uint merge_entry_word(uint entry) { return 2u * params.merge_grid_cells + entry; }

// The wave's light-vertex slots, and whether a slot holds a vertex stored this wave.
uint merge_slot_count() { return push.pixel_count * push.sample_count * params.light_vertex_slots; }
bool merge_slot_stored(uint slot) {
    uint path = slot / params.light_vertex_slots;
    return slot % params.light_vertex_slots < path_mis[path].light_vertices;
}

uint merge_bucket_of_slot(uint slot) {
    return merge_bucket(merge_cell_of(merge_points[slot].xyz / merge_cell_size()));
}
#endif
