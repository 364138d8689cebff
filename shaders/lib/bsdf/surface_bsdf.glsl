// A surface point's BSDF as the stages that join subpaths see it (light_shade.comp, connect_subpaths.comp, and
// shade.comp's MIS densities for bidirectional path tracing): the point reloaded from a hit, the BSDF and shading frame
// path tracing builds for a viewer on a given side, and the light subpath's sampling of a next direction with its pdf.
// Glass and diffuse transmission included: a direction may cross the surface, and each evaluation builds the BSDF for
// the side its eye-side direction is on.
#ifndef FH_SURFACE_BSDF_GLSL
#define FH_SURFACE_BSDF_GLSL
#include "lib/bsdf/bsdf_layers.glsl"
#include "lib/sampling/sampling.glsl"
#include "lib/material/transmission.glsl"
#include "lib/geometry/motion.glsl"
#include "lib/spectral/spectrum.glsl"

// Whether direction w (local frame: w_local) may leave here. A reflection (w_local.z > 0) must stay above the
// geometric surface ng, or light leaks through it. A transmission (w_local.z < 0) below it crosses the surface; one
// that stays above it (the interpolated normal tilts the shading frame away from the facet, at rims and silhouettes)
// continues on wo's side without crossing, as Cycles lets it (shaders/lib/bsdf/README.md "Glass", "Interpolated normals on glass").
bool may_leave_towards(vec3 w, vec3 ng, vec3 w_local) {
    float g = dot(w, ng);
    return g != 0.0f && (w_local.z < 0.0f || g > 0.0f);
}

// What a transmission that stays on wo's side is multiplied by: the glass lobe's 1 / eta^2 converts between the
// radiance of the two sides, and such a path never reaches the other side, so it is taken back (eta^2). Diffuse
// transmission is thin-walled and has no such factor; with both lobes on one surface the path keeps the factor
// (darker, never brighter).
float same_side_transmission_scale(BsdfParams bsdf, bool volume, vec3 w, vec3 ng, vec3 w_local) {
    if (!volume || has_diffuse_transmission(bsdf) || !(w_local.z < 0.0f) || !(dot(w, ng) > 0.0f)) return 1.0f;
    return bsdf.glass.eta * bsdf.glass.eta;
}

// A hit's surface with its material resolved (textures, normal maps, anisotropy) and placed by its instance.
struct ShadingPoint {
    SurfaceHit s;
    Material m;
    AnisotropyLayer anisotropy;
    uint triangle;
    float b1, b2;
    float transmission;  // KHR_materials_transmission's share at the point (0 without)
    bool volume;         // the mesh bounds a volume (KHR_materials_volume): it refracts by the indices of its sides
    float eta_front;     // a volume's n behind the front face (against s.ng) / n in front of it (set_media)
};

// The first half of a shading point, what every vertex needs: the surface at a hit and its material, the instance
// placed at the path's shutter time (motion blur; 0.5 without). `inst` is the placed instance, for
// finish_shading_point.
ShadingPoint begin_shading_point(uint triangle, float b1, float b2, uint instance, float time, out Instance inst) {
    ShadingPoint sp;
    sp.triangle = triangle;
    sp.b1 = b1;
    sp.b2 = b2;
    sp.s = load_surface(triangle, b1, b2);  // object space for an instance
    if (scene_has_instances && instance != INVALID_INDEX) {
        inst = move_instance(load_instance(instance), time);
        if (inst.material != INVALID_INDEX) sp.s.material = inst.material;
    }
    sp.m = resolve_material(load_material(sp.s.material), triangle, b1, b2);
    return sp;
}

// The second half: the anisotropy's direction (in the mesh's tangent frame, before the instance places it), normal
// textures, the surface placed by its instance, and the transmission. A point that does not scatter (an unlit
// surface, or the last vertex --max-depth allows) skips what only scattering reads: the anisotropy and the glass.
void finish_shading_point(inout ShadingPoint sp, uint instance, Instance inst, bool scatters) {
    sp.anisotropy.strength = 0.0f;
    sp.anisotropy.direction = vec3(0.0f);
    if (effect_on(EFFECT_ANISOTROPY) && scatters) {
        sp.anisotropy = eval_anisotropy_layer(sp.s.material, sp.triangle, sp.b1, sp.b2, sp.s.ns);
        sp.s.ta = sp.anisotropy.direction;
    }
    sp.s.ns = apply_normal_texture(sp.m, sp.triangle, sp.b1, sp.b2, sp.s.ns);
    sp.s.nc = apply_clearcoat_normal_texture(sp.s.material, sp.triangle, sp.b1, sp.b2, sp.s.nc);
    if (scene_has_instances && instance != INVALID_INDEX) sp.s = place_surface(sp.s, inst);
    sp.transmission = scatters ? eval_transmission(sp.s.material, sp.triangle, sp.b1, sp.b2) : 0.0f;
    sp.volume = scatters && effect_on(EFFECT_TRANSMISSION) && encloses_volume(sp.s.material);
    sp.eta_front = 1.0f;
}

// The whole shading point of a vertex that scatters, as the stages joining subpaths load it, with a moving instance
// placed at the path's shutter time (shade.comp builds its points with the same two halves).
ShadingPoint load_shading_point(uint triangle, float b1, float b2, uint instance, float time) {
    Instance inst;
    ShadingPoint sp = begin_shading_point(triangle, b1, b2, instance, time, inst);
    finish_shading_point(sp, instance, inst, true);
    return sp;
}

// KHR_materials_dispersion (EFFECT_SPECTRAL): a dispersive volume that light can pass into refracts by its index at
// the hero wavelength `lambda`, which the point takes here (before set_media); true where it does, and the path's
// other wavelengths must then stop (terminate_secondary_wavelengths: their directions would differ).
bool disperse_at(inout ShadingPoint sp, float lambda) {
    if (!effect_on(EFFECT_SPECTRAL) || !sp.volume || !(sp.transmission > 0.0f)) return false;
    float dispersion = load_material_layers(sp.s.material).dispersion;
    if (!(dispersion > 0.0f)) return false;
    sp.m.ior = eval_dispersive_ior(sp.m.ior, dispersion, lambda);
    return true;
}

// The volumes around a point: `media`, the stack of the subpath arriving on the side `front` of s.ng (path_media).
void set_media(inout ShadingPoint sp, uvec4 media, bool front) {
    if (!sp.volume) return;
    float eta = refraction_eta_at(sp.s.material, sp.m.ior, media, front);
    sp.eta_front = front ? eta : 1.0f / max(eta, 1.0e-4f);
}

// The volumes across the surface from a subpath in `media` on the side `front`: it enters the point's volume, or
// leaves it for the outer ones.
uvec4 media_across(ShadingPoint sp, uvec4 media, bool front) {
    if (!sp.volume) return media;
    return front ? enter_medium(media, sp.s.material) : leave_medium(media, sp.s.material);
}

// The volume a segment leaving the point along w travels in, for a subpath in `media` on the side `front`.
uint medium_towards(ShadingPoint sp, uvec4 media, bool front, vec3 w) {
    return (dot(w, sp.s.ng) > 0.0f) == front ? media.x : media_across(sp, media, front).x;
}

// A surface's BSDF and shading frame as shade.comp builds them for a viewer towards `eye`: the frame's normal is the
// shading normal on the eye's side (the geometric one where the shading normal faces away from the eye; kept so a
// mirror reflection stays above the surface where a normal texture or glass tilts it), and the clear coat's normal
// too; glass refracts by the indices as seen from the eye's side. Light tracing must evaluate the very function path
// tracing does, so the frame follows the eye-side direction of each evaluation, not the light's.
struct SurfaceBsdf {
    Frame frame;
    BsdfParams bsdf;
    vec3 ng;        // the geometric normal on the eye's side
    bool volume;
    bool transmits; // a lobe sends light through the surface
    bool tilted;    // the shading normal differs from the facet's (sample_next_direction)
};

SurfaceBsdf make_surface_bsdf(ShadingPoint sp, vec3 eye) {
    bool front = dot(sp.s.ng, eye) > 0.0f;
    vec3 ng = front ? sp.s.ng : -sp.s.ng;
    vec3 ns_side = front ? sp.s.ns : -sp.s.ns;
    vec3 ns = ns_side;
    if (dot(ns, eye) <= 0.0f) ns = ng;
    bool glass = effect_on(EFFECT_TRANSMISSION) && sp.transmission > 0.0f;
    if ((effect_on(EFFECT_NORMAL_TEXTURE) && sp.m.normal_texture != INVALID_INDEX) || glass)
        ns = keep_reflection_above_surface(ns, ng, eye);
    SurfaceBsdf b;
    b.frame = make_frame(ns);
    BsdfParams p = make_bsdf_params(sp.m);
    if (effect_on(EFFECT_TRANSMISSION))
        p = with_transmission(p, sp.transmission,
                              sp.volume ? (front ? sp.eta_front : 1.0f / max(sp.eta_front, 1.0e-4f)) : sp.m.ior,
                              sp.volume ? 0u : 1u);
    b.bsdf = add_bsdf_layers(p, sp.s, sp.triangle, sp.b1, sp.b2, b.frame, sp.anisotropy, front, ng, eye);
    b.ng = ng;
    b.volume = sp.volume;
    b.transmits = has_transmission_lobe(b.bsdf);
    b.tilted = dot(b.frame.n, ng) < 1.0f || (b.transmits && dot(ns_side, ng) < 1.0f);
    return b;
}

// Whether make_surface_bsdf(sp, eye) builds the very BSDF it built for `built_for`: the same side, a shading normal
// that faces both (no fallback to the facet's), and nothing else that follows the eye (a normal texture's or glass's
// frame, the clear coat's normal). A stage that needs the BSDF for many eyes at one point rebuilds it only where not
// (merge.comp).
bool surface_bsdf_serves(ShadingPoint sp, vec3 built_for, vec3 eye) {
    bool front = dot(sp.s.ng, eye) > 0.0f;
    if (front != dot(sp.s.ng, built_for) > 0.0f) return false;
    if ((effect_on(EFFECT_NORMAL_TEXTURE) && sp.m.normal_texture != INVALID_INDEX) ||
        (effect_on(EFFECT_TRANSMISSION) && sp.transmission > 0.0f) || effect_on(EFFECT_CLEARCOAT))
        return false;
    vec3 ns = front ? sp.s.ns : -sp.s.ns;
    return dot(ns, built_for) > 0.0f && dot(ns, eye) > 0.0f;
}

// Whether the path tracer's BSDF at b lets light arrive from `light` (local: light_local), as shade.comp tests its
// samples and shadow rays.
bool surface_bsdf_allows(SurfaceBsdf b, vec3 light, vec3 light_local) {
    return b.transmits ? may_leave_towards(light, b.ng, light_local) : light_local.z > 0.0f && dot(light, b.ng) > 0.0f;
}

// f(eye, light) cos(light) in the frame b was built for.
vec3 eval_surface_bsdf(SurfaceBsdf b, vec3 eye, vec3 light) {
    vec3 light_local = to_local(b.frame, light);
    if (!surface_bsdf_allows(b, light, light_local)) return vec3(0.0f);
    return eval_bsdf(b.bsdf, to_local(b.frame, eye), light_local) *
           same_side_transmission_scale(b.bsdf, b.volume, light, b.ng, light_local);
}

// The solid-angle pdf with which path tracing's BSDF sampling, looking from `eye`, proposes `light`.
float pdf_surface_bsdf(SurfaceBsdf b, vec3 eye, vec3 light) {
    vec3 light_local = to_local(b.frame, light);
    return surface_bsdf_allows(b, light, light_local) ? pdf_bsdf(b.bsdf, to_local(b.frame, eye), light_local) : 0.0f;
}

// The next direction of a light subpath leaving towards the eye side, and its solid-angle pdf (0: none). Mostly the
// BSDF's own sampling as if the eye were towards the light. Where the shading normal differs from the facet's, the
// path tracer's BSDF seen from an eye below the shading normal's hemisphere (but above the facet) falls back to the
// facet's frame and reflects light there, which that sampling never proposes (through a transmitting surface, the eye
// on the far side builds its frame from its own side, which differs likewise): a share FACET_SAMPLING_SHARE of the
// directions is then drawn cosine-weighted about the facet (a transmitting one: on either side, half each), so every
// direction with light is proposed (unbiased), and the pdf is the mixture's. A flat facet draws from the BSDF alone.
// `at_light`: the BSDF built for an eye towards wl.
const float FACET_SAMPLING_SHARE = 0.1f;

struct NextDirection {
    vec3 wi;
    float pdf;
};

// The mixture's pdf of proposing wi (the BSDF sampler proposes directions its BSDF allows only).
float pdf_next_direction(SurfaceBsdf at_light, vec3 wl, vec3 wi) {
    float facet_share = at_light.tilted ? FACET_SAMPLING_SHARE : 0.0f;
    float cos_g = dot(wi, at_light.ng);
    float facet = at_light.transmits ? 0.5f * pdf_cosine_hemisphere(abs(cos_g)) : pdf_cosine_hemisphere(cos_g);
    return (1.0f - facet_share) * pdf_surface_bsdf(at_light, wl, wi) + facet_share * facet;
}

NextDirection sample_next_direction(SurfaceBsdf at_light, vec3 wl, vec3 u) {
    NextDirection next;
    vec3 ng = at_light.ng;
    next.wi = ng;
    next.pdf = 0.0f;
    float facet_share = at_light.tilted ? FACET_SAMPLING_SHARE : 0.0f;
    if (u.x < facet_share) {
        vec3 local = sample_cosine_hemisphere(u.yz);
        if (!(local.z > 0.0f)) return next;
        next.wi = to_world(make_frame(ng), local);
        if (at_light.transmits && u.x < 0.5f * facet_share) next.wi -= 2.0f * dot(next.wi, ng) * ng;  // the far side
    } else {
        u.x = min((u.x - facet_share) / (1.0f - facet_share), 0.99999994f);
        BsdfSample bs = sample_bsdf(at_light.bsdf, to_local(at_light.frame, wl), u);
        if (bs.valid == 0u) return next;
        next.wi = to_world(at_light.frame, bs.wi);
        if (!surface_bsdf_allows(at_light, next.wi, bs.wi)) return next;
        if (facet_share == 0.0f) {
            next.pdf = bs.pdf;
            return next;
        }
    }
    next.pdf = pdf_next_direction(at_light, wl, next.wi);
    return next;
}
#endif
