// Stage "connect_subpaths" (`--integrator bdpt`): the strategies with s, t >= 2 of bidirectional path tracing. Each
// camera vertex just found (the queued ray's hit, before shade moves the path on) is joined to every stored vertex of
// the light subpath with the same (pixel, sample) (light_shade.comp) whose full path keeps within FrameParams.bdpt_depth: both
// BSDFs evaluated towards each other (the light side's adjoint, with the shading-normal correction, as light tracing
// has it), the MIS weight from both sides' quantities (lib/integrator/bdpt.glsl), and a shadow ray between them. A path's
// connections are summed in a fixed order by one invocation, so the result is the same bits every run.
// Reads: rays[queue depth & 1], hits, paths, path media, path_mis, light_vertices, triangles, materials, textures,
// instances, BVH. Writes: paths[].radiance, counters.traced_shadow_rays.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/core/queue.glsl"
#include "lib/core/effects.glsl"
#include "lib/bsdf/surface_bsdf.glsl"
#include "lib/integrator/bdpt.glsl"
#include "lib/geometry/traverse.glsl"
#include "lib/spectral/path_color.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint parity = push.depth & 1u;
    if (i >= counters.ray_count[parity]) return;
    HitItem hit = load_hit_item(i);
    if (hit.triangle == INVALID_INDEX) return;
    RayItem ray = load_ray_item(ray_slot(parity, i));
    uint path = ray.path;
    PathMis camera_mis = load_path_mis(path);
    uint segments = push.depth + 1u;  // camera segments up to this vertex
    // Light vertex k has k + 1 segments; the joint adds one.
    if (params.bdpt_depth < segments + 2u) return;  // longer paths are path traced (bdpt_weighs)
    uint last = min(min(camera_mis.light_vertices, params.light_vertex_slots), params.bdpt_depth - segments - 1u);
    if (last == 0u) return;

    PathState state = load_path_state(path);
    // The camera side's throughput at both subpaths' wavelengths (spectral: the path's four; path_color.glsl).
    vec4 beta = vec4(state.throughput_r, state.throughput_g, state.throughput_b, 0.0f);
    SpectralFrame spectral;
    uint camera_flags = 0u;
    if (effect_on(EFFECT_SPECTRAL)) {
        PathSpectrum spectrum = path_spectra[path];
        beta.w = spectrum.throughput_3;
        camera_flags = spectrum.flags;
        spectral = make_spectral_frame(spectrum.wavelength_u);
    }
    vec3 wo = -vec3(ray.dir_x, ray.dir_y, ray.dir_z);
    float time = load_path_time(path);  // both subpaths' shutter time (motion blur)
    ShadingPoint y = load_shading_point(hit.triangle, hit.b1, hit.b2, hit.instance, time);
    bool front_y = dot(y.s.ng, wo) > 0.0f;
    uvec4 media_y = tracks_media() ? path_media[path] : uvec4(INVALID_INDEX);
    // A dispersive y: the hero wavelength alone goes on through it (as shade.comp will have it, after this stage).
    if (disperse_at(y, spectral.lambda.x) && (camera_flags & PATH_SECONDARIES_TERMINATED) == 0u) {
        beta = terminate_secondary_wavelengths(beta);
        camera_flags |= PATH_SECONDARIES_TERMINATED;
    }
    set_media(y, media_y, front_y);
    // Beer-Lambert along the segment to y (shade, after this stage, applies it to the path's own throughput).
    if (effect_on(EFFECT_ABSORPTION)) beta *= eval_path_medium_transmittance(spectral, media_y.x, hit.t);
    SurfaceBsdf at_y = make_surface_bsdf(y, wo);
    float cos_wo = dot(wo, at_y.ng);
    bool unlit = effect_on(EFFECT_UNLIT) && (y.m.flags & MATERIAL_UNLIT) != 0u;  // black but to the camera's own ray
    if (!(cos_wo > 0.0f) || !(max_path_component(beta) > 0.0f) || unlit) return;
    account_segment(camera_mis, hit.t, cos_wo, camera_segment_has_distance(segments));

    vec3 sum = vec3(0.0f);
    uint traced = 0u;
    for (uint k = 0u; k < last; ++k) {
        LightVertex v = load_light_vertex(path * params.light_vertex_slots + k);
        vec3 wl = vec3(v.to_light_x, v.to_light_y, v.to_light_z);
        ShadingPoint z = load_shading_point(v.triangle, v.b1, v.b2, v.instance, time);
        z.eta_front = v.eta_front;
        vec3 d = z.s.p - y.s.p;
        float dist2 = dot(d, d);
        if (!(dist2 > 0.0f)) continue;
        vec3 w = d * inversesqrt(dist2);  // from y towards z
        // Geometric cosines; either end may join through its surface where a lobe transmits (the BSDFs say).
        float cos_y = abs(dot(w, y.s.ng));
        float cos_z = abs(dot(w, z.s.ng));
        float cos_wl = abs(dot(wl, z.s.ng));
        if (!(cos_y > 0.0f && cos_z > 0.0f && cos_wl > 0.0f)) continue;

        vec3 f_y = eval_surface_bsdf(at_y, wo, w);  // f cos at y, towards z
        SurfaceBsdf at_z = make_surface_bsdf(z, -w);
        vec3 f_z = eval_surface_bsdf(at_z, -w, wl);  // f cos at z, light from wl
        vec4 light_beta = vec4(v.throughput_r, v.throughput_g, v.throughput_b, v.throughput_3);
        vec4 contrib = beta * lift_color(spectral, f_y) * lift_color(spectral, f_z) * light_beta *
                       (cos_z / (cos_wl * dist2));
        // Both sides dispersed: each weighted its hero wavelength by 4 for the whole path, which takes it once.
        if (effect_on(EFFECT_SPECTRAL) && (camera_flags & v.spectrum_flags & PATH_SECONDARIES_TERMINATED) != 0u)
            contrib *= 0.25f;
        // Beer-Lambert along the joint, inside an absorbing volume (on y's side towards z).
        if (effect_on(EFFECT_ABSORPTION))
            contrib *= eval_path_medium_transmittance(spectral, medium_towards(y, media_y, front_y, w), sqrt(dist2));
        if (!(max_path_component(contrib) > 0.0f)) continue;

        PathMis light_mis;
        light_mis.dvcm = v.dvcm;
        light_mis.dvc = v.dvc;
        float camera_forward_area = pdf_surface_bsdf(at_y, wo, w) * cos_z / dist2;
        float light_forward_area = pdf_next_direction(make_surface_bsdf(z, wl), wl, -w) * cos_y / dist2;
        float camera_reverse = pdf_next_direction(make_surface_bsdf(y, w), w, wo);
        float light_reverse = pdf_surface_bsdf(at_z, -w, wl);
        float weight = weight_strategy(k + 2u, segments + 1u,
                                       weight_subpath_connection(camera_mis, camera_reverse, light_forward_area,
                                                                 light_mis, light_reverse, camera_forward_area));
        if (!(weight > 0.0f)) continue;  // and never 0 x an overflowed contribution (NaN) into the path's sum
        contrib *= weight;

        // Visibility, from just off y to just off z (pbrt's ShadowEpsilon short of it).
        vec3 origin = offset_ray_origin(y.s.p, y.s.p_error, y.s.ng, w);
        vec3 target = offset_ray_origin(z.s.p, z.s.p_error, z.s.ng, -w);
        vec3 to_target = target - origin;
        float len = length(to_target);
        if (!(len > 0.0f)) continue;
        uint alpha_seed = effect_on(EFFECT_ALPHA) ? pcg_hash(state.rng ^ pcg_hash(k ^ 0x3c6ef372u)) : 0u;
        TraceHit blocker = trace_ray(origin, to_target / len, len * (1.0f - 1e-4f), true, hit.triangle, alpha_seed, time);
        traced += 1u;
        if (blocker.triangle == INVALID_INDEX) sum += film_color(spectral, contrib);
    }
    COUNT_IN_SUBGROUP(counters.traced_shadow_rays, traced);
    state.radiance_r += sum.x;
    state.radiance_g += sum.y;
    state.radiance_b += sum.z;
    store_path_radiance(path, state);  // one uvec4 store: the radiance and the rng as it was
}
