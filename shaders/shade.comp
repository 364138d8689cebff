// Stage "shade": one path vertex per queued ray. Adds emission seen by the ray, or the environment's radiance
// when it escaped (both MIS-weighted against light sampling), resolves the material (textures, vertex colours,
// normal map, anisotropy, thin film, glass, dispersion, diffuse transmission, sheen, clear coat, unlit: only the
// effects the scene has are compiled in), samples a light and pushes a shadow ray (next-event estimation), samples the
// BSDF, applies Russian roulette and pushes the continuation ray. A spectral render (EFFECT_SPECTRAL) carries four
// wavelengths per path and hands the film RGB (lib/spectral/path_color.glsl).
// Reads: rays[queue depth & 1], hits, paths, triangles, materials, emitters, textures, environment, and for
// glass, sheens and clear coats the material layers, path media and path spectra. Writes: paths, path media, path
// spectra, rays[queue (depth + 1) & 1], shadow_rays, counters.ray_count / shadow_count.
// The steps: load the path, the light of an escaped ray, what a hit shows and emits, the BSDF, next-event estimation,
// scattering with Russian roulette, store the path.
// With `--aov` it also records the path's AOVs (lib/core/aov.glsl; writes path_aovs); with `--adaptive` it counts the
// path's work (lib/core/wave_pixels.glsl; path_work).
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
#include "lib/core/aov.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

float max_component(vec3 v) { return max(v.x, max(v.y, v.z)); }

// A path at the vertex being shaded: what is loaded from paths and their side buffers and stored back at the end.
struct PathVertex {
    uint path;
    PathState state;
    vec4 beta;               // throughput; w: a spectral path's fourth wavelength
    vec3 radiance;
    uint rng;
    PathSpectrum spectrum;   // a spectral path's wavelengths (layout.h PathSpectrum)
    SpectralFrame spectral;
    uint segments;           // segments of this path including the ray just traced
    PathMis mis;             // BDPT's quantities of the camera subpath
    float dvm;               // and vcm's third (lib/integrator/bdpt.glsl)
    uvec4 media;             // the volumes the path is in, innermost first
    uint medium;
};

// Step 0: the path's state, and Beer-Lambert along the segment just traced inside an absorbing volume.
PathVertex load_path_vertex(uint path, HitItem hit) {
    PathVertex v;
    v.path = path;
    v.state = load_path_state(path);
    v.beta = vec4(v.state.throughput_r, v.state.throughput_g, v.state.throughput_b, 0.0f);
    v.radiance = vec3(v.state.radiance_r, v.state.radiance_g, v.state.radiance_b);
    v.rng = v.state.rng;
    if (effect_on(EFFECT_SPECTRAL)) {
        v.spectrum = path_spectra[path];
        v.beta.w = v.spectrum.throughput_3;
        v.spectral = make_spectral_frame(v.spectrum.wavelength_u);
    }
    v.segments = push.depth + 1u;
    if (bdpt) v.mis = load_path_mis(path);
    v.dvm = vcm ? path_dvm[path] : 0.0f;
    v.media = tracks_media() ? path_media[path] : uvec4(INVALID_INDEX);
    v.medium = v.media.x;
    if (effect_on(EFFECT_ABSORPTION))
        v.beta *= eval_path_medium_transmittance(v.spectral, v.medium,
                                                 hit.triangle == INVALID_INDEX ? uintBitsToFloat(0x7f800000u) : hit.t);
    return v;
}

// Step 1, a ray that escaped: the environment's radiance, weighted against NEE's sampling of the environment.
void add_escaped_light(inout PathVertex v, vec3 dir) {
    float weight = 1.0f;
    if ((params.flags & RENDER_NEE) != 0u && v.state.bsdf_pdf > 0.0f && params.env_pick_pdf > 0.0f)
        weight = (params.flags & RENDER_MIS) != 0u
                     ? power_heuristic(v.state.bsdf_pdf, params.env_pick_pdf * pdf_environment(dir))
                     : 0.0f;
    if (bdpt_weighs(v.segments))
        weight = weight_strategy(0u, v.segments + 1u, v.segments == 1u ? 1.0f : weight_environment_hit(
            v.mis, params.env_pick_pdf * pdf_environment(dir),
            (effect_on(EFFECT_LIGHT_TREE) ? params.env_emission_pick_pdf : params.env_pick_pdf) * pdf_environment(dir)));
    v.radiance += film_color(v.spectral, v.beta * lift_color(v.spectral, eval_environment(dir))) * weight *
                  escape_scale(v.medium);
}

// Step 2, a ray that hit: what the surface shows the camera (unlit) and emits. Paths that could also have sampled
// this light by NEE are weighted by the power heuristic (Veach 1997, eq. 9.13); with NEE on and MIS off, only NEE
// counts light from surfaces.
void add_emission(inout PathVertex v, ShadingPoint sp, HitItem hit, vec3 wo, bool unlit, bool front,
                  bool double_sided) {
    SurfaceHit s = sp.s;
    if (unlit && push.depth == 0u)  // BDPT: s = 0 alone makes it (--bdpt-strategy keeps it with (0,2) only)
        v.radiance += film_color(v.spectral, v.beta * lift_color(v.spectral, max(vec3(sp.m.base_color), vec3(0.0f)))) *
                      (bdpt ? weight_strategy(0u, 2u, 1.0f) : 1.0f);
    vec3 emission = sp.m.emission.xyz;
    if (effect_on(EFFECT_EMISSIVE_TRIANGLES) && (front || double_sided) && max_component(emission) > 0.0f) {
        float weight = 1.0f;
        bool nee = (params.flags & RENDER_NEE) != 0u && v.state.bsdf_pdf > 0.0f;
        bool mis = nee && (params.flags & RENDER_MIS) != 0u;
        float cos_light = abs(dot(s.ng, wo));
        // NEE's density of this point from the vertex the ray left (a camera ray's: none), per solid angle: the
        // table's, or the tree's as NEE there would have walked it (walked only where a weight reads it).
        float light_pdf = s.light_pdf_area * hit.t * hit.t / cos_light;
        if (effect_on(EFFECT_LIGHT_TREE) && v.segments > 1u && (mis || bdpt_weighs(v.segments)))
            light_pdf = tree_emitter_hit_pdf(unpack_light_point(path_light_points[v.path]), hit.triangle,
                                             s.light_entry, hit.t, cos_light);
        if (nee) weight = mis ? power_heuristic(v.state.bsdf_pdf, light_pdf) : 0.0f;
        if (bdpt_weighs(v.segments)) {
            float direct_pdf_area = effect_on(EFFECT_LIGHT_TREE) ? light_pdf * cos_light / (hit.t * hit.t)
                                                                  : s.light_pdf_area;
            weight = weight_strategy(0u, v.segments + 1u, v.segments == 1u ? 1.0f
                                     : weight_emission_hit(v.mis, direct_pdf_area, s.light_pdf_area, cos_light,
                                                           double_sided));
        }
        v.radiance += film_color(v.spectral, v.beta * lift_color(v.spectral, emission)) * weight;
    }
}

// A surface that scatters, as path tracing sees it from wo: the shading frame, the BSDF and the volumes across it.
struct Scattering {
    vec3 ng;               // the geometric normal on wo's side
    Frame frame;           // around the shading normal on wo's side
    vec3 wo_local;
    BsdfParams bsdf;
    bool volume;
    bool transmits;        // a lobe sends light through the surface
    uvec4 media_beyond;    // the volumes across the surface
    uint medium_beyond;
    LightTreePoint light_point;  // where NEE stands
};

// Step 3: the BSDF at the point for a viewer along wo. Dispersion (KHR_materials_dispersion) where light refracts into
// a volume gives the whole BSDF the hero wavelength's index, and stops the path's other wavelengths (their
// directions would differ).
Scattering make_scattering(inout PathVertex v, inout ShadingPoint sp, vec3 wo, bool front) {
    SurfaceHit s = sp.s;
    Scattering sc;
    // Both normals on the side the ray came from (z of the local frame).
    sc.ng = front ? s.ng : -s.ng;
    vec3 ns = front ? s.ns : -s.ns;
    // Interpolated normals can face away from a grazing viewer although the surface faces it; the
    // BSDF would then return black (black facets at silhouettes). Shade such points with the
    // geometric normal (tests/README.md "Numerical stability", case 8).
    if (dot(ns, wo) <= 0.0f) ns = sc.ng;
    // Glass (KHR_materials_transmission): thin-walled, or the surface of a volume, entered from the front.
    sc.volume = sp.volume;
    float transmission = sp.transmission;
    // A mirror reflection about the shading normal must stay above the geometric surface, or the path dies
    // there: normal textures tilt it that far anywhere, and interpolated normals at the curved rims of thin
    // glass, where light guided along the wall by total internal reflection meets it at every bounce
    // (shaders/lib/bsdf/README.md "Glass", "Interpolated normals on glass": 15% of a vase's light was lost so).
    if ((effect_on(EFFECT_NORMAL_TEXTURE) && sp.m.normal_texture != INVALID_INDEX) ||
        (effect_on(EFFECT_TRANSMISSION) && transmission > 0.0f))
        ns = keep_reflection_above_surface(ns, sc.ng, wo);
    sc.frame = make_frame(ns);
    sc.wo_local = to_local(sc.frame, wo);
    // The volumes across the surface: entering one (inside another, nested) or leaving back into the outer.
    sc.media_beyond = sc.volume ? (front ? enter_medium(v.media, s.material) : leave_medium(v.media, s.material))
                                : v.media;
    if (disperse_at(sp, v.spectral.lambda.x) && (v.spectrum.flags & PATH_SECONDARIES_TERMINATED) == 0u) {
        v.beta = terminate_secondary_wavelengths(v.beta);
        v.spectrum.flags |= PATH_SECONDARIES_TERMINATED;
    }
    sc.bsdf = make_bsdf_params(sp.m);
    float eta = sp.m.ior;  // n beyond / n on this side (lib/material/transmission.glsl); thin-walled: the ior
    if (effect_on(EFFECT_TRANSMISSION)) {
        if (sc.volume) eta = refraction_eta_at(s.material, sp.m.ior, v.media, front);
        sc.bsdf = with_transmission(sc.bsdf, transmission, eta, sc.volume ? 0u : 1u);
    }
    sc.bsdf = add_bsdf_layers(sc.bsdf, s, sp.triangle, sp.b1, sp.b2, sc.frame, sp.anisotropy, front, sc.ng, wo);
    sc.transmits = has_transmission_lobe(sc.bsdf);
    sc.medium_beyond = sc.media_beyond.x;
    // BDPT's reverse densities: the light subpath's sampler arriving along a direction.
    if (bdpt) sp.eta_front = !sc.volume ? 1.0f : front ? eta : 1.0f / max(eta, 1.0e-4f);
    // Where NEE stands; the light tree also bounds by the normal on the side the path came from.
    sc.light_point.p = s.p;
    sc.light_point.n = sc.ng;
    sc.light_point.kind = LIGHT_POINT_NO_NORMAL;
    if (effect_on(EFFECT_LIGHT_TREE))
        sc.light_point = make_light_point(s.p, sc.ng, sc.transmits ? LIGHT_POINT_TWO_SIDED : LIGHT_POINT_ONE_SIDED);
    return sc;
}

// Step 4, next-event estimation: a light sample, its contribution weighted against BSDF sampling, and the shadow ray
// connect traces for it. True when there is a shadow ray to push.
bool sample_light(PathVertex v, ShadingPoint sp, Scattering sc, vec3 wo, VertexSamples u, inout ShadowRayItem shadow) {
    if ((params.flags & RENDER_NEE) == 0u || params.emitter_count == 0u) return false;
    SurfaceHit s = sp.s;
    LightConnection light = sample_light_connection(sc.light_point, u.pick, u.light);
    vec3 wi = light.wi;
    if (light.valid == 0u || !(sc.transmits || dot(wi, sc.ng) > 0.0f)) return false;
    vec3 wi_local = to_local(sc.frame, wi);
    vec3 f = !sc.transmits ? eval_bsdf(sc.bsdf, sc.wo_local, wi_local)
             : may_leave_towards(wi, sc.ng, wi_local)
                 ? eval_bsdf(sc.bsdf, sc.wo_local, wi_local) *
                       same_side_transmission_scale(sc.bsdf, sc.volume, wi, sc.ng, wi_local)
                 : vec3(0.0f);
    float weight = (params.flags & RENDER_MIS) != 0u && light.delta == 0u
                       ? power_heuristic(light.pdf, pdf_bsdf(sc.bsdf, sc.wo_local, wi_local))
                       : 1.0f;
    if (bdpt_weighs(v.segments + 1u))
        weight = weight_strategy(1u, v.segments + 1u, weight_light_connection(
            v.mis, light.delta == 0u ? pdf_bsdf(sc.bsdf, sc.wo_local, wi_local) : 0.0f, light.pdf,
            light.emission_over_direct, abs(dot(wi, sc.ng)),
            pdf_next_direction(make_surface_bsdf(sp, wi), wi, wo)));
    vec4 contrib = v.beta * lift_color(v.spectral, f) * lift_color(v.spectral, light.radiance_over_pdf) * weight;
    if (!(max_path_component(contrib) > 0.0f)) return false;
    vec3 origin = offset_ray_origin(s.p, s.p_error, sc.ng, wi);
    vec3 d = wi;
    float t_max = 3.0e38f;  // directional light: nothing beyond the scene can block it
    if (light.at_infinity == 0u) {
        d = light.target - origin;
        float len = length(d);
        d /= len;
        t_max = len * (1.0f - 1e-4f);  // pbrt's ShadowEpsilon
    }
    uint shadow_medium = dot(wi, sc.ng) < 0.0f ? sc.medium_beyond : v.medium;
    if (effect_on(EFFECT_ABSORPTION))
        contrib *= eval_path_medium_transmittance(
            v.spectral, shadow_medium, light.at_infinity != 0u ? uintBitsToFloat(0x7f800000u) : t_max);
    if (light.at_infinity != 0u) contrib *= escape_scale(shadow_medium);
    vec3 contrib_rgb = film_color(v.spectral, contrib);
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
    return t_max > 0.0f;
}

// Step 5, scattering: a direction from the BSDF, the throughput it carries, Russian roulette (unbiased: survivors
// are divided by the survival probability) and the continuation ray. True when there is a ray to push.
bool scatter(inout PathVertex v, ShadingPoint sp, Scattering sc, vec3 wo, VertexSamples u, inout RayItem next) {
    SurfaceHit s = sp.s;
    BsdfSample bs = sample_bsdf(sc.bsdf, sc.wo_local, u.bsdf);
    vec3 wi = to_world(sc.frame, bs.wi);
    if (bs.valid == 0u || !(sc.transmits ? may_leave_towards(wi, sc.ng, bs.wi) : dot(wi, sc.ng) > 0.0f)) return false;
    v.beta *= lift_color(v.spectral, bs.weight) * same_side_transmission_scale(sc.bsdf, sc.volume, wi, sc.ng, bs.wi);
    if (dot(wi, sc.ng) < 0.0f) {
        v.medium = sc.medium_beyond;
        v.media = sc.media_beyond;
    }
    bool survive = true;
    if ((params.flags & RENDER_RR) != 0u && v.segments >= params.rr_start_depth) {
        float q = min(max_path_component(v.beta) * roulette_scale(v.medium) * params.rr_survival_scale, 0.95f);
        survive = u.roulette < q;
        v.beta /= q;
    }
    if (!survive || !(max_path_component(v.beta) > 0.0f)) return false;
    vec3 origin = offset_ray_origin(s.p, s.p_error, sc.ng, wi);
    next.origin_x = origin.x;
    next.origin_y = origin.y;
    next.origin_z = origin.z;
    next.dir_x = wi.x;
    next.dir_y = wi.y;
    next.dir_z = wi.z;
    v.state.bsdf_pdf = bs.pdf;
    if (effect_on(EFFECT_LIGHT_TREE))  // for the MIS weight of an emitter the ray hits
        path_light_points[v.path] = pack_light_point(sc.light_point.p, sc.light_point.n, sc.light_point.kind);
    if (bdpt) {
        float reverse = pdf_next_direction(make_surface_bsdf(sp, wi), wi, wo);
        if (vcm) v.dvm = scattered_dvm(v.dvm, v.mis, abs(dot(wi, sc.ng)), bs.pdf, reverse);
        account_scattering(v.mis, abs(dot(wi, sc.ng)), bs.pdf, reverse);
    }
    return true;
}

// Step 6: the path's state back to its buffers (the side buffers only where they changed).
void store_path_vertex(PathVertex v, uint spectrum_flags_before, uvec4 media_before) {
    v.state.throughput_r = v.beta.x;
    v.state.throughput_g = v.beta.y;
    v.state.throughput_b = v.beta.z;
    v.state.radiance_r = v.radiance.x;
    v.state.radiance_g = v.radiance.y;
    v.state.radiance_b = v.radiance.z;
    v.state.rng = v.rng;
    store_path_state(v.path, v.state);
    if (effect_on(EFFECT_SPECTRAL)) {
        path_spectra[v.path].throughput_3 = v.beta.w;
        if (v.spectrum.flags != spectrum_flags_before) path_spectra[v.path].flags = v.spectrum.flags;
    }
    if (tracks_media() && any(notEqual(v.media, media_before))) path_media[v.path] = v.media;
    if (bdpt) store_path_mis(v.path, v.mis);  // one uvec4 store: dvcm and dvc, the rest as loaded
    if (vcm) path_dvm[v.path] = v.dvm;
}

// The path vertex of queued ray i, in the steps above: what it pushes to the next extend queue and to connect's
// shadow queue.
void shade_vertex(uint i, uint parity, out bool push_ray, out RayItem next, out bool push_shadow,
                  out ShadowRayItem shadow, out bool escaped) {
    RayItem ray = load_ray_item(ray_slot(parity, i));
    HitItem hit = load_hit_item(i);
    escaped = hit.triangle == INVALID_INDEX;  // counted here for --stats: in extend it took a second atomic
    PathVertex v = load_path_vertex(ray.path, hit);
    uint spectrum_flags_before = effect_on(EFFECT_SPECTRAL) ? v.spectrum.flags : 0u;
    uvec4 media_before = v.media;
    push_shadow = false;
    push_ray = false;
    next.path = v.path;
    next.origin_triangle = hit.triangle;
    shadow.path = v.path;
    shadow.origin_triangle = hit.triangle;
    vec3 dir = vec3(ray.dir_x, ray.dir_y, ray.dir_z);

    if (hit.triangle == INVALID_INDEX && effect_on(EFFECT_ENVIRONMENT)) add_escaped_light(v, dir);
    if (aovs_on && hit.triangle == INVALID_INDEX) record_aovs(v.path, push.depth, false, 0.0f, true, vec3(0.0f), vec3(0.0f));
    if (hit.triangle != INVALID_INDEX) {
        vec3 wo = -dir;
        // The shading point as the light subpaths' stages build it (lib/bsdf/surface_bsdf.glsl), in two halves: a
        // vertex that cannot scatter skips what only scattering reads. KHR_materials_unlit: camera rays see the base
        // colour (times its texture and COLOR_0); every other ray finds a black surface that ends the path
        // (shaders/lib/bsdf/README.md "Unlit").
        Instance inst;
        // The path's shutter time places a moving instance; a hit on the world's own triangles never reads it.
        float time = scene_has_instances && hit.instance != INVALID_INDEX ? load_path_time(v.path) : 0.5f;
        ShadingPoint sp = begin_shading_point(hit.triangle, hit.b1, hit.b2, hit.instance, time, inst);
        bool unlit = effect_on(EFFECT_UNLIT) && (sp.m.flags & MATERIAL_UNLIT) != 0u;
        bool may_extend = !unlit && (params.max_depth == 0u || v.segments < params.max_depth);
        finish_shading_point(sp, hit.instance, inst, may_extend);
        bool front = dot(sp.s.ng, wo) > 0.0f;
        bool double_sided = (sp.m.flags & MATERIAL_DOUBLE_SIDED) != 0u;
        if (bdpt) account_segment(v.mis, hit.t, abs(dot(sp.s.ng, wo)), camera_segment_has_distance(v.segments));
        if (vcm) v.dvm = segment_dvm(v.dvm, abs(dot(sp.s.ng, wo)));
        add_emission(v, sp, hit, wo, unlit, front, double_sided);
        vec3 albedo = clamp(sp.m.base_color.rgb, vec3(0.0f), vec3(1.0f));
        if (aovs_on && !may_extend)
            record_aovs(v.path, push.depth, true, hit.t, false, albedo, front ? sp.s.ns : -sp.s.ns);
        if (may_extend) {
            Scattering sc = make_scattering(v, sp, wo, front);
            if (aovs_on) record_aovs(v.path, push.depth, true, hit.t, aovs_see_through(sc.bsdf), albedo, sc.frame.n);
            VertexSamples u = draw_vertex_samples(v.path, push.depth, v.rng);
            push_shadow = sample_light(v, sp, sc, wo, u, shadow);
            push_ray = scatter(v, sp, sc, wo, u, next);
        }
    }
    store_path_vertex(v, spectrum_flags_before, media_before);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint parity = push.depth & 1u;
    bool push_ray = false, push_shadow = false;
    RayItem next;
    ShadowRayItem shadow;
    bool escaped = false;
    if (i < counters.ray_count[parity]) {
        shade_vertex(i, parity, push_ray, next, push_shadow, shadow, escaped);
        if (pixel_list_on)
            path_work[next.path] +=
                (escaped ? PATH_WORK_ESCAPE : PATH_WORK_HIT) + (push_shadow ? PATH_WORK_SHADOW_RAY : 0u);
    }
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
