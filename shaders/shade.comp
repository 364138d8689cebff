// Stage "shade": one path vertex per queued ray. Adds emission seen by the ray, or the environment's radiance
// when it escaped (both MIS-weighted against light sampling), resolves the material (textures, vertex colours,
// normal map, anisotropy, thin film, glass, dispersion, diffuse transmission, sheen, clear coat, unlit: only the
// effects the scene has are compiled in), samples a light and pushes a shadow ray (next-event estimation), samples the
// BSDF, applies Russian roulette and pushes the continuation ray. A spectral render (EFFECT_SPECTRAL) carries four
// wavelengths per path and hands the film RGB (lib/spectral/path_color.glsl).
// Reads: rays[queue depth & 1], hits, paths, triangles, materials, emitters, textures, environment, and for
// glass, sheens and clear coats the material layers, path media and path spectra. Writes: paths, path media, path
// spectra, rays[queue (depth + 1) & 1], shadow_rays, counters.ray_count / shadow_count.
// `--integrator bdpt` (the shade_bdpt SPIR-V, FH_INTEGRATOR) weights emission and NEE against every strategy of bidirectional path tracing
// and carries the camera subpath's MIS quantities (path_mis; lib/integrator/bdpt.glsl) instead of the path tracer's two-way MIS.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/core/queue.glsl"
#include "lib/sampling/rng.glsl"
#include "lib/sampling/path_sampler.glsl"
#include "lib/sampling/sampling.glsl"
#include "lib/core/effects.glsl"
#include "lib/bsdf/bsdf_layers.glsl"
#include "lib/geometry/motion.glsl"
#include "lib/light/lights.glsl"
#include "lib/material/transmission.glsl"
#include "lib/spectral/path_color.glsl"
#include "lib/bsdf/surface_bsdf.glsl"
#include "lib/integrator/bdpt.glsl"
#include "lib/core/ray_order.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

float max_component(vec3 v) { return max(v.x, max(v.y, v.z)); }

// The path vertex of queued ray i: what it pushes to the next extend queue and to connect's shadow queue.
void shade_vertex(uint i, uint parity, out bool push_ray, out RayItem next, out bool push_shadow,
                  out ShadowRayItem shadow, out bool escaped) {
    RayItem ray = load_ray_item(ray_slot(parity, i));
    HitItem hit = load_hit_item(i);
    escaped = hit.triangle == INVALID_INDEX;  // counted here for --stats: in extend it took a second atomic
    uint path = ray.path;
    PathState state = load_path_state(path);
    vec4 beta = vec4(state.throughput_r, state.throughput_g, state.throughput_b, 0.0f);
    vec3 radiance = vec3(state.radiance_r, state.radiance_g, state.radiance_b);
    uint rng = state.rng;
    // A spectral path's wavelengths and fourth throughput (layout.h PathSpectrum).
    PathSpectrum spectrum;
    SpectralFrame spectral;
    if (effect_on(EFFECT_SPECTRAL)) {
        spectrum = path_spectra[path];
        beta.w = spectrum.throughput_3;
        spectral = make_spectral_frame(spectrum.wavelength_u);
    }
    uint flags_before = effect_on(EFFECT_SPECTRAL) ? spectrum.flags : 0u;
    uint segments = push.depth + 1u;  // segments of this path including the ray just traced
    PathMis mis;
    if (bdpt) mis = load_path_mis(path);
    // Beer-Lambert along the segment just traced when the path is inside an absorbing volume.
    uvec4 media = tracks_media() ? path_media[path] : uvec4(INVALID_INDEX);  // innermost first
    uvec4 media_before = media;
    uint medium = media.x;
    if (effect_on(EFFECT_ABSORPTION))
        beta *= eval_path_medium_transmittance(spectral, medium,
                                               hit.triangle == INVALID_INDEX ? uintBitsToFloat(0x7f800000u) : hit.t);

    push_shadow = false;
    push_ray = false;
    next.path = path;
    next.origin_triangle = hit.triangle;
    shadow.path = path;
    shadow.origin_triangle = hit.triangle;

    if (hit.triangle == INVALID_INDEX && effect_on(EFFECT_ENVIRONMENT)) {
        // The ray escaped: environment radiance, weighted against NEE's sampling of the environment.
        vec3 dir = vec3(ray.dir_x, ray.dir_y, ray.dir_z);
        float weight = 1.0f;
        if ((params.flags & RENDER_NEE) != 0u && state.bsdf_pdf > 0.0f && params.env_pick_pdf > 0.0f)
            weight = (params.flags & RENDER_MIS) != 0u
                         ? power_heuristic(state.bsdf_pdf, params.env_pick_pdf * pdf_environment(dir))
                         : 0.0f;
        if (bdpt)
            weight = weight_strategy(0u, segments + 1u, segments == 1u ? 1.0f
                                                        : weight_environment_hit(mis, params.env_pick_pdf * pdf_environment(dir)));
        radiance += film_color(spectral, beta * lift_color(spectral, eval_environment(dir))) * weight * escape_scale(medium);
    }
    if (hit.triangle != INVALID_INDEX) {
        vec3 dir = vec3(ray.dir_x, ray.dir_y, ray.dir_z);
        vec3 wo = -dir;
        SurfaceHit s = load_surface(hit.triangle, hit.b1, hit.b2);  // object space for an instance
        bool instanced = scene_has_instances && hit.instance != INVALID_INDEX;
        Instance inst;
        if (instanced) {
            inst = move_instance(load_instance(hit.instance), load_path_time(path));
            if (inst.material != INVALID_INDEX) s.material = inst.material;
        }
        Material m = resolve_material(load_material(s.material), hit.triangle, hit.b1, hit.b2);
        // KHR_materials_unlit: camera rays see the base colour (times its texture and COLOR_0); every other
        // ray finds a black surface that ends the path (shaders/lib/bsdf/README.md "Unlit").
        bool unlit = effect_on(EFFECT_UNLIT) && (m.flags & MATERIAL_UNLIT) != 0u;
        bool may_extend = !unlit && (params.max_depth == 0u || segments < params.max_depth);
        // The anisotropy's direction lies in the mesh's tangent frame (object space, before placing the instance);
        // only a vertex that scatters reads it.
        AnisotropyLayer anisotropy;
        anisotropy.strength = 0.0f;
        anisotropy.direction = vec3(0.0f);
        if (effect_on(EFFECT_ANISOTROPY) && may_extend) {
            anisotropy = eval_anisotropy_layer(s.material, hit.triangle, hit.b1, hit.b2, s.ns);
            s.ta = anisotropy.direction;
        }
        s.ns = apply_normal_texture(m, hit.triangle, hit.b1, hit.b2, s.ns);
        s.nc = apply_clearcoat_normal_texture(s.material, hit.triangle, hit.b1, hit.b2, s.nc);
        if (instanced) s = place_surface(s, inst);
        bool front = dot(s.ng, wo) > 0.0f;
        bool double_sided = (m.flags & MATERIAL_DOUBLE_SIDED) != 0u;
        if (bdpt) account_segment(mis, hit.t, abs(dot(s.ng, wo)), camera_segment_has_distance(segments));

        if (unlit && push.depth == 0u)  // BDPT: s = 0 alone makes it (--bdpt-strategy keeps it with (0,2) only)
            radiance += film_color(spectral, beta * lift_color(spectral, max(vec3(m.base_color), vec3(0.0f)))) *
                        (bdpt ? weight_strategy(0u, 2u, 1.0f) : 1.0f);

        // Emission. Paths that could also have sampled this light by NEE are weighted by the power
        // heuristic (Veach 1997, eq. 9.13); with NEE on and MIS off, only NEE counts light from surfaces.
        vec3 emission = m.emission.xyz;
        if (effect_on(EFFECT_EMISSIVE_TRIANGLES) && (front || double_sided) && max_component(emission) > 0.0f) {
            float weight = 1.0f;
            bool nee = (params.flags & RENDER_NEE) != 0u && state.bsdf_pdf > 0.0f;
            if (nee) {
                if ((params.flags & RENDER_MIS) != 0u) {
                    float cos_light = abs(dot(s.ng, wo));
                    float light_pdf = s.light_pdf_area * hit.t * hit.t / cos_light;
                    if (effect_on(EFFECT_LIGHT_TREE))  // as NEE at the vertex the ray left would have sampled it
                        light_pdf = tree_emitter_hit_pdf(unpack_light_point(path_light_points[path]), hit.triangle,
                                                         s.light_entry, hit.t, cos_light);
                    weight = power_heuristic(state.bsdf_pdf, light_pdf);
                } else {
                    weight = 0.0f;
                }
            }
            if (bdpt)
                weight = weight_strategy(0u, segments + 1u, segments == 1u ? 1.0f
                                         : weight_emission_hit(mis, s.light_pdf_area, abs(dot(s.ng, wo)), double_sided));
            radiance += film_color(spectral, beta * lift_color(spectral, emission)) * weight;
        }

        if (may_extend) {
            // Both normals on the side the ray came from (z of the local frame).
            vec3 ng = front ? s.ng : -s.ng;
            vec3 ns = front ? s.ns : -s.ns;
            // Interpolated normals can face away from a grazing viewer although the surface faces it; the
            // BSDF would then return black (black facets at silhouettes). Shade such points with the
            // geometric normal (tests/README.md "Numerical stability", case 8).
            if (dot(ns, wo) <= 0.0f) ns = ng;
            // Glass (KHR_materials_transmission): thin-walled, or the surface of a volume, entered from the front.
            bool volume = false;
            float transmission = 0.0f;
            if (effect_on(EFFECT_TRANSMISSION)) {
                volume = encloses_volume(s.material);
                transmission = eval_transmission(s.material, hit.triangle, hit.b1, hit.b2);
            }
            // A mirror reflection about the shading normal must stay above the geometric surface, or the path dies
            // there: normal textures tilt it that far anywhere, and interpolated normals at the curved rims of thin
            // glass, where light guided along the wall by total internal reflection meets it at every bounce
            // (shaders/lib/bsdf/README.md "Glass", "Interpolated normals on glass": 15% of a vase's light was lost so).
            if ((effect_on(EFFECT_NORMAL_TEXTURE) && m.normal_texture != INVALID_INDEX) ||
                (effect_on(EFFECT_TRANSMISSION) && transmission > 0.0f))
                ns = keep_reflection_above_surface(ns, ng, wo);
            Frame frame = make_frame(ns);
            vec3 wo_local = to_local(frame, wo);
            // The volumes across the surface: entering one (inside another, nested) or leaving back into the outer.
            uvec4 media_beyond = volume ? (front ? enter_medium(media, s.material) : leave_medium(media, s.material))
                                        : media;
            // Dispersion (KHR_materials_dispersion) where light refracts into a volume: the whole BSDF takes the hero
            // wavelength's index, and the other wavelengths stop here (their directions would differ).
            if (effect_on(EFFECT_SPECTRAL) && volume && transmission > 0.0f) {
                float dispersion = load_material_layers(s.material).dispersion;
                if (dispersion > 0.0f) {
                    m.ior = eval_dispersive_ior(m.ior, dispersion, spectral.lambda.x);
                    if ((spectrum.flags & PATH_SECONDARIES_TERMINATED) == 0u) {
                        beta = terminate_secondary_wavelengths(beta);
                        spectrum.flags |= PATH_SECONDARIES_TERMINATED;
                    }
                }
            }
            BsdfParams bsdf = make_bsdf_params(m);
            float eta = m.ior;  // n beyond / n on this side (lib/material/transmission.glsl); thin-walled: the ior
            if (effect_on(EFFECT_TRANSMISSION)) {
                if (volume) eta = refraction_eta_at(s.material, m.ior, media, front);
                bsdf = with_transmission(bsdf, transmission, eta, volume ? 0u : 1u);
            }
            bsdf = add_bsdf_layers(bsdf, s, hit.triangle, hit.b1, hit.b2, frame, anisotropy, front, ng, wo);
            bool transmits = has_transmission_lobe(bsdf);
            uint medium_beyond = media_beyond.x;  // across the surface
            // BDPT's reverse densities: the light subpath's sampler arriving along a direction.
            ShadingPoint sp;
            if (bdpt) {
                sp.s = s;
                sp.m = m;
                sp.anisotropy = anisotropy;
                sp.triangle = hit.triangle;
                sp.b1 = hit.b1;
                sp.b2 = hit.b2;
                sp.transmission = transmission;
                sp.volume = volume;
                sp.eta_front = !volume ? 1.0f : front ? eta : 1.0f / max(eta, 1.0e-4f);
            }

            VertexSamples u = draw_vertex_samples(path, push.depth, rng);
            // Where NEE stands; the light tree also bounds by the normal on the side the path came from.
            LightTreePoint light_point;
            light_point.p = s.p;
            light_point.n = ng;
            light_point.kind = LIGHT_POINT_NO_NORMAL;
            if (effect_on(EFFECT_LIGHT_TREE))
                light_point = make_light_point(s.p, ng, transmits ? LIGHT_POINT_TWO_SIDED : LIGHT_POINT_ONE_SIDED);
            if ((params.flags & RENDER_NEE) != 0u && params.emitter_count > 0u) {
                LightConnection light = sample_light_connection(light_point, u.pick, u.light);
                vec3 wi = light.wi;
                if (light.valid != 0u && (transmits || dot(wi, ng) > 0.0f)) {
                    vec3 wi_local = to_local(frame, wi);
                    vec3 f = !transmits ? eval_bsdf(bsdf, wo_local, wi_local)
                             : may_leave_towards(wi, ng, wi_local)
                                 ? eval_bsdf(bsdf, wo_local, wi_local) *
                                       same_side_transmission_scale(bsdf, volume, wi, ng, wi_local)
                                 : vec3(0.0f);
                    float weight = (params.flags & RENDER_MIS) != 0u && light.delta == 0u
                                       ? power_heuristic(light.pdf, pdf_bsdf(bsdf, wo_local, wi_local))
                                       : 1.0f;
                    if (bdpt)
                        weight = weight_strategy(1u, segments + 1u, weight_light_connection(
                            mis, light.delta == 0u ? pdf_bsdf(bsdf, wo_local, wi_local) : 0.0f, light.pdf,
                            light.emission_over_direct, abs(dot(wi, ng)),
                            pdf_next_direction(make_surface_bsdf(sp, wi), wi, wo)));
                    vec4 contrib = beta * lift_color(spectral, f) * lift_color(spectral, light.radiance_over_pdf) * weight;
                    if (max_path_component(contrib) > 0.0f) {
                        vec3 origin = offset_ray_origin(s.p, s.p_error, ng, wi);
                        vec3 d = wi;
                        float t_max = 3.0e38f;  // directional light: nothing beyond the scene can block it
                        if (light.at_infinity == 0u) {
                            d = light.target - origin;
                            float len = length(d);
                            d /= len;
                            t_max = len * (1.0f - 1e-4f);  // pbrt's ShadowEpsilon
                        }
                        uint shadow_medium = dot(wi, ng) < 0.0f ? medium_beyond : medium;
                        if (effect_on(EFFECT_ABSORPTION))
                            contrib *= eval_path_medium_transmittance(
                                spectral, shadow_medium, light.at_infinity != 0u ? uintBitsToFloat(0x7f800000u) : t_max);
                        if (light.at_infinity != 0u) contrib *= escape_scale(shadow_medium);
                        vec3 contrib_rgb = film_color(spectral, contrib);
                        shadow.origin_x = origin.x;
                        shadow.origin_y = origin.y;
                        shadow.origin_z = origin.z;
                        shadow.dir_x = d.x;
                        shadow.dir_y = d.y;
                        shadow.dir_z = d.z;
                        shadow.t_max = t_max;
                        shadow.contrib_r = contrib_rgb.x;
                        shadow.contrib_g = contrib_rgb.y;
                        shadow.contrib_b = contrib_rgb.z;
                        push_shadow = t_max > 0.0f;
                    }
                }
            }

            BsdfSample bs = sample_bsdf(bsdf, wo_local, u.bsdf);
            vec3 wi = to_world(frame, bs.wi);
            if (bs.valid != 0u && (transmits ? may_leave_towards(wi, ng, bs.wi) : dot(wi, ng) > 0.0f)) {
                beta *= lift_color(spectral, bs.weight) * same_side_transmission_scale(bsdf, volume, wi, ng, bs.wi);
                if (dot(wi, ng) < 0.0f) {
                    medium = medium_beyond;
                    media = media_beyond;
                }
                bool survive = true;
                // Russian roulette (unbiased: survivors are divided by the survival probability).
                if ((params.flags & RENDER_RR) != 0u && segments >= params.rr_start_depth) {
                    float q = min(max_path_component(beta) * roulette_scale(medium) * params.rr_survival_scale, 0.95f);
                    survive = u.roulette < q;
                    beta /= q;
                }
                if (survive && max_path_component(beta) > 0.0f) {
                    vec3 origin = offset_ray_origin(s.p, s.p_error, ng, wi);
                    next.origin_x = origin.x;
                    next.origin_y = origin.y;
                    next.origin_z = origin.z;
                    next.dir_x = wi.x;
                    next.dir_y = wi.y;
                    next.dir_z = wi.z;
                    state.bsdf_pdf = bs.pdf;
                    push_ray = true;
                    if (effect_on(EFFECT_LIGHT_TREE))  // for the MIS weight of an emitter the ray hits
                        path_light_points[path] = pack_light_point(light_point.p, light_point.n, light_point.kind);
                    if (bdpt)
                        account_scattering(mis, abs(dot(wi, ng)), bs.pdf,
                                           pdf_next_direction(make_surface_bsdf(sp, wi), wi, wo));
                }
            }
        }
    }

    state.throughput_r = beta.x;
    state.throughput_g = beta.y;
    state.throughput_b = beta.z;
    state.radiance_r = radiance.x;
    state.radiance_g = radiance.y;
    state.radiance_b = radiance.z;
    state.rng = rng;
    store_path_state(path, state);
    if (effect_on(EFFECT_SPECTRAL)) {
        path_spectra[path].throughput_3 = beta.w;
        if (spectrum.flags != flags_before) path_spectra[path].flags = spectrum.flags;
    }
    if (tracks_media() && any(notEqual(media, media_before))) path_media[path] = media;
    if (bdpt) {
        store_path_mis(path, mis);  // one uvec4 store: dvcm and dvc, the rest as loaded
    }
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint parity = push.depth & 1u;
    bool push_ray = false, push_shadow = false;
    RayItem next;
    ShadowRayItem shadow;
    bool escaped = false;
    if (i < counters.ray_count[parity]) shade_vertex(i, parity, push_ray, next, push_shadow, shadow, escaped);
    // Every invocation of the workgroup gets here: the queues' slots are taken with one atomic per workgroup.
    uint ray_slot_index, shadow_slot;
    PUSH_VERTEX_RESULTS_IN_WORKGROUP(counters.ray_count[parity ^ 1u], push_ray, ray_slot_index, counters.shadow_count,
                                     push_shadow, shadow_slot, counters.escaped_rays, escaped);
    if (push_ray) store_ray_item(ray_slot(parity ^ 1u, ray_slot_index), next);
    // The next extend sorts its rays: each is binned here, where its origin and direction are at hand.
    if (ray_sort_built && push_ray && push.bin_pushed_rays != 0u)
        bin_ray(ray_slot_index, vec3(next.origin_x, next.origin_y, next.origin_z),
                vec3(next.dir_x, next.dir_y, next.dir_z));
    if (push_shadow) store_shadow_ray(shadow_slot, shadow);
}
