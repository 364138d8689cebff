// Stage "light_generate" (`--integrator light` and `bdpt`): starts one light subpath per (pixel, sample) of the wave: a
// light by power, a point on it and a first direction (lib/integrator/light_subpath.glsl), and the light's own vertex joined to
// the camera (the s = 1, t = 1 strategy: a splat; light tracing only). BDPT also starts the path's MIS quantities.
// Reads: params, push, triangles, materials, emitters, punctual lights, light media, the environment (with EFFECT_EMISSIVE_TEXTURE
// / EFFECT_ALPHA textures).
// Writes: rays[queue 0], paths (throughput: the power the subpath carries; bsdf_pdf: its largest component at the
// light, Russian roulette's scale; radiance 0), shadow_rays (one splat per subpath, empty where there is none),
// counters (as generate, and the shadow queue's length), path_mis (bdpt), path media, path_times (motion blur),
// path_spectra (spectral: the camera subpath's wavelengths, and the fourth one's power).
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
#include "lib/spectral/path_color.glsl"

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
    // The time (motion blur) and the wavelengths (spectral) the camera subpath of this index has (its sampler's),
    // shared by both subpaths; with a thin lens, where on the aperture the light's own vertex is seen from.
    float time = 0.5f;
    float wavelength_u = 0.0f;
    if (effect_on(EFFECT_MOTION_BLUR) || effect_on(EFFECT_SPECTRAL)) {
        uint camera_rng = init_rng(path_pixel(i), path_sample_index(i), params.seed);
        CameraSamples camera_u = draw_camera_samples(i, camera_rng);
        time = camera_u.time;
        wavelength_u = camera_u.wavelength;
        if (effect_on(EFFECT_MOTION_BLUR)) path_times[i] = time;
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
    if (vcm) path_dvm[i] = start.mis.dvc * vc_weight_factor();
    // The volumes the light stands in, probed on the host (render/light_media.h); the camera subpath starts its own.
    if (tracks_media()) path_media[i] = effect_on(EFFECT_VOLUME) ? light_media[start.emitter] : uvec4(INVALID_INDEX);

    // The power at the subpath's wavelengths (spectral: the light's RGB upsampled, as NEE's is).
    vec4 power = vec4(start.power, 0.0f);
    if (effect_on(EFFECT_SPECTRAL)) {
        power = lift_color(make_spectral_frame(wavelength_u), start.power);
        PathSpectrum spectrum;
        spectrum.wavelength_u = wavelength_u;
        spectrum.throughput_3 = power.w;
        spectrum.flags = 0u;
        spectrum.pad = 0.0f;
        path_spectra[i] = spectrum;
    }

    PathState state;
    state.throughput_r = power.x;
    state.throughput_g = power.y;
    state.throughput_b = power.z;
    state.bsdf_pdf = max_path_component(power);
    state.radiance_r = 0.0f;
    state.radiance_g = 0.0f;
    state.radiance_b = 0.0f;
    state.rng = rng;
    store_path_state(i, state);
}
