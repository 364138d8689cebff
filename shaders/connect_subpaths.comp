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
#include "lib/integrator/camera_vertex.glsl"
#include "lib/geometry/traverse.glsl"

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

    CameraVertex c;
    if (!load_camera_vertex(ray, hit, camera_mis, segments, c)) return;
    vec4 beta = c.beta;
    SpectralFrame spectral = c.spectral;
    ShadingPoint y = c.y;
    SurfaceBsdf at_y = c.at_y;
    vec3 wo = c.wo;
    float time = c.time;

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
        if (effect_on(EFFECT_SPECTRAL) && (c.spectrum_flags & v.spectrum_flags & PATH_SECONDARIES_TERMINATED) != 0u)
            contrib *= 0.25f;
        // Beer-Lambert along the joint, inside an absorbing volume (on y's side towards z).
        if (effect_on(EFFECT_ABSORPTION))
            contrib *= eval_path_medium_transmittance(spectral, medium_towards(y, c.media, c.front, w), sqrt(dist2));
        if (!(max_path_component(contrib) > 0.0f)) continue;

        PathMis light_mis;
        light_mis.dvcm = v.dvcm;
        light_mis.dvc = v.dvc;
        float camera_forward_area = pdf_surface_bsdf(at_y, wo, w) * cos_z / dist2;
        float light_forward_area = pdf_next_direction(make_surface_bsdf(z, wl), wl, -w) * cos_y / dist2;
        float camera_reverse = pdf_next_direction(make_surface_bsdf(y, w), w, wo);
        float light_reverse = pdf_surface_bsdf(at_z, -w, wl);
        float weight = weight_strategy(k + 2u, segments + 1u,
                                       weight_subpath_connection(c.mis, camera_reverse, light_forward_area,
                                                                 light_mis, light_reverse, camera_forward_area));
        if (!(weight > 0.0f)) continue;  // and never 0 x an overflowed contribution (NaN) into the path's sum
        contrib *= weight;

        // Visibility, from just off y to just off z (pbrt's ShadowEpsilon short of it).
        vec3 origin = offset_ray_origin(y.s.p, y.s.p_error, y.s.ng, w);
        vec3 target = offset_ray_origin(z.s.p, z.s.p_error, z.s.ng, -w);
        vec3 to_target = target - origin;
        float len = length(to_target);
        if (!(len > 0.0f)) continue;
        uint alpha_seed = effect_on(EFFECT_ALPHA) ? pcg_hash(c.state.rng ^ pcg_hash(k ^ 0x3c6ef372u)) : 0u;
        TraceHit blocker = trace_ray(origin, to_target / len, len * (1.0f - 1e-4f), true, hit.triangle, alpha_seed, time);
        traced += 1u;
        if (blocker.triangle == INVALID_INDEX) sum += film_color(spectral, contrib);
    }
    COUNT_IN_SUBGROUP(counters.traced_shadow_rays, traced);
    c.state.radiance_r += sum.x;
    c.state.radiance_g += sum.y;
    c.state.radiance_b += sum.z;
    store_path_radiance(path, c.state);  // one uvec4 store: the radiance and the rng as it was
}
