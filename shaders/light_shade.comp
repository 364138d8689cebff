// Stage "light_shade" (`--integrator light` and `bdpt`): one light-subpath vertex per queued ray. Joins the vertex to the camera
// (t = 1: a splat through a shadow ray, when the full path keeps within --max-depth), samples the BSDF for the next
// segment, applies Russian roulette and pushes the continuation ray. Light carries importance's adjoint: the BSDF is
// evaluated with its arguments swapped (f(towards the eye side, towards the light)) and the shading normal's
// correction |wo.ng| / |wi.ng| of Veach 1997 (sec. 5.3) is applied, so a non-symmetric BSDF and interpolated normals
// stay unbiased. Through glass the swap is the whole adjoint: the path tracer's 1 / eta^2 of refraction is evaluated
// for the eye's side (Veach 1997 sec. 5.2), and the subpath keeps its stack of volumes (path_media) for the indices
// and for Beer-Lambert absorption along its segments and its splats.
// Bidirectional path tracing also keeps the vertex for the camera subpath (light_vertices), weights the splat by MIS
// and carries the path's MIS quantities (lib/integrator/bdpt.glsl).
// Reads: rays[queue depth & 1], hits, paths, path media, triangles, materials, textures, instances, path_mis. Writes:
// paths, path media, rays[queue (depth + 1) & 1], shadow_rays, counters.ray_count / shadow_count, light_vertices,
// path_mis.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/core/queue.glsl"
#include "lib/sampling/rng.glsl"
#include "lib/sampling/sampling.glsl"
#include "lib/core/effects.glsl"
#include "lib/bsdf/surface_bsdf.glsl"
#include "lib/geometry/motion.glsl"
#include "lib/integrator/light_tracing.glsl"
#include "lib/integrator/bdpt.glsl"
#include "lib/spectral/path_color.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

// The light subpath's vertex at queued ray i: what it pushes to the next extend queue and to connect's shadow queue.
void shade_light_vertex(uint i, uint parity, out bool push_ray, out RayItem next, out bool push_shadow,
                        out ShadowRayItem shadow, out bool escaped) {
    RayItem ray = load_ray_item(ray_slot(parity, i));
    HitItem hit = load_hit_item(i);
    escaped = hit.triangle == INVALID_INDEX;  // counted here for --stats: in extend it took a second atomic
    uint path = ray.path;
    PathState state = load_path_state(path);
    // The throughput at the subpath's wavelengths (lib/spectral/path_color.glsl: RGB in xyz unless spectral).
    vec4 beta = vec4(state.throughput_r, state.throughput_g, state.throughput_b, 0.0f);
    SpectralFrame spectral;
    PathSpectrum spectrum;
    if (effect_on(EFFECT_SPECTRAL)) {
        spectrum = path_spectra[path];
        beta.w = spectrum.throughput_3;
        spectral = make_spectral_frame(spectrum.wavelength_u);
    }
    uint spectrum_flags_before = effect_on(EFFECT_SPECTRAL) ? spectrum.flags : 0u;
    uint rng = state.rng;
    uint segments = push.depth + 1u;  // segments of the light subpath up to this vertex
    // The longest path the subpath may make: BDPT's light subpaths stop where its strategies do (bdpt_weighs).
    uint max_depth = bdpt ? params.bdpt_depth : params.max_depth;
    PathMis mis;
    float dvm = 0.0f;  // vcm: the merges' quantity (lib/integrator/bdpt.glsl)
    if (bdpt) mis = load_path_mis(path);
    if (vcm) dvm = path_dvm[path];

    push_shadow = false;
    push_ray = false;
    next.path = path;
    next.origin_triangle = hit.triangle;

    uvec4 media = tracks_media() ? path_media[path] : uvec4(INVALID_INDEX);  // innermost first
    uvec4 media_before = media;

    // Beer-Lambert along the segment just traced, inside an absorbing volume.
    if (effect_on(EFFECT_ABSORPTION) && hit.triangle != INVALID_INDEX)
        beta *= eval_path_medium_transmittance(spectral, media.x, hit.t);

    if (hit.triangle != INVALID_INDEX && max_path_component(beta) > 0.0f) {
        vec3 wl = -vec3(ray.dir_x, ray.dir_y, ray.dir_z);  // towards the light
        float time = load_path_time(path);  // the subpath's shutter time (motion blur), its camera subpath's too
        ShadingPoint sp = load_shading_point(hit.triangle, hit.b1, hit.b2, hit.instance, time);
        SurfaceHit s = sp.s;
        bool front = dot(s.ng, wl) > 0.0f;  // the side the light arrives on
        // Dispersion: the hero wavelength's index from here on, the others stop (as shade.comp's make_scattering).
        if (disperse_at(sp, spectral.lambda.x) && (spectrum.flags & PATH_SECONDARIES_TERMINATED) == 0u) {
            beta = terminate_secondary_wavelengths(beta);
            spectrum.flags |= PATH_SECONDARIES_TERMINATED;
        }
        set_media(sp, media, front);
        // Proposal for the next direction: the BSDF as if the eye were towards the light.
        SurfaceBsdf at_light = make_surface_bsdf(sp, wl);
        vec3 ng = at_light.ng;
        // 0 only for a ray in the facet's plane: the vertex then sends nothing. An unlit surface (KHR_materials_unlit) is
        // black to every ray but the camera's (BDPT's s = 0 at the first camera vertex shows it): it ends the subpath.
        bool unlit = effect_on(EFFECT_UNLIT) && (sp.m.flags & MATERIAL_UNLIT) != 0u;
        float cos_light_g = unlit ? 0.0f : dot(wl, ng);
        if (bdpt && cos_light_g > 0.0f) {
            account_segment(mis, hit.t, cos_light_g, segments > 1u || (mis.flags & PATH_MIS_LIGHT_AT_INFINITY) == 0u);
            // The light tree: NEE here (as shade.comp's make_scattering stands for a viewer on the light's side, the
            // only side a reflecting surface joins it to) picks the subpath's light by its own probability.
            if (effect_on(EFFECT_LIGHT_TREE) && segments == 1u)
                fold_tree_pick_at_first_hit(
                    mis, make_light_point(s.p, ng, at_light.transmits ? LIGHT_POINT_TWO_SIDED : LIGHT_POINT_ONE_SIDED),
                    ray.origin_triangle, vec3(ray.dir_x, ray.dir_y, ray.dir_z), hit.t);
            if (vcm) dvm = segment_dvm(dvm, cos_light_g);
            // Kept for the camera subpath while a camera vertex can still join it within --max-depth.
            if (segments <= params.light_vertex_slots) {
                LightVertex v;
                v.throughput_r = beta.x;
                v.throughput_g = beta.y;
                v.throughput_b = beta.z;
                v.dvcm = mis.dvcm;
                v.to_light_x = wl.x;
                v.to_light_y = wl.y;
                v.to_light_z = wl.z;
                v.dvc = mis.dvc;
                v.triangle = hit.triangle;
                v.b1 = hit.b1;
                v.b2 = hit.b2;
                v.instance = hit.instance;
                v.eta_front = sp.eta_front;
                v.throughput_3 = beta.w;
                v.spectrum_flags = effect_on(EFFECT_SPECTRAL) ? spectrum.flags : 0u;
                v.pad = 0u;
                store_light_vertex(path * params.light_vertex_slots + push.depth, v);
                if (vcm) merge_points[path * params.light_vertex_slots + push.depth] = vec4(s.p, dvm);
                mis.light_vertices = segments;
            }
        }

        // t = 1: the camera sees this vertex (through the surface, if it transmits); the full path has one segment
        // more than the subpath.
        if (cos_light_g > 0.0f && (max_depth == 0u || segments + 1u <= max_depth)) {
            vec2 u_lens = effect_on(EFFECT_THIN_LENS) ? vec2(next_float(rng), next_float(rng)) : vec2(0.0f);
            FilmSplat splat = project_to_film(make_splat_camera(time, u_lens), s.p);
            float cos_camera_g = abs(dot(splat.to_camera, ng));
            if (splat.valid && cos_camera_g > 0.0f) {
                SurfaceBsdf at_camera = make_surface_bsdf(sp, splat.to_camera);
                vec3 f = eval_surface_bsdf(at_camera, splat.to_camera, wl);  // f(camera, light) cos_light
                vec4 contrib = beta * lift_color(spectral, f) * (cos_camera_g / cos_light_g * splat.importance);
                if (effect_on(EFFECT_ABSORPTION))
                    contrib *= eval_path_medium_transmittance(spectral, medium_towards(sp, media, front, splat.to_camera),
                                                              splat.dist);
                if (bdpt)
                    contrib *= weight_strategy(segments + 1u, 1u, weight_camera_connection(
                                                   mis, splat.importance * cos_camera_g,
                                                   pdf_surface_bsdf(at_camera, splat.to_camera, wl)));
                if (max_path_component(contrib) > 0.0f) {
                    shadow = make_splat_ray(s.p, s.p_error, at_camera.ng, splat, film_color(spectral, contrib),
                                            hit.triangle, path);
                    push_shadow = true;
                }
            }
        }

        // The next segment, if a path through it can still reach the camera within --max-depth.
        vec3 u_bsdf = vec3(next_float(rng), next_float(rng), next_float(rng));
        float u_roulette = next_float(rng);
        if (cos_light_g > 0.0f && (max_depth == 0u || segments + 1u < max_depth)) {
            NextDirection next_dir = sample_next_direction(at_light, wl, u_bsdf);
            vec3 wi = next_dir.wi;
            float cos_next_g = abs(dot(wi, ng));
            if (next_dir.pdf > 0.0f && cos_next_g > 0.0f) {
                // Adjoint: f(next, light) cos_light as the path tracer's frame from `next` sees it, over the
                // proposal's pdf, with the shading-normal correction.
                SurfaceBsdf at_next = make_surface_bsdf(sp, wi);
                beta *= lift_color(spectral, eval_surface_bsdf(at_next, wi, wl)) *
                        (cos_next_g / (cos_light_g * next_dir.pdf));
                float reverse = bdpt ? pdf_surface_bsdf(at_next, wi, wl) : 0.0f;
                if (vcm) dvm = scattered_dvm(dvm, mis, cos_next_g, next_dir.pdf, reverse);
                if (bdpt) account_scattering(mis, cos_next_g, next_dir.pdf, reverse);
                bool survive = true;
                // Russian roulette on the throughput relative to what the subpath carried from the light.
                if ((params.flags & RENDER_RR) != 0u && segments >= params.rr_start_depth) {
                    float q = min(max_path_component(beta) / state.bsdf_pdf, 0.95f);
                    survive = u_roulette < q;
                    beta /= q;
                }
                if (survive && max_path_component(beta) > 0.0f) {
                    // Crossing into (or out of) a volume.
                    if (dot(wi, ng) < 0.0f) media = media_across(sp, media, front);
                    vec3 origin = offset_ray_origin(s.p, s.p_error, ng, wi);
                    next.origin_x = origin.x;
                    next.origin_y = origin.y;
                    next.origin_z = origin.z;
                    next.dir_x = wi.x;
                    next.dir_y = wi.y;
                    next.dir_z = wi.z;
                    push_ray = true;
                }
            }
        }
    }

    state.throughput_r = beta.x;
    state.throughput_g = beta.y;
    state.throughput_b = beta.z;
    state.rng = rng;
    store_path_state(path, state);
    if (effect_on(EFFECT_SPECTRAL)) {
        path_spectra[path].throughput_3 = beta.w;
        if (spectrum.flags != spectrum_flags_before) path_spectra[path].flags = spectrum.flags;
    }
    if (bdpt) store_path_mis(path, mis);
    if (vcm) path_dvm[path] = dvm;
    if (tracks_media() && any(notEqual(media, media_before))) path_media[path] = media;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint parity = push.depth & 1u;
    bool push_ray = false, push_shadow = false, escaped = false;
    RayItem next;
    ShadowRayItem shadow;
    if (i < counters.ray_count[parity]) shade_light_vertex(i, parity, push_ray, next, push_shadow, shadow, escaped);
    // Every invocation of the workgroup gets here: the queues' slots are taken with one atomic per workgroup.
    uint ray_slot_index, shadow_slot;
    PUSH_VERTEX_RESULTS_IN_WORKGROUP(counters.ray_count[parity ^ 1u], push_ray, ray_slot_index, counters.shadow_count,
                                     push_shadow, shadow_slot, counters.escaped_rays, escaped);
    if (push_ray) store_ray_item(ray_slot(parity ^ 1u, ray_slot_index), next);
    if (push_shadow) store_shadow_ray(shadow_slot, shadow);
}
