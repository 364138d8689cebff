// Stage "generate": starts one path per (pixel, sample) of the wave.
// Reads: params, push (wave's pixel and sample ranges). Writes: rays[queue 0], paths, path media (cameras
// start outside every volume), path spectra (a spectral render's wavelengths, EFFECT_SPECTRAL), path times (when
// in the shutter, EFFECT_MOTION_BLUR), counters (queue 0 length, indirect size of the first extend/shade), and with
// `--integrator bdpt` the camera subpath's MIS quantities (path_mis); with `--adaptive` it takes the wave's pixels
// from the pixel list and zeroes path_work (lib/core/wave_pixels.glsl).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/core/queue.glsl"
#include "lib/sampling/rng.glsl"
#include "lib/sampling/sampling.glsl"
#include "lib/geometry/camera.glsl"
#include "lib/core/effects.glsl"
#include "lib/sampling/path_sampler.glsl"
#include "lib/integrator/bdpt.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint total = push.pixel_count * push.sample_count;
    if (i == 0u) reset_counters(total, 0u);
    if (i >= total) return;

    // Sample-major order inside the wave: path i is sample i / pixel_count of pixel i % pixel_count.
    uint pixel = path_pixel(i);
    uint rng = init_rng(pixel, path_sample_index(i), params.seed);
    CameraSamples camera_u = draw_camera_samples(i, rng);

    vec2 u = camera_u.film;
    vec2 offset = (params.filter_type == FILTER_GAUSSIAN) ? sample_gaussian_filter(u, params.filter_radius)
                                                           : u - vec2(0.5f);
    vec2 film = vec2(float(pixel % params.width), float(pixel / params.width)) + vec2(0.5f) + offset;
    CameraRay ray = make_camera_ray(film, camera_u.lens, camera_u.time);
    if (effect_on(EFFECT_MOTION_BLUR)) path_times[i] = camera_u.time;
    if (pixel_list_on) path_work[i] = 0u;

    RayItem item;
    item.origin_x = ray.origin.x;
    item.origin_y = ray.origin.y;
    item.origin_z = ray.origin.z;
    item.path = i;
    item.dir_x = ray.dir.x;
    item.dir_y = ray.dir.y;
    item.dir_z = ray.dir.z;
    item.origin_triangle = INVALID_INDEX;
    store_ray_item(ray_slot(0u, i), item);

    PathState state;
    state.throughput_r = 1.0f;
    state.throughput_g = 1.0f;
    state.throughput_b = 1.0f;
    state.bsdf_pdf = 0.0f;
    state.radiance_r = 0.0f;
    state.radiance_g = 0.0f;
    state.radiance_b = 0.0f;
    state.rng = rng;
    store_path_state(i, state);
    if (bdpt) {  // the light subpath's vertex count stays for connect_subpaths
        PathMis mis = start_camera_mis(ray.dir, camera_view_at(camera_u.time).forward);
        path_mis[i].dvcm = mis.dvcm;
        path_mis[i].dvc = mis.dvc;
        if (vcm) path_dvm[i] = 0.0f;
    }
    if (effect_on(EFFECT_VOLUME) || effect_on(EFFECT_ABSORPTION)) path_media[i] =
        uvec4(params.camera_medium, params.camera_medium_outer, params.camera_medium_outermost, INVALID_INDEX);
    if (effect_on(EFFECT_SPECTRAL)) {
        PathSpectrum spectrum;
        spectrum.wavelength_u = camera_u.wavelength;
        spectrum.throughput_3 = 1.0f;
        spectrum.flags = 0u;
        spectrum.pad = 0.0f;
        path_spectra[i] = spectrum;
    }
}
