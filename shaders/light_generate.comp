// Stage "light_generate" (`--integrator light` and `bdpt`): starts one light subpath per (pixel, sample) of the wave: a
// light by power, a point on it and a first direction (lib/integrator/light_subpath.glsl), and the light's own vertex joined to
// the camera (the s = 1, t = 1 strategy: a splat; light tracing only). BDPT also starts the path's MIS quantities.
// Reads: params, push, triangles, materials, emitters, punctual lights, the environment (with EFFECT_EMISSIVE_TEXTURE
// / EFFECT_ALPHA textures).
// Writes: rays[queue 0], paths (throughput: the power the subpath carries; bsdf_pdf: its largest component at the
// light, Russian roulette's scale; radiance 0), shadow_rays (one splat per subpath, empty where there is none),
// counters (as generate, and the shadow queue's length), path_mis (bdpt), path media, path_times (motion blur).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/core/queue.glsl"
#include "lib/sampling/rng.glsl"
#include "lib/sampling/sampling.glsl"
#include "lib/core/effects.glsl"
#include "lib/sampling/path_sampler.glsl"
#include "lib/integrator/light_subpath.glsl"
#include "lib/material/transmission.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint total = push.pixel_count * push.sample_count;
    if (i == 0u) reset_counters(total, total);
    if (i >= total) return;

    // Light subpaths draw from the path's PCG stream whatever --sampler says (the Sobol' dimensions are the camera's).
    uint rng = init_rng(path_pixel(i), path_sample_index(i), params.seed);
    // BDPT's camera subpath of the same index starts from that very state (--sampler independent): the light subpath
    // takes a stream of its own, or a connection would join two subpaths drawn from the same numbers.
    if (bdpt) rng = pcg_hash(rng ^ 0x6c8e9cf5u);
    float u_pick = next_float(rng);
    vec2 u_point = vec2(next_float(rng), next_float(rng));
    vec2 u_dir = vec2(next_float(rng), next_float(rng));
    float u_side = next_float(rng);
    // Motion blur: the time the camera subpath of this index has (its sampler's), shared by both subpaths; with a thin
    // lens, where on the aperture the light's own vertex is seen from.
    float time = 0.5f;
    if (effect_on(EFFECT_MOTION_BLUR)) {
        uint camera_rng = init_rng(path_pixel(i), path_sample_index(i), params.seed);
        time = draw_camera_samples(i, camera_rng).time;
        path_times[i] = time;
    }
    vec2 u_lens = effect_on(EFFECT_THIN_LENS) ? vec2(next_float(rng), next_float(rng)) : vec2(0.0f);

    // No light in the table (BDPT where every emitter moves): no light subpath; the camera subpaths find them.
    LightStart start = params.emitter_count == 0u
                           ? make_no_light_start()
                           : start_light_subpath(u_pick, u_point, u_dir, u_side, make_splat_camera(time, u_lens), i);

    RayItem item;
    item.origin_x = start.origin.x;
    item.origin_y = start.origin.y;
    item.origin_z = start.origin.z;
    item.path = i;
    item.dir_x = start.dir.x;
    item.dir_y = start.dir.y;
    item.dir_z = start.dir.z;
    item.origin_triangle = start.triangle;
    store_ray_item(ray_slot(0u, i), item);
    // Bidirectional path tracing leaves a light seen directly to the camera subpath (s = 0 alone, lib/integrator/bdpt.glsl).
    store_shadow_ray(i, bdpt ? make_empty_splat() : start.splat);
    if (bdpt) store_path_mis(i, start.mis);
    // Lights stand outside every volume (shaders/lib/integrator/README.md "Bidirectional path tracing"); the camera subpath starts its own.
    if (tracks_media()) path_media[i] = uvec4(INVALID_INDEX);

    PathState state;
    state.throughput_r = start.power.x;
    state.throughput_g = start.power.y;
    state.throughput_b = start.power.z;
    state.bsdf_pdf = max_value(start.power);
    state.radiance_r = 0.0f;
    state.radiance_g = 0.0f;
    state.radiance_b = 0.0f;
    state.rng = rng;
    store_path_state(i, state);
}
