// The glass lobe of KHR_materials_transmission: a rough dielectric interface with GGX microfacets (Walter et
// al. 2007, "Microfacet Models for Refraction through Rough Surfaces"; pbrt-v4's DielectricBxDF), either
// refracting into a volume (KHR_materials_volume) or thin-walled (light leaves on the other side in the
// mirrored reflection direction, unbent: the spec's thin-walled case). Shared GLSL/C++ subset.
//
// Local frame as bsdf.glsl: z = shading normal on wo's side, wo.z > 0; wi.z > 0 reflects, wi.z < 0 transmits.
// Per microfacet, exact unpolarised Fresnel F(wo.h) (total internal reflection included) splits the light:
//   reflected   R = specularFactor * min(F * specularColorFactor, 1)       (the spec's fresnel_mix)
//   transmitted T = base_color * (1 - max(R))                             (so R + T <= 1 in every channel)
// Reflection: R D V cos (as the opaque specular lobe). Refraction with eta = n beyond / n on wo's side
// (Walter eq. 21, pbrt-v4 radiance mode with its 1 / eta^2):
//   f cos_i = T D G2 |wi.h| (wo.h) / (cos_o (wi.h + wo.h / eta)^2 eta^2) = 4 T D V cos_i |wi.h| (wo.h) / (...)
// Thin-walled: f(wo, wi) = T D V evaluated at the mirror image of wi (reciprocal, and the same energy as R).
// Single scattering alone loses the light that bounces between microfacets (rough glass: up to half of it from
// inside); glass_multiscatter.glsl gives it back, and eval_glass / pdf_glass / sample_glass below are the sum.
// KHR_materials_iridescence: a thin film on the outside mixes its reflectance F_film(wo.h) (thin_film.glsl) into R,
//   R = mix(R, F_film, iridescence), and T = base_color (1 - max(R)) as above (the extension's rgb_mix with the
// BTDF as its base): per microfacet R + T <= 1 still. Seen from inside a volume (eta < 1) light meets the film at
// the angle it refracts to outside: a lossless stack reflects the same from both sides (Stokes' relations). The
// choice between reflection and refraction still follows the exact F (unbiased: f / pdf carries R and T).
// Compiled out (GLASS_HAS_IRIDESCENCE false) in stages without EFFECT_IRIDESCENCE.
#ifndef FH_DIELECTRIC_GLSL
#define FH_DIELECTRIC_GLSL

#include "lib/sampling/sampling.glsl"
#include "lib/bsdf/ggx.glsl"
#include "lib/bsdf/thin_film.glsl"

#ifndef GLASS_HAS_IRIDESCENCE
#define GLASS_HAS_IRIDESCENCE true
#endif
#ifndef GLASS_HAS_MULTISCATTER
#define GLASS_HAS_MULTISCATTER true
#endif
#include "lib/bsdf/glass_multiscatter.glsl"

// A refracting eta within this of 1 is moved to 1 +- this: at eta = 1 the interface is invisible and rough
// refraction degenerates into a delta that no finite pdf describes. (Thin-walled glass has no such limit.)
const float GLASS_MIN_ETA_OFFSET = 1.0e-3f;

struct GlassParams {
    vec3 transmission_tint;  // base colour: what passes through is tinted by it
    GgxRoughness roughness;  // GGX roughness (as the opaque specular lobe; anisotropic with it)
    vec3 specular_color;     // KHR_materials_specular specularColorFactor
    float specular;          // specularFactor
    float eta;               // n beyond the surface / n on wo's side; thin-walled: the ior
    uint thin_walled;        // 1: no volume behind the surface
    ThinFilm film;           // KHR_materials_iridescence (weight 0: none); the opaque lobes of bsdf.glsl read it too
};

// Unpolarised Fresnel reflectance for cos_i (incident direction against the normal on its side) and
// eta = n_t / n_i; 1 under total internal reflection (sin_t >= 1).
float fresnel_dielectric(float cos_i, float eta) {
    float c = clamp(cos_i, 0.0f, 1.0f);
    float sin2_t = (1.0f - c * c) / (eta * eta);
    if (sin2_t >= 1.0f) {
        return 1.0f;
    }
    float cos_t = sqrt(1.0f - sin2_t);
    float r_parallel = (eta * c - cos_t) / (eta * c + cos_t);
    float r_perpendicular = (c - eta * cos_t) / (c + eta * cos_t);
    return 0.5f * (r_parallel * r_parallel + r_perpendicular * r_perpendicular);
}

// eta for refraction at an interface of index ratio `ratio` (>= 1e-4), kept GLASS_MIN_ETA_OFFSET away from 1.
float refraction_eta(float ratio) {
    float eta = max(ratio, 1.0e-4f);
    if (abs(eta - 1.0f) < GLASS_MIN_ETA_OFFSET) {
        eta = eta < 1.0f ? 1.0f - GLASS_MIN_ETA_OFFSET : 1.0f + GLASS_MIN_ETA_OFFSET;
    }
    return eta;
}

// R for a microfacet seen at cos theta = cos_o (wo.h) whose exact Fresnel reflectance is `fresnel`.
vec3 glass_reflectance(GlassParams g, float cos_o, float fresnel) {
    vec3 r = g.specular * min(fresnel * g.specular_color, vec3(1.0f));
    if (GLASS_HAS_IRIDESCENCE && g.film.weight > 0.0f && fresnel < 1.0f) {
        float c = cos_o;
        if (g.thin_walled == 0u && g.eta < 1.0f) {
            c = sqrt(max(1.0f - (1.0f - cos_o * cos_o) / (g.eta * g.eta), 0.0f));  // fresnel < 1: no TIR
        }
        float n = (g.eta - 1.0f) / (g.eta + 1.0f);  // the same for eta and 1 / eta
        vec3 base_f0 = min(vec3(n * n) * g.specular_color, vec3(1.0f)) * g.specular;
        r = mix_thin_film(r, g.film, c, base_f0);
    }
    return r;
}

// T for a microfacet of reflectance `reflectance` (glass_reflectance).
vec3 glass_transmittance(GlassParams g, vec3 reflectance) {
    return g.transmission_tint * (1.0f - max_value(reflectance));
}

// The microfacet normal that refracts wo into wi (Walter eq. 16: h ~ wo + eta wi, turned to +z), with the
// Jacobian's denominator (wi.h + wo.h / eta)^2. valid = 0 when no microfacet facing wo does it.
struct RefractionHalf {
    vec3 h;
    float denom;
    uint valid;
};

RefractionHalf refraction_half_vector(vec3 wo, vec3 wi, float eta) {
    RefractionHalf r;
    r.h = vec3(0.0f, 0.0f, 1.0f);
    r.denom = 0.0f;
    r.valid = 0u;
    vec3 h = wo + wi * eta;
    float len = length(h);
    if (!(len > 0.0f)) {
        return r;
    }
    h = h / len;
    if (h.z < 0.0f) {
        h = -h;
    }
    if (!(dot(h, wo) > 0.0f && dot(h, wi) < 0.0f)) {
        return r;  // a back-facing microfacet
    }
    float d = dot(wi, h) + dot(wo, h) / eta;
    r.h = h;
    r.denom = d * d;
    r.valid = r.denom > 0.0f ? 1u : 0u;
    return r;
}

// f cos(theta_i) of the glass lobe's single scattering.
vec3 eval_glass_single(GlassParams g, vec3 wo, vec3 wi) {
    if (!(wo.z > 0.0f)) {
        return vec3(0.0f);
    }
    if (wi.z > 0.0f) {
        vec3 h = normalize(wo + wi);
        float f = fresnel_dielectric(dot(wo, h), g.eta);
        return glass_reflectance(g, dot(wo, h), f) * (ggx_d_lobe(g.roughness, h) * ggx_v_cos_lobe(g.roughness, wo, wi));
    }
    if (!(wi.z < 0.0f)) {
        return vec3(0.0f);
    }
    if (g.thin_walled != 0u) {
        vec3 mirrored = vec3(wi.x, wi.y, -wi.z);
        vec3 h = normalize(wo + mirrored);
        float f = fresnel_dielectric(dot(wo, h), g.eta);
        return glass_transmittance(g, glass_reflectance(g, dot(wo, h), f)) * (ggx_d_lobe(g.roughness, h) * ggx_v_cos_lobe(g.roughness, wo, mirrored));
    }
    RefractionHalf r = refraction_half_vector(wo, wi, g.eta);
    if (r.valid == 0u) {
        return vec3(0.0f);
    }
    float f = fresnel_dielectric(dot(wo, r.h), g.eta);
    float jacobian = abs(dot(wi, r.h)) * dot(wo, r.h) / (r.denom * g.eta * g.eta);
    return glass_transmittance(g, glass_reflectance(g, dot(wo, r.h), f)) * (4.0f * ggx_d_lobe(g.roughness, r.h) * ggx_v_cos_lobe(g.roughness, wo, -wi) * jacobian);
}

// Solid-angle pdf of sample_glass_single: h from the visible normals, then reflection with probability F(wo.h).
float pdf_glass_single(GlassParams g, vec3 wo, vec3 wi) {
    if (!(wo.z > 0.0f)) {
        return 0.0f;
    }
    if (wi.z > 0.0f) {
        vec3 h = normalize(wo + wi);
        return fresnel_dielectric(dot(wo, h), g.eta) * pdf_ggx_vndf_reflection_lobe(g.roughness, wo, h);
    }
    if (!(wi.z < 0.0f)) {
        return 0.0f;
    }
    if (g.thin_walled != 0u) {
        vec3 h = normalize(wo + vec3(wi.x, wi.y, -wi.z));
        return (1.0f - fresnel_dielectric(dot(wo, h), g.eta)) * pdf_ggx_vndf_reflection_lobe(g.roughness, wo, h);
    }
    RefractionHalf r = refraction_half_vector(wo, wi, g.eta);
    if (r.valid == 0u) {
        return 0.0f;
    }
    float reflect_to_refract = 4.0f * dot(wo, r.h) * abs(dot(wi, r.h)) / r.denom;  // D_wo(h) |wi.h| / denom
    return (1.0f - fresnel_dielectric(dot(wo, r.h), g.eta)) * pdf_ggx_vndf_reflection_lobe(g.roughness, wo, r.h) *
           reflect_to_refract;
}

// A direction of the glass lobe's single scattering: u.yz pick a visible microfacet normal, u.x < F(wo.h) reflects
// about it, else the light refracts (thin-walled: leaves mirrored). Returns vec3(0) when there is no direction.
vec3 sample_glass_single(GlassParams g, vec3 wo, vec3 u) {
    vec3 h = sample_ggx_vndf_lobe(g.roughness, wo, vec2(u.y, u.z));
    float cos_o = dot(wo, h);
    if (!(cos_o > 0.0f)) {
        return vec3(0.0f);
    }
    vec3 reflected = 2.0f * cos_o * h - wo;
    bool reflects = u.x < fresnel_dielectric(cos_o, g.eta);
    if (reflects || g.thin_walled != 0u) {
        // A reflection must stay above the surface; a thin wall's transmission is its mirror image below.
        if (!(reflected.z > 0.0f)) {
            return vec3(0.0f);
        }
        return reflects ? reflected : vec3(reflected.x, reflected.y, -reflected.z);
    }
    float sin2_t = (1.0f - cos_o * cos_o) / (g.eta * g.eta);
    if (sin2_t >= 1.0f) {
        return vec3(0.0f);  // total internal reflection (F = 1: not reached)
    }
    float cos_t = sqrt(1.0f - sin2_t);
    vec3 refracted = -wo / g.eta + (cos_o / g.eta - cos_t) * h;
    if (!(refracted.z < 0.0f)) {
        return vec3(0.0f);  // a steep microfacet sent it back up: not a transmission
    }
    return refracted;
}

// ---- The whole glass lobe: single scattering plus the energy it loses between microfacets ---------------------
// (glass_multiscatter.glsl). Stages without EFFECT_GLASS_MULTISCATTER define GLASS_HAS_MULTISCATTER false and keep
// single scattering alone, with the same bits as before the compensation existed.

GlassMultiscatter make_glass_multiscatter_of(GlassParams g, vec3 wo) {
    return make_glass_multiscatter(g.roughness.alpha, g.eta, g.thin_walled, wo.z);
}

// What tints the given-back energy: reflections the specular colour times specularFactor, transmissions the base
// colour. The lobe is sized for white glass (specularFactor 1); a refracting interface of weaker reflection w =
// specularFactor max(specularColor) < 1 keeps more in single scattering, E(w) = E(0) + w (E(1) - E(0)) (energy is
// linear in the reflectance's scale: per microfacet w F g_r + (1 - w F) g_t), so the lobe is scaled by w as well:
// E(w) + w (1 - E(1)) = mix(E(0), 1, w) <= 1. Above 1 (a specular colour brighter than white, which min(F c, 1)
// lets reflect more than white glass does) nothing bounds what single scattering keeps, and the lobe is left out.
// A thin wall's single scattering keeps the same energy whatever w (both parts leave through the mirrored
// geometry): its lobe is only tinted.
vec3 glass_multiscatter_tint(GlassParams g, vec3 wi) {
    if (g.thin_walled != 0u) {
        return wi.z > 0.0f ? g.specular * min(g.specular_color, vec3(1.0f)) : g.transmission_tint;
    }
    float w = g.specular * max_value(g.specular_color);
    if (w > 1.0f) {
        return vec3(0.0f);
    }
    return wi.z > 0.0f ? g.specular * g.specular_color : g.transmission_tint * w;
}

// f cos(theta_i) of the glass lobe.
vec3 eval_glass(GlassParams g, vec3 wo, vec3 wi) {
    vec3 f = eval_glass_single(g, wo, wi);
    if (GLASS_HAS_MULTISCATTER && wo.z > 0.0f) {
        GlassMultiscatter s = make_glass_multiscatter_of(g, wo);
        if (s.loss > 0.0f) {
            f += glass_multiscatter_tint(g, wi) * eval_glass_multiscatter(s, g.roughness.alpha, wi);
        }
    }
    return f;
}

// Solid-angle pdf of sample_glass: the multiple-scattering lobe with probability 1 - E_o(mu_o) (its share of white
// glass's energy), single scattering otherwise.
float pdf_glass(GlassParams g, vec3 wo, vec3 wi) {
    float pdf = pdf_glass_single(g, wo, wi);
    if (GLASS_HAS_MULTISCATTER && wo.z > 0.0f) {
        GlassMultiscatter s = make_glass_multiscatter_of(g, wo);
        if (s.loss > 0.0f) {
            pdf = mix(pdf, pdf_glass_multiscatter(s, wi), s.loss);
        }
    }
    return pdf;
}

// A direction of the glass lobe: u.x < 1 - E_o(mu_o) picks the multiple-scattering lobe (u.x rescaled and reused),
// else single scattering.
vec3 sample_glass(GlassParams g, vec3 wo, vec3 u) {
    if (GLASS_HAS_MULTISCATTER && wo.z > 0.0f) {
        GlassMultiscatter s = make_glass_multiscatter_of(g, wo);
        if (u.x < s.loss) {
            return sample_glass_multiscatter(s, vec3(u.x / s.loss, u.y, u.z));
        }
        if (s.loss > 0.0f) {
            u.x = min((u.x - s.loss) / (1.0f - s.loss), 0.99999994f);
        }
    }
    return sample_glass_single(g, wo, u);
}

#endif
