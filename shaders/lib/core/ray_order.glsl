// The order extend takes the ray queue in (layout.h RAY_ORDER_*): a counting sort of the queue by a key of each ray's
// direction and origin, binned by shade (bin_ray as it pushes) or bin_rays, then sum_ray_bins, scan_ray_bins and
// scatter_rays before extend. Only the order in which the lanes pick rays changes: each ray's hit is written at its
// own queue index, so the images keep their bits.
#ifndef FH_RAY_ORDER_GLSL
#define FH_RAY_ORDER_GLSL

// Set where the ray sort's stages are built (StageOptions::sort_rays): without it shade compiles no binning and extend
// no look-up of the sorted order, which lavapipe would otherwise run (masked) for every ray.
layout(constant_id = SPEC_SORT_RAYS) const bool ray_sort_built = false;

// Queued ray i's words in the per-ray arrays of the ray-sort buffer (layout.h RAY_SORT_FIXED_WORDS on).
uint ray_sort_key_word(uint i) { return RAY_SORT_FIXED_WORDS + i; }
uint ray_sort_rank_word(uint i) { return RAY_SORT_FIXED_WORDS + params.wave_capacity + i; }
uint ray_sort_order_word(uint i) { return RAY_SORT_FIXED_WORDS + 2u * params.wave_capacity + i; }

// Spreads the low RAY_SORT_ORIGIN_BITS bits of v to every third bit (Morton order of the origin cells).
uint spread_to_every_third_bit(uint v) {
    uint spread = 0u;
    for (uint bit = 0u; bit < RAY_SORT_ORIGIN_BITS; ++bit) spread |= ((v >> bit) & 1u) << (3u * bit);
    return spread;
}

// The sort key: the direction's cell in an octahedral map (8 x 8 cells of about equal solid angle) above the origin's
// cell in the scene's box (8 x 8 x 8, Morton order). Sorted by direction first: lanes whose rays point apart take
// different children at the root already; the origin then keeps the rays of one direction cell near each other. Every
// key is below RAY_SORT_BINS whatever the input (a non-finite value lands in some cell: the masks keep it in range).
uint make_ray_sort_key(vec3 origin, vec3 dir) {
    const float cells = float(1u << RAY_SORT_DIRECTION_BITS);
    const uint cell_mask = (1u << RAY_SORT_DIRECTION_BITS) - 1u;
    vec2 p = dir.xy / max(abs(dir.x) + abs(dir.y) + abs(dir.z), 1e-30f);
    if (dir.z < 0.0f) p = (1.0f - abs(p.yx)) * vec2(p.x >= 0.0f ? 1.0f : -1.0f, p.y >= 0.0f ? 1.0f : -1.0f);
    uvec2 d = uvec2(clamp((p * 0.5f + 0.5f) * cells, vec2(0.0f), vec2(cells - 1.0f))) & cell_mask;
    const float origin_cells = float(1u << RAY_SORT_ORIGIN_BITS);
    const uint origin_mask = (1u << RAY_SORT_ORIGIN_BITS) - 1u;
    vec3 extent = max(params.scene_max.xyz - params.scene_min.xyz, vec3(1e-30f));
    vec3 u = clamp((origin - params.scene_min.xyz) / extent * origin_cells, vec3(0.0f), vec3(origin_cells - 1.0f));
    uvec3 c = uvec3(u) & origin_mask;
    uint morton = spread_to_every_third_bit(c.x) | (spread_to_every_third_bit(c.y) << 1) |
                  (spread_to_every_third_bit(c.z) << 2);
    uint direction = (d.y << RAY_SORT_DIRECTION_BITS) | d.x;
    return (direction << (3u * RAY_SORT_ORIGIN_BITS)) | morton;
}

// Counts queued ray i under its key and keeps its rank among the rays of that key (bin_rays, or shade as it pushes).
void bin_ray(uint i, vec3 origin, vec3 dir) {
    uint key = make_ray_sort_key(origin, dir);
    ray_sort_words[ray_sort_key_word(i)] = key;
    ray_sort_words[ray_sort_rank_word(i)] = atomicAdd(ray_sort_words[RAY_SORT_COUNTS + key], 1u);
}

// The queue index of the i-th ray extend traces.
uint select_ray_index(uint i) {
    return ray_sort_built && push.ray_order == RAY_ORDER_SORTED ? ray_sort_words[ray_sort_order_word(i)] : i;
}

#endif
