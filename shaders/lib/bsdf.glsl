// The glTF 2.0 metallic-roughness BRDF (glTF 2.0 spec, Appendix B) with KHR_materials_specular and
// KHR_materials_ior: evaluation, pdf and importance sampling. Shared GLSL/C++ subset (see cpp_compat.h).
//
// Directions live in the local shading frame (z = shading normal); wo and wi both point away from the
// surface. Reflection only: wo.z <= 0 or wi.z <= 0 gives f = 0 and pdf = 0.
//   f = mix(dielectric_brdf, metal_brdf, metallic)
//   dielectric_brdf = (1 - max_value(F_d)) * base_color / pi + F_d * specular,
//       F_d = f0 + (f90 - f0) (1 - |v.h|)^5, f0 = min(((ior-1)/(ior+1))^2 specularColor, 1) specular,
//       f90 = specular (KHR_materials_specular, "Implementation"; max_value keeps colored f0 in energy)
//   metal_brdf = (base_color + (1 - base_color) (1 - |v.h|)^5) * specular
//   specular = D(h) V(wo, wi): Trowbridge-Reitz/GGX D, height-correlated Smith V, alpha = roughness^2.
#ifndef FREDHOLM_LIB_BSDF_GLSL
#define FREDHOLM_LIB_BSDF_GLSL

#ifdef __cplusplus
using fh::gpu::Material;  // C++: include shaders/shared/layout.h at global scope before this file
#else
#include "../shared/layout.h"
#endif
#include "sampling.glsl"
#include "ggx.glsl"

// Smallest GGX alpha: roughness 0 becomes a very sharp but finite lobe (D <= 1 / (pi 1e-6) = 3.2e5), never
// a delta, so every path stays a plain (non-delta) sample with a finite pdf.
const float BSDF_MIN_ALPHA = 1.0e-3f;
// Range of the specular lobe's selection probability when both lobes are present, so that neither lobe is
// starved when the Fresnel estimate below is poor (e.g. rough surfaces at grazing angles).
const float BSDF_MIN_LOBE_PROBABILITY = 0.05f;

struct BsdfParams {
    vec3 base_color;
    float metallic;
    float alpha;            // GGX alpha = roughness^2, at least BSDF_MIN_ALPHA
    vec3 f0_dielectric;     // dielectric Fresnel at normal incidence (includes specularFactor)
    float f90_dielectric;   // dielectric Fresnel at grazing incidence = specularFactor
};

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
    return p;
}

float max_value(vec3 c) {
    return max(c.x, max(c.y, c.z));
}

// Schlick 1994's weight (1 - cos)^5.
float schlick_weight(float cos_theta) {
    float m = clamp(1.0f - cos_theta, 0.0f, 1.0f);
    float m2 = m * m;
    return m2 * m2 * m;
}

// Probability of sampling the specular lobe for outgoing cos theta `cos_o`: a Fresnel-weighted estimate of
// the two lobes' albedos (specular ~ F(cos_o), diffuse ~ (1 - max F_d(cos_o)) (1 - metallic) base_color),
// clamped to [BSDF_MIN_LOBE_PROBABILITY, 1 - BSDF_MIN_LOBE_PROBABILITY] when both lobes exist, and exactly
// 0 (1) when the specular (diffuse) lobe is absent. Depends on wo only, so pdf_bsdf can recompute it.
float specular_probability(BsdfParams p, float cos_o) {
    float w = schlick_weight(cos_o);
    vec3 f_dielectric = p.f0_dielectric + (vec3(p.f90_dielectric) - p.f0_dielectric) * w;
    vec3 f_metal = p.base_color + (vec3(1.0f) - p.base_color) * w;
    float diffuse = (1.0f - p.metallic) * (1.0f - max_value(f_dielectric)) * luminance(p.base_color);
    bool has_specular = p.metallic > 0.0f || p.f90_dielectric > 0.0f || max_value(p.f0_dielectric) > 0.0f;
    if (!has_specular) {
        return 0.0f;
    }
    if (!(diffuse > 0.0f)) {
        return 1.0f;
    }
    float specular = luminance(mix(f_dielectric, f_metal, p.metallic));
    float q = specular / (specular + diffuse);
    return clamp(q, BSDF_MIN_LOBE_PROBABILITY, 1.0f - BSDF_MIN_LOBE_PROBABILITY);
}

// f(wo, wi) * cos(theta_i): the BRDF already multiplied by the cosine of the incident direction.
vec3 eval_bsdf(BsdfParams p, vec3 wo, vec3 wi) {
    if (!(wo.z > 0.0f && wi.z > 0.0f)) {
        return vec3(0.0f);
    }
    vec3 h = normalize(wo + wi);  // |wo + wi| >= wo.z + wi.z > 0
    float w = schlick_weight(abs(dot(wo, h)));
    float specular = ggx_d(h, p.alpha) * ggx_v_cos(wo.z, wi.z, p.alpha);
    vec3 diffuse = p.base_color * (INV_PI * wi.z);
    vec3 f_dielectric = p.f0_dielectric + (vec3(p.f90_dielectric) - p.f0_dielectric) * w;
    vec3 dielectric = (1.0f - max_value(f_dielectric)) * diffuse + f_dielectric * specular;
    vec3 metal = (p.base_color + (vec3(1.0f) - p.base_color) * w) * specular;
    return mix(dielectric, metal, p.metallic);
}

float pdf_bsdf_lobes(BsdfParams p, float p_specular, vec3 wo, vec3 wi) {
    if (!(wo.z > 0.0f && wi.z > 0.0f)) {
        return 0.0f;
    }
    float pdf_specular = p_specular > 0.0f ? pdf_ggx_vndf_reflection(wo, normalize(wo + wi), p.alpha) : 0.0f;
    return p_specular * pdf_specular + (1.0f - p_specular) * pdf_cosine_hemisphere(wi.z);
}

// Solid-angle pdf of sample_bsdf (one-sample MIS over the lobes: Veach 1997 sec. 9.2.4, "balance" mix).
float pdf_bsdf(BsdfParams p, vec3 wo, vec3 wi) {
    return pdf_bsdf_lobes(p, specular_probability(p, wo.z), wo, wi);
}

struct BsdfSample {
    vec3 wi;
    float pdf;      // solid-angle pdf of wi, = pdf_bsdf(wo, wi)
    vec3 weight;    // eval_bsdf(wo, wi) / pdf: f cos / pdf of the whole BRDF (not per lobe), unbiased
    uint valid;     // 0: no direction (wo below the surface, or the sample left the upper hemisphere)
};

// u.x picks the lobe (specular with probability specular_probability), u.yz pick the direction: visible
// normals of GGX (Dupuy & Benyoub 2023) reflected about, or the cosine-weighted hemisphere.
BsdfSample sample_bsdf(BsdfParams p, vec3 wo, vec3 u) {
    BsdfSample s;
    s.wi = vec3(0.0f, 0.0f, 1.0f);
    s.pdf = 0.0f;
    s.weight = vec3(0.0f);
    s.valid = 0u;
    if (!(wo.z > 0.0f)) {
        return s;
    }
    float p_specular = specular_probability(p, wo.z);
    vec3 wi;
    if (u.x < p_specular) {
        vec3 h = sample_ggx_vndf(wo, p.alpha, vec2(u.y, u.z));
        wi = 2.0f * dot(wo, h) * h - wo;  // reflect wo about h; h = 0 (degenerate) gives -wo, rejected below
    } else {
        wi = sample_cosine_hemisphere(vec2(u.y, u.z));
    }
    float pdf = pdf_bsdf_lobes(p, p_specular, wo, wi);
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
