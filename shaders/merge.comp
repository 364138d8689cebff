// Stage "merge" (`--integrator vcm`): vertex merging at each camera vertex just found (the queued ray's hit, after
// connect_subpaths and before shade moves the path on). Every light vertex of the wave within the merging radius r of
// it (the hash grid, lib/integrator/vertex_merging.glsl) is taken as light arriving at the camera vertex itself: the
// camera side's BSDF towards the light vertex's arriving direction, with the shading-normal correction light tracing
// has, times the light vertex's throughput, over pi r^2 and the wave's light subpaths (a density estimate: biased for
// r > 0, consistent as r shrinks with the sample index), weighted by MIS against every connection and every other merge
// of the same path (lib/integrator/bdpt.glsl weight_merge). Merges make paths of up to FrameParams.bdpt_depth segments.
// A path's merges are summed in the grid's order (each bucket's slots ascending) by one invocation: the same bits every
// run for the same wave.
// Reads: rays[queue depth & 1], hits, paths, path media, path_mis, path_dvm, light_vertices, merge_points, the grid,
// triangles, materials, textures, instances. Writes: paths[].radiance.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/core/queue.glsl"
#include "lib/core/effects.glsl"
#include "lib/integrator/camera_vertex.glsl"
#include "lib/integrator/vertex_merging.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

// Light vertices are merged in batches: first the next MERGE_BATCH within the radius are listed (cheap tests), then
// each listed one is weighed and added (BSDFs and pdfs). On 8 SIMD lanes the costly part then runs as often as the
// lane with the most merges needs, not once per grid entry any lane visits.
const uint MERGE_BATCH = 16u;

// Where the search over the 2 x 2 x 2 cells nearest y stands: the cell (0..8) and the next entry of its bucket.
struct MergeCursor {
    ivec3 corner;
    uint buckets[8];
    uint cell;
    uint entry, entry_end;
};

// The next cell whose bucket no earlier cell shares (distinct cells may hash to one bucket), or cell 8: done.
void open_next_cell(inout MergeCursor m) {
    for (++m.cell; m.cell < 8u; ++m.cell) {
        uint n = m.cell;
        m.buckets[n] = merge_bucket(m.corner + ivec3(n & 1u, (n >> 1u) & 1u, n >> 2u));
        bool seen = false;
        for (uint k = 0u; k < n; ++k) seen = seen || m.buckets[k] == m.buckets[n];
        if (seen) continue;
        m.entry = merge_grid_words[merge_start_word(m.buckets[n])];
        m.entry_end = m.entry + merge_grid_words[merge_count_word(m.buckets[n])];
        return;
    }
}

MergeCursor start_merge_search(vec3 p) {
    MergeCursor m;
    vec3 cell_units = p / merge_cell_size();
    m.corner = merge_cell_of(cell_units) - ivec3(lessThan(fract(cell_units), vec3(0.5f)));
    m.cell = uint(-1);
    m.entry = m.entry_end = 0u;
    open_next_cell(m);
    return m;
}

// Lists up to MERGE_BATCH light vertices within the radius of p whose merged path keeps within bdpt_depth; returns
// how many (fewer: the search is done).
uint list_merge_candidates(inout MergeCursor m, vec3 p, uint segments, out uint listed[MERGE_BATCH]) {
    float r2 = push.merge_radius * push.merge_radius;
    uint n = 0u;
    while (m.cell < 8u && n < MERGE_BATCH) {
        if (m.entry == m.entry_end) {
            open_next_cell(m);
            continue;
        }
        uint slot = merge_grid_words[merge_entry_word(m.entry++)];
        vec3 d = merge_points[slot].xyz - p;
        // Light vertex k has k + 1 segments; merged, the path has the camera's besides.
        if (dot(d, d) <= r2 && segments + slot % params.light_vertex_slots + 1u <= params.bdpt_depth) listed[n++] = slot;
    }
    return n;
}

// The merge of camera vertex c (dvm: its merging quantity at y) with the light vertex in `slot`, MIS-weighted, at the
// path's wavelengths (lib/spectral/path_color.glsl) and without the camera subpath's throughput.
vec4 merge_light_vertex(CameraVertex c, float dvm, uint slot) {
    LightVertex v = load_light_vertex(slot);
    vec3 wl = vec3(v.to_light_x, v.to_light_y, v.to_light_z);
    float cos_wl = abs(dot(wl, c.at_y.ng));
    vec3 f = eval_surface_bsdf(c.at_y, c.wo, wl);  // f cos(wl) at y
    if (!(cos_wl > 0.0f) || !(max_value(f) > 0.0f)) return vec4(0.0f);
    float camera_forward = pdf_surface_bsdf(c.at_y, c.wo, wl);
    // The light side's sampler at y, arriving along wl: the BSDF built for that eye (most often y's own).
    SurfaceBsdf at_light = surface_bsdf_serves(c.y, c.wo, wl) ? c.at_y : make_surface_bsdf(c.y, wl);
    float camera_reverse = pdf_next_direction(at_light, wl, c.wo);
    float weight = weight_merge(c.mis, dvm, camera_reverse, v.dvcm, merge_points[slot].w, camera_forward);
    if (!(weight > 0.0f)) return vec4(0.0f);  // and never 0 x an overflowed contribution (NaN) into the path's sum
    vec4 light_beta = vec4(v.throughput_r, v.throughput_g, v.throughput_b, v.throughput_3);
    vec4 contrib = lift_color(c.spectral, f) * (weight / cos_wl) * light_beta;
    // Both sides dispersed: each weighted its hero wavelength by 4 for the whole path, which takes it once.
    if (effect_on(EFFECT_SPECTRAL) && (c.spectrum_flags & v.spectrum_flags & PATH_SECONDARIES_TERMINATED) != 0u)
        contrib *= 0.25f;
    return contrib;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint parity = push.depth & 1u;
    if (i >= counters.ray_count[parity]) return;
    HitItem hit = load_hit_item(i);
    uint segments = push.depth + 1u;  // camera segments up to this vertex
    if (hit.triangle == INVALID_INDEX || params.bdpt_depth < segments + 1u) return;
    RayItem ray = load_ray_item(ray_slot(parity, i));
    CameraVertex c;
    if (!load_camera_vertex(ray, hit, load_path_mis(ray.path), segments, c)) return;
    float dvm = segment_dvm(path_dvm[ray.path], dot(c.wo, c.at_y.ng));

    vec4 sum = vec4(0.0f);
    MergeCursor search = start_merge_search(c.y.s.p);
    uint listed[MERGE_BATCH];
    uint n;
    do {
        n = list_merge_candidates(search, c.y.s.p, segments, listed);
        for (uint k = 0u; k < n; ++k) sum += merge_light_vertex(c, dvm, listed[k]);
    } while (n == MERGE_BATCH);
    if (!(max_path_component(sum) > 0.0f)) return;
    vec3 merged = film_color(c.spectral, sum * (c.beta / merge_eta()));
    c.state.radiance_r += merged.x;
    c.state.radiance_g += merged.y;
    c.state.radiance_b += merged.z;
    store_path_radiance(ray.path, c.state);  // one uvec4 store: the radiance and the rng as it was
}
