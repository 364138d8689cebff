// A surface point's BSDF as the stages that join subpaths see it (light_shade.comp, connect_subpaths.comp, and
// shade.comp's MIS densities for bidirectional path tracing): the point reloaded from a hit, the BSDF and shading frame
// path tracing builds for a viewer on a given side, and the light subpath's sampling of a next direction with its pdf.
// Reflection only: a scene with transmission is refused on the host (render/light_tracing.cpp).
#ifndef FH_SURFACE_BSDF_GLSL
#define FH_SURFACE_BSDF_GLSL
#include "bsdf_layers.glsl"
#include "sampling.glsl"

// A hit's surface with its material resolved (textures, normal maps, anisotropy) and placed by its instance.
struct ShadingPoint {
    SurfaceHit s;
    Material m;
    AnisotropyLayer anisotropy;
    uint triangle;
    float b1, b2;
};

ShadingPoint load_shading_point(uint triangle, float b1, float b2, uint instance) {
    ShadingPoint sp;
    sp.triangle = triangle;
    sp.b1 = b1;
    sp.b2 = b2;
    sp.s = load_surface(triangle, b1, b2);
    bool instanced = scene_has_instances && instance != INVALID_INDEX;
    Instance inst;
    if (instanced) {
        inst = load_instance(instance);
        if (inst.material != INVALID_INDEX) sp.s.material = inst.material;
    }
    sp.m = resolve_material(load_material(sp.s.material), triangle, b1, b2);
    sp.anisotropy.strength = 0.0f;
    sp.anisotropy.direction = vec3(0.0f);
    if (effect_on(EFFECT_ANISOTROPY)) {
        sp.anisotropy = eval_anisotropy_layer(sp.s.material, triangle, b1, b2, sp.s.ns);
        sp.s.ta = sp.anisotropy.direction;
    }
    sp.s.ns = apply_normal_texture(sp.m, triangle, b1, b2, sp.s.ns);
    sp.s.nc = apply_clearcoat_normal_texture(sp.s.material, triangle, b1, b2, sp.s.nc);
    if (instanced) sp.s = place_surface(sp.s, inst);
    return sp;
}

// A surface's BSDF and shading frame as shade.comp builds them for a viewer towards `eye`: the frame's normal is the
// shading normal on the eye's side (the geometric one where the shading normal faces away from the eye; kept so a
// mirror reflection stays above the surface where a normal texture tilts it), and the clear coat's normal too.
// Light tracing must evaluate the very function path tracing does, so the frame follows the eye-side direction of
// each evaluation, not the light's. `front`: the side of s.ng the directions are on; ng: the geometric normal there.
struct SurfaceBsdf {
    Frame frame;
    BsdfParams bsdf;
};

SurfaceBsdf make_surface_bsdf(ShadingPoint sp, bool front, vec3 ng, vec3 eye) {
    vec3 ns = front ? sp.s.ns : -sp.s.ns;
    if (dot(ns, eye) <= 0.0f) ns = ng;
    if (effect_on(EFFECT_NORMAL_TEXTURE) && sp.m.normal_texture != INVALID_INDEX)
        ns = keep_reflection_above_surface(ns, ng, eye);
    SurfaceBsdf b;
    b.frame = make_frame(ns);
    b.bsdf = add_bsdf_layers(make_bsdf_params(sp.m), sp.s, sp.triangle, sp.b1, sp.b2, b.frame, sp.anisotropy, front, ng,
                             eye);
    return b;
}

// f(eye, light) cos(light) in the frame b was built for.
vec3 eval_surface_bsdf(SurfaceBsdf b, vec3 eye, vec3 light) {
    return eval_bsdf(b.bsdf, to_local(b.frame, eye), to_local(b.frame, light));
}

// The solid-angle pdf with which path tracing's BSDF sampling, looking from `eye`, proposes `light`.
float pdf_surface_bsdf(SurfaceBsdf b, vec3 eye, vec3 light) {
    vec3 light_local = to_local(b.frame, light);
    return light_local.z > 0.0f ? pdf_bsdf(b.bsdf, to_local(b.frame, eye), light_local) : 0.0f;
}

// The next direction of a light subpath leaving towards the eye side, and its solid-angle pdf (0: none). Mostly the
// BSDF's own sampling as if the eye were towards the light. Where the shading normal differs from the facet's, the
// path tracer's BSDF seen from an eye below the shading normal's hemisphere (but above the facet) falls back to the
// facet's frame and reflects light there, which that sampling never proposes: a share FACET_SAMPLING_SHARE of the
// directions is then drawn cosine-weighted about the facet, so every direction with light is proposed (unbiased), and
// the pdf is the mixture's. A flat facet draws from the BSDF alone. `at_light`: the BSDF built for an eye towards wl.
const float FACET_SAMPLING_SHARE = 0.1f;

struct NextDirection {
    vec3 wi;
    float pdf;
};

// The mixture's pdf of proposing wi (the BSDF sampler proposes directions above its frame only).
float pdf_next_direction(SurfaceBsdf at_light, vec3 ng, vec3 wl, vec3 wi) {
    float facet_share = dot(at_light.frame.n, ng) < 1.0f ? FACET_SAMPLING_SHARE : 0.0f;
    return (1.0f - facet_share) * pdf_surface_bsdf(at_light, wl, wi) +
           facet_share * pdf_cosine_hemisphere(dot(wi, ng));
}

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
    next.pdf = pdf_next_direction(at_light, ng, wl, next.wi);
    return next;
}
#endif
