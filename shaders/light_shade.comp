// Stage "light_shade" (`--integrator light`): one light-subpath vertex per queued ray. Joins the vertex to the camera
// (t = 1: a splat through a shadow ray, when the full path keeps within --max-depth), samples the BSDF for the next
// segment, applies Russian roulette and pushes the continuation ray. Light carries importance's adjoint: the BSDF is
// evaluated with its arguments swapped (f(towards the eye side, towards the light)) and the shading normal's
// correction |wo.ng| / |wi.ng| of Veach 1997 (sec. 5.3) is applied, so a non-symmetric BSDF and interpolated normals
// stay unbiased. Reflection only: a scene with transmission is refused on the host (render/light_tracing.cpp).
// Reads: rays[queue depth & 1], hits, paths, triangles, materials, textures, instances. Writes: paths, rays[queue
// (depth + 1) & 1], shadow_rays, counters.ray_count / shadow_count.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/bindings.glsl"
#include "lib/queue.glsl"
#include "lib/rng.glsl"
#include "lib/sampling.glsl"
#include "lib/effects.glsl"
#include "lib/bsdf_layers.glsl"
#include "lib/motion.glsl"
#include "lib/light_tracing.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

// A surface's BSDF and shading frame as shade.comp builds them for a viewer towards `eye`: the frame's normal is the
// shading normal on the eye's side (the geometric one where the shading normal faces away from the eye; kept so a
// mirror reflection stays above the surface where a normal texture tilts it), and the clear coat's normal too.
// Light tracing must evaluate the very function path tracing does, so the frame follows the eye-side direction of
// each evaluation, not the light's.
struct SurfaceBsdf {
    Frame frame;
    BsdfParams bsdf;
};

SurfaceBsdf make_surface_bsdf(SurfaceHit s, Material m, uint triangle, float b1, float b2, AnisotropyLayer anisotropy,
                              bool front, vec3 ng, vec3 eye) {
    vec3 ns = front ? s.ns : -s.ns;
    if (dot(ns, eye) <= 0.0f) ns = ng;
    if (effect_on(EFFECT_NORMAL_TEXTURE) && m.normal_texture != INVALID_INDEX) ns = keep_reflection_above_surface(ns, ng, eye);
    SurfaceBsdf b;
    b.frame = make_frame(ns);
    b.bsdf = add_bsdf_layers(make_bsdf_params(m), s, triangle, b1, b2, b.frame, anisotropy, front, ng, eye);
    return b;
}

// The next direction of a light subpath leaving towards the eye side, and its solid-angle pdf (0: none). Mostly the
// BSDF's own sampling as if the eye were towards the light. Where the shading normal differs from the facet's, the
// path tracer's BSDF seen from an eye below the shading normal's hemisphere (but above the facet) falls back to the
// facet's frame and reflects light there, which that sampling never proposes: a share FACET_SAMPLING_SHARE of the
// directions is then drawn cosine-weighted about the facet, so every direction with light is proposed (unbiased), and
// the pdf is the mixture's. A flat facet draws from the BSDF alone.
const float FACET_SAMPLING_SHARE = 0.1f;

struct NextDirection {
    vec3 wi;
    float pdf;
};

NextDirection sample_next_direction(SurfaceBsdf at_light, vec3 ng, vec3 wl, vec3 u) {
    NextDirection next;
    next.wi = ng;
    next.pdf = 0.0f;
    vec3 wl_local = to_local(at_light.frame, wl);
    bool tilted = dot(at_light.frame.n, ng) < 1.0f;
    float facet_share = tilted ? FACET_SAMPLING_SHARE : 0.0f;
    if (u.x < facet_share) {
        vec3 local = sample_cosine_hemisphere(u.yz);
        if (!(local.z > 0.0f)) return next;
        next.wi = to_world(make_frame(ng), local);
    } else {
        u.x = min((u.x - facet_share) / (1.0f - facet_share), 0.99999994f);
        BsdfSample bs = sample_bsdf(at_light.bsdf, wl_local, u);
        if (bs.valid == 0u) return next;
        next.wi = to_world(at_light.frame, bs.wi);
        if (!tilted) {
            next.pdf = bs.pdf;
            return next;
        }
    }
    // The mixture's pdf: the BSDF sampler proposes directions above its frame only.
    vec3 wi_local = to_local(at_light.frame, next.wi);
    float bsdf_pdf = wi_local.z > 0.0f ? pdf_bsdf(at_light.bsdf, wl_local, wi_local) : 0.0f;
    next.pdf = (1.0f - facet_share) * bsdf_pdf + facet_share * pdf_cosine_hemisphere(dot(next.wi, ng));
    return next;
}

// f(eye, light) cos(light) in the frame b was built for.
vec3 eval_surface_bsdf(SurfaceBsdf b, vec3 eye, vec3 light) {
    return eval_bsdf(b.bsdf, to_local(b.frame, eye), to_local(b.frame, light));
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint parity = push.depth & 1u;
    if (i >= counters.ray_count[parity]) return;
    RayItem ray = rays[ray_slot(parity, i)];
    HitItem hit = hits[i];
    uint path = ray.path;
    PathState state = paths[path];
    vec3 beta = vec3(state.throughput_r, state.throughput_g, state.throughput_b);
    uint rng = state.rng;
    uint segments = push.depth + 1u;  // segments of the light subpath up to this vertex

    bool push_shadow = false;
    bool push_ray = false;
    ShadowRayItem shadow;
    RayItem next;
    next.path = path;
    next.origin_triangle = hit.triangle;

    if (hit.triangle != INVALID_INDEX && max_value(beta) > 0.0f) {
        vec3 wl = -vec3(ray.dir_x, ray.dir_y, ray.dir_z);  // towards the light
        SurfaceHit s = load_surface(hit.triangle, hit.b1, hit.b2);
        bool instanced = scene_has_instances && hit.instance != INVALID_INDEX;
        Instance inst;
        if (instanced) {
            inst = load_instance(hit.instance);
            if (inst.material != INVALID_INDEX) s.material = inst.material;
        }
        Material m = resolve_material(load_material(s.material), hit.triangle, hit.b1, hit.b2);
        AnisotropyLayer anisotropy;
        anisotropy.strength = 0.0f;
        anisotropy.direction = vec3(0.0f);
        if (effect_on(EFFECT_ANISOTROPY)) {
            anisotropy = eval_anisotropy_layer(s.material, hit.triangle, hit.b1, hit.b2, s.ns);
            s.ta = anisotropy.direction;
        }
        s.ns = apply_normal_texture(m, hit.triangle, hit.b1, hit.b2, s.ns);
        s.nc = apply_clearcoat_normal_texture(s.material, hit.triangle, hit.b1, hit.b2, s.nc);
        if (instanced) s = place_surface(s, inst);
        bool front = dot(s.ng, wl) > 0.0f;  // reflection only: every direction here is on wl's side
        vec3 ng = front ? s.ng : -s.ng;
        // Proposal for the next direction: the BSDF as if the eye were towards the light.
        SurfaceBsdf at_light = make_surface_bsdf(s, m, hit.triangle, hit.b1, hit.b2, anisotropy, front, ng, wl);
        float cos_light_g = dot(wl, ng);  // 0 only for a ray in the facet's plane: the vertex then sends nothing

        // t = 1: the camera sees this vertex; the full path has one segment more than the subpath.
        if (cos_light_g > 0.0f && (params.max_depth == 0u || segments + 1u <= params.max_depth)) {
            FilmSplat splat = project_to_film(s.p);
            float cos_camera_g = dot(splat.to_camera, ng);
            if (splat.valid && cos_camera_g > 0.0f) {
                SurfaceBsdf at_camera =
                    make_surface_bsdf(s, m, hit.triangle, hit.b1, hit.b2, anisotropy, front, ng, splat.to_camera);
                vec3 f = eval_surface_bsdf(at_camera, splat.to_camera, wl);  // f(camera, light) cos_light
                vec3 contrib = beta * f * (cos_camera_g / cos_light_g * splat.importance);
                if (max_value(contrib) > 0.0f) {
                    shadow = make_splat_ray(s.p, s.p_error, ng, splat, contrib, hit.triangle);
                    push_shadow = true;
                }
            }
        }

        // The next segment, if a path through it can still reach the camera within --max-depth.
        vec3 u_bsdf = vec3(next_float(rng), next_float(rng), next_float(rng));
        float u_roulette = next_float(rng);
        if (cos_light_g > 0.0f && (params.max_depth == 0u || segments + 1u < params.max_depth)) {
            NextDirection next_dir = sample_next_direction(at_light, ng, wl, u_bsdf);
            vec3 wi = next_dir.wi;
            float cos_next_g = dot(wi, ng);
            if (next_dir.pdf > 0.0f && cos_next_g > 0.0f) {
                // Adjoint: f(next, light) cos_light as the path tracer's frame from `next` sees it, over the
                // proposal's pdf, with the shading-normal correction.
                SurfaceBsdf at_next = make_surface_bsdf(s, m, hit.triangle, hit.b1, hit.b2, anisotropy, front, ng, wi);
                beta *= eval_surface_bsdf(at_next, wi, wl) * (cos_next_g / (cos_light_g * next_dir.pdf));
                bool survive = true;
                // Russian roulette on the throughput relative to what the subpath carried from the light.
                if ((params.flags & RENDER_RR) != 0u && segments >= params.rr_start_depth) {
                    float q = min(max_value(beta) / state.bsdf_pdf, 0.95f);
                    survive = u_roulette < q;
                    beta /= q;
                }
                if (survive && max_value(beta) > 0.0f) {
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
    paths[path] = state;

    uint slot;
    PUSH_TO_QUEUE(counters.ray_count[parity ^ 1u], push_ray, slot);
    if (push_ray) rays[ray_slot(parity ^ 1u, slot)] = next;
    PUSH_TO_QUEUE(counters.shadow_count, push_shadow, slot);
    if (push_shadow) shadow_rays[slot] = shadow;
}
