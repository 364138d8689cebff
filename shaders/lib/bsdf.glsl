// The glTF 2.0 metallic-roughness BRDF (glTF 2.0 spec, Appendix B) with KHR_materials_specular and
// KHR_materials_ior, made energy conserving: evaluation, pdf and importance sampling. Shared GLSL/C++ subset.
//
// Directions live in the local shading frame (z = shading normal); wo and wi both point away from the
// surface. Reflection only: wo.z <= 0 or wi.z <= 0 gives f = 0 and pdf = 0.
//   f = mix(dielectric_brdf, metal_brdf, metallic)                                  (as the spec)
//   metal_brdf = (base_color + (1 - base_color) (1 - |v.h|)^5) * specular          (as the spec)
//   dielectric_brdf = F_d * specular + base_color / pi * (1 - E(mu_o)) (1 - E(mu_i)) / (1 - E_avg)
//       F_d = f0 + (f90 - f0) (1 - |v.h|)^5, f0 = min(((ior-1)/(ior+1))^2 specularColor, 1) specular,
//       f90 = specular (KHR_materials_specular, "Implementation")
//   specular = D(h) V(wo, wi): Trowbridge-Reitz/GGX D, height-correlated Smith V, alpha = roughness^2.
//
// DEVIATION from the spec, whose dielectric weights Lambert by 1 - max_value(F_d(v.h)): that is not energy
// conserving (a white dielectric reflects 1.03x what it receives at 60 deg, 1.35x at 80, 1.85x at 89). We
// weight Lambert by the energy the specular layer leaves instead, "albedo scaling" (Kelemen & Szirmay-Kalos
// 2001, "A Microfacet Based Coupled Specular-Matte BRDF Model with Importance Sampling"; also Autodesk
// Standard Surface, OpenPBR and Dassault Enterprise PBR): E(mu) = max_value(f0) A(mu) + f90 B(mu) is the
// specular layer's albedo, E_avg = 2 int E mu dmu (ggx_albedo.glsl). The albedo is then E_c(mu_o) +
// base_color (1 - E(mu_o)) <= 1 per channel, and f stays reciprocal. specularFactor 0 (f0 = f90 = 0, E = 0)
// gives exactly Lambert; metallic 1 gives exactly the spec's metal.
//
// KHR_materials_transmission replaces a fraction `transmission` of the dielectric by the glass lobe of
// dielectric.glsl (its own exact-Fresnel reflection and the refraction or thin-walled pass-through):
//   dielectric = mix(F_d specular + albedo-scaled Lambert, glass, transmission)
// a convex mix of two energy-conserving, reciprocal BSDFs. Stages compiled without EFFECT_TRANSMISSION define
// BSDF_HAS_TRANSMISSION false, and none of the glass code is left in them.
#ifndef FREDHOLM_LIB_BSDF_GLSL
#define FREDHOLM_LIB_BSDF_GLSL

#ifdef __cplusplus
using fh::gpu::Material;  // C++: include shaders/shared/layout.h at global scope before this file
#else
#include "../shared/layout.h"
#endif
#include "sampling.glsl"
#include "ggx.glsl"
#include "ggx_albedo.glsl"
#include "dielectric.glsl"

#ifndef BSDF_HAS_TRANSMISSION
#define BSDF_HAS_TRANSMISSION true
#endif

// Smallest GGX alpha: roughness 0 becomes a very sharp but finite lobe (D <= 1 / (pi 1e-6) = 3.2e5), never
// a delta, so every path stays a plain (non-delta) sample with a finite pdf.
const float BSDF_MIN_ALPHA = 1.0e-3f;
// Range of the specular lobe's selection probability when both lobes are present, so that neither lobe is
// starved (the lobe albedos below ignore how the two lobes are distributed over wi).
const float BSDF_MIN_LOBE_PROBABILITY = 0.05f;

struct BsdfParams {
    vec3 base_color;
    float metallic;
    float alpha;            // GGX alpha = roughness^2, at least BSDF_MIN_ALPHA
    vec3 f0_dielectric;     // dielectric Fresnel at normal incidence (includes specularFactor)
    float f90_dielectric;   // dielectric Fresnel at grazing incidence = specularFactor
    float diffuse_scale;    // 1 / (1 - E_avg) of the dielectric's specular layer (see the top of the file)
    float transmission;     // KHR_materials_transmission: the glass lobe's share of the dielectric
    GlassParams glass;
};

// Floor of 1 - E_avg (approached only by f0 = f90 = 1 at small alpha): loses energy, never adds it.
const float BSDF_MIN_DIFFUSE_TRANSMITTANCE = 1.0e-4f;

BsdfParams make_bsdf_params(Material m) {
    BsdfParams p;
    p.base_color = clamp(vec3(m.base_color), vec3(0.0f), vec3(1.0f));
    p.metallic = clamp(m.metallic, 0.0f, 1.0f);
    float roughness = clamp(m.roughness, 0.0f, 1.0f);
    p.alpha = max(roughness * roughness, BSDF_MIN_ALPHA);
    // KHR_materials_ior: f0 = ((ior - 1) / (ior + 1))^2; ior = 0 is legal and gives f0 = 1.
    float r = (m.ior - 1.0f) / max(m.ior + 1.0f, 1.0e-6f);
    float specular = clamp(m.specular_color.w, 0.0f, 1.0f);
    p.f0_dielectric = min(vec3(r * r) * vec3(m.specular_color), vec3(1.0f)) * specular;
    p.f90_dielectric = specular;
    vec2 average = ggx_albedo_average(p.alpha);
    float e_average = max_value(p.f0_dielectric) * average.x + p.f90_dielectric * average.y;
    p.diffuse_scale = 1.0f / max(1.0f - e_average, BSDF_MIN_DIFFUSE_TRANSMITTANCE);
    p.transmission = 0.0f;
    p.glass.transmission_tint = p.base_color;
    p.glass.alpha = p.alpha;
    p.glass.specular_color = max(vec3(m.specular_color), vec3(0.0f));
    p.glass.specular = specular;
    p.glass.eta = max(m.ior, 1.0e-4f);
    p.glass.thin_walled = 1u;
    return p;
}

// `p` with a fraction `transmission` of its dielectric made glass: thin-walled (eta = the ior) or the surface
// of a volume (eta = n beyond the surface / n on the viewer's side).
BsdfParams with_transmission(BsdfParams p, float transmission, float eta, uint thin_walled) {
    p.transmission = clamp(transmission, 0.0f, 1.0f);
    p.glass.thin_walled = thin_walled;
    p.glass.eta = thin_walled != 0u ? max(eta, 1.0e-4f) : refraction_eta(eta);
    return p;
}

bool has_glass(BsdfParams p) {
    return BSDF_HAS_TRANSMISSION && p.transmission > 0.0f && p.metallic < 1.0f;
}

// Fraction of the light from cos theta = mu that the dielectric's specular layer lets through to the
// diffuse base: 1 - E(mu), E = max_value(f0) A + f90 B, given ggx_albedo(mu, alpha) = (A, B).
float diffuse_transmittance(BsdfParams p, vec2 albedo) {
    return max(1.0f - (max_value(p.f0_dielectric) * albedo.x + p.f90_dielectric * albedo.y), 0.0f);
}

// Schlick 1994's weight (1 - cos)^5.
float schlick_weight(float cos_theta) {
    float m = clamp(1.0f - cos_theta, 0.0f, 1.0f);
    float m2 = m * m;
    return m2 * m2 * m;
}

// The opaque lobes' shares of the albedo for outgoing cos theta `cos_o` (luminances): the specular layers'
// mix(opaque (f0 A + f90 B), base_color A + B, metallic) and the diffuse lobe's (1 - metallic) opaque base_color
// (1 - E(cos_o)); `opaque` = 1 - transmission, the part of the dielectric that is not glass.
struct LobeAlbedos {
    float specular;
    float diffuse;
};

LobeAlbedos estimate_lobe_albedos(BsdfParams p, float cos_o, float opaque) {
    vec2 albedo = ggx_albedo(cos_o, p.alpha);
    LobeAlbedos a;
    a.diffuse = (1.0f - p.metallic) * opaque * diffuse_transmittance(p, albedo) * luminance(p.base_color);
    vec3 e_dielectric = p.f0_dielectric * albedo.x + vec3(p.f90_dielectric * albedo.y);
    vec3 e_metal = p.base_color * albedo.x + vec3(albedo.y);
    a.specular = luminance(mix(e_dielectric * opaque, e_metal, p.metallic));
    return a;
}

// Probability of sampling the specular lobe without glass: its share of the albedo (estimate_lobe_albedos),
// clamped to [BSDF_MIN_LOBE_PROBABILITY, 1 - BSDF_MIN_LOBE_PROBABILITY] when both lobes exist, and exactly 0 (1)
// when the specular (diffuse) lobe is absent. Depends on wo only, so pdf_bsdf can recompute it.
float specular_probability(BsdfParams p, float cos_o) {
    bool has_specular = p.metallic > 0.0f || p.f90_dielectric > 0.0f || max_value(p.f0_dielectric) > 0.0f;
    if (!has_specular) {
        return 0.0f;
    }
    LobeAlbedos a = estimate_lobe_albedos(p, cos_o, 1.0f);
    if (!(a.diffuse > 0.0f)) {
        return 1.0f;
    }
    float q = a.specular / (a.specular + a.diffuse);
    return clamp(q, BSDF_MIN_LOBE_PROBABILITY, 1.0f - BSDF_MIN_LOBE_PROBABILITY);
}

// f(wo, wi) * cos(theta_i): the BRDF already multiplied by the cosine of the incident direction.
vec3 eval_bsdf(BsdfParams p, vec3 wo, vec3 wi) {
    if (!(wo.z > 0.0f && wi.z > 0.0f)) {
        if (has_glass(p) && wo.z > 0.0f && wi.z < 0.0f) {
            return eval_glass(p.glass, wo, wi) * ((1.0f - p.metallic) * p.transmission);
        }
        return vec3(0.0f);
    }
    vec3 h = normalize(wo + wi);  // |wo + wi| >= wo.z + wi.z > 0
    float w = schlick_weight(abs(dot(wo, h)));
    float specular = ggx_d(h, p.alpha) * ggx_v_cos(wo.z, wi.z, p.alpha);
    float transmittance = diffuse_transmittance(p, ggx_albedo(wo.z, p.alpha)) *
                          diffuse_transmittance(p, ggx_albedo(wi.z, p.alpha)) * p.diffuse_scale;
    vec3 diffuse = p.base_color * (INV_PI * wi.z * transmittance);
    vec3 f_dielectric = p.f0_dielectric + (vec3(p.f90_dielectric) - p.f0_dielectric) * w;
    vec3 dielectric = diffuse + f_dielectric * specular;
    if (has_glass(p)) {
        dielectric = mix(dielectric, eval_glass(p.glass, wo, wi), p.transmission);
    }
    vec3 metal = (p.base_color + (vec3(1.0f) - p.base_color) * w) * specular;
    return mix(dielectric, metal, p.metallic);
}

// Which lobe sample_bsdf draws from: specular reflection with probability `specular`, the glass lobe with
// `glass`, Lambert with the rest.
struct LobeChoice {
    float specular;
    float glass;
};

// Without glass: specular_probability. With it: each lobe's share of the albedo (the glass lobe's estimated
// as F(cos_o) + (1 - F) luminance(base_color)), every lobe present at least BSDF_MIN_LOBE_PROBABILITY before
// renormalising. Depends on wo only.
LobeChoice choose_lobes(BsdfParams p, float cos_o) {
    LobeChoice c;
    c.glass = 0.0f;
    if (!has_glass(p)) {
        c.specular = specular_probability(p, cos_o);
        return c;
    }
    LobeAlbedos a = estimate_lobe_albedos(p, cos_o, 1.0f - p.transmission);
    float f = fresnel_dielectric(cos_o, p.glass.eta);
    float glass = (1.0f - p.metallic) * p.transmission * (f + (1.0f - f) * luminance(p.base_color));
    float total = a.specular + a.diffuse + glass;
    if (!(total > 0.0f)) {
        c.specular = 0.0f;
        c.glass = 1.0f;
        return c;
    }
    float q_specular = a.specular > 0.0f ? max(a.specular / total, BSDF_MIN_LOBE_PROBABILITY) : 0.0f;
    float q_diffuse = a.diffuse > 0.0f ? max(a.diffuse / total, BSDF_MIN_LOBE_PROBABILITY) : 0.0f;
    float q_glass = glass > 0.0f ? max(glass / total, BSDF_MIN_LOBE_PROBABILITY) : 0.0f;
    float norm = q_specular + q_diffuse + q_glass;
    c.specular = q_specular / norm;
    c.glass = q_glass / norm;
    return c;
}

float pdf_bsdf_lobes(BsdfParams p, LobeChoice c, vec3 wo, vec3 wi) {
    if (!(wo.z > 0.0f && wi.z > 0.0f)) {
        if (c.glass > 0.0f && wo.z > 0.0f && wi.z < 0.0f) {
            return c.glass * pdf_glass(p.glass, wo, wi);
        }
        return 0.0f;
    }
    float pdf_specular = c.specular > 0.0f ? pdf_ggx_vndf_reflection(wo, normalize(wo + wi), p.alpha) : 0.0f;
    float pdf = c.specular * pdf_specular + (1.0f - c.specular - c.glass) * pdf_cosine_hemisphere(wi.z);
    if (c.glass > 0.0f) {
        pdf += c.glass * pdf_glass(p.glass, wo, wi);
    }
    return pdf;
}

// Solid-angle pdf of sample_bsdf (one-sample MIS over the lobes: Veach 1997 sec. 9.2.4, "balance" mix).
float pdf_bsdf(BsdfParams p, vec3 wo, vec3 wi) {
    return pdf_bsdf_lobes(p, choose_lobes(p, wo.z), wo, wi);
}

struct BsdfSample {
    vec3 wi;
    float pdf;      // solid-angle pdf of wi, = pdf_bsdf(wo, wi)
    vec3 weight;    // eval_bsdf(wo, wi) / pdf: f cos / pdf of the whole BRDF (not per lobe), unbiased
    uint valid;     // 0: no direction (wo below the surface, or no lobe sends light that way)
};

// u.x picks the lobe (specular with probability specular_probability), u.yz pick the direction: visible
// normals of GGX (Dupuy & Benyoub 2023) reflected about, the glass lobe, or the cosine-weighted hemisphere.
BsdfSample sample_bsdf(BsdfParams p, vec3 wo, vec3 u) {
    BsdfSample s;
    s.wi = vec3(0.0f, 0.0f, 1.0f);
    s.pdf = 0.0f;
    s.weight = vec3(0.0f);
    s.valid = 0u;
    if (!(wo.z > 0.0f)) {
        return s;
    }
    LobeChoice c = choose_lobes(p, wo.z);
    vec3 wi;
    if (u.x < c.specular) {
        vec3 h = sample_ggx_vndf(wo, p.alpha, vec2(u.y, u.z));
        wi = 2.0f * dot(wo, h) * h - wo;  // reflect wo about h; h = 0 (degenerate) gives -wo, rejected below
        if (!(wi.z > 0.0f)) {
            return s;  // below the surface: not a reflection (nor, with glass, a transmission of this lobe)
        }
    } else if (u.x < c.specular + c.glass) {
        float u_glass = min((u.x - c.specular) / c.glass, 0.99999994f);  // reused: reflect or refract
        wi = sample_glass(p.glass, wo, vec3(u_glass, u.y, u.z));
    } else {
        wi = sample_cosine_hemisphere(vec2(u.y, u.z));
    }
    float pdf = pdf_bsdf_lobes(p, c, wo, wi);
    if (!(pdf > 0.0f)) {
        return s;
    }
    s.wi = wi;
    s.pdf = pdf;
    s.weight = eval_bsdf(p, wo, wi) / pdf;
    s.valid = 1u;
    return s;
}

#endif
