// The Trowbridge-Reitz (GGX) microfacet distribution in the local frame (z = normal): normal distribution,
// height-correlated Smith visibility, and visible-normal sampling with its pdf; isotropic, and anisotropic
// (KHR_materials_anisotropy) through GgxRoughness, whose isotropic case runs the isotropic code unchanged.
// Shared GLSL/C++ subset (see cpp_compat.h). All directions are unit vectors with z > 0 where it matters.
#ifndef FH_GGX_GLSL
#define FH_GGX_GLSL

#include "lib/sampling/sampling.glsl"

// D(h) = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2) (Trowbridge & Reitz 1975; Walter et al. 2007 eq. 33),
// rewritten for a unit h as 1 / (pi alpha^2 ((h.x^2 + h.y^2) / alpha^2 + h.z^2)^2): the textbook form
// cancels catastrophically near h = n when alpha is small (1 - 1e-6 + ... in float).
float ggx_d(vec3 h, float alpha) {
    float a2 = alpha * alpha;
    float t = (h.x * h.x + h.y * h.y) / a2 + h.z * h.z;
    return 1.0f / (PI * a2 * t * t);
}

// sqrt(cos^2 (1 - alpha^2) + alpha^2) = cos * sqrt(1 + alpha^2 tan^2): the term 2 Lambda(w) + 1 scaled by cos.
float ggx_lambda_term(float cos_theta, float alpha) {
    float a2 = alpha * alpha;
    return sqrt(cos_theta * cos_theta * (1.0f - a2) + a2);
}

// V(wo, wi) * cos(theta_i), where V = G2 / (4 cos_o cos_i) with the height-correlated Smith G2 (Heitz 2014,
// "Understanding the Masking-Shadowing Function", eq. 99):
//   V = 0.5 / (cos_i sqrt(cos_o^2 (1 - a^2) + a^2) + cos_o sqrt(cos_i^2 (1 - a^2) + a^2))   (glTF App. B).
// Dividing numerator and denominator by cos_i keeps it finite for grazing angles: V cos_i <= 0.5 / alpha.
float ggx_v_cos(float cos_o, float cos_i, float alpha) {
    if (!(cos_o > 0.0f && cos_i > 0.0f)) {
        return 0.0f;
    }
    float lambda_o = ggx_lambda_term(cos_o, alpha);
    float lambda_i = ggx_lambda_term(cos_i, alpha);
    return 0.5f / (lambda_o + (cos_o / cos_i) * lambda_i);
}

// Samples a microfacet normal h from the distribution of normals visible from wo,
// D_wo(h) = G1(wo) max(0, wo.h) D(h) / wo.z (Heitz 2018, "Sampling the GGX Distribution of Visible
// Normals", JCGT 7(4), eq. 1), by sampling a spherical cap in the stretched (alpha = 1) configuration
// (Dupuy & Benyoub 2023, "Sound and Fast Sampling of the GGX Distribution of Visible Normals", listing 3).
// Returns vec3(0) in the measure-zero degenerate case where the stretched normal vanishes. alpha: (alpha_x, alpha_y),
// the roughness along the frame's x and y axes (equal: isotropic).
vec3 sample_ggx_vndf_stretched(vec3 wo, vec2 alpha, vec2 u) {
    vec3 wo_std = normalize(vec3(alpha.x * wo.x, alpha.y * wo.y, wo.z));
    float phi = TWO_PI * u.x;
    float z = (1.0f - u.y) * (1.0f + wo_std.z) - wo_std.z;  // uniform in [-wo_std.z, 1]
    float sin_theta = sqrt(clamp(1.0f - z * z, 0.0f, 1.0f));
    vec3 h_std = vec3(sin_theta * cos(phi), sin_theta * sin(phi), z) + wo_std;
    vec3 h = vec3(alpha.x * h_std.x, alpha.y * h_std.y, max(h_std.z, 0.0f));
    float len = length(h);
    if (!(len > 1.0e-18f)) {
        return vec3(0.0f);
    }
    return h / len;
}

vec3 sample_ggx_vndf(vec3 wo, float alpha, vec2 u) {
    return sample_ggx_vndf_stretched(wo, vec2(alpha, alpha), u);
}

// Solid-angle pdf of wi = reflect(wo, h) with h ~ D_wo: D_wo(h) / (4 wo.h) = G1(wo) D(h) / (4 wo.z)
// (Heitz 2018 eq. 17 with the reflection Jacobian 1 / (4 wo.h), Walter et al. 2007 eq. 14). With
// G1(wo) = 2 wo.z / (wo.z + sqrt(wo.z^2 (1 - a^2) + a^2)) the 1 / wo.z cancels, so grazing wo stays finite.
float pdf_ggx_vndf_reflection(vec3 wo, vec3 h, float alpha) {
    if (!(wo.z > 0.0f)) {
        return 0.0f;
    }
    return ggx_d(h, alpha) * 0.5f / (wo.z + ggx_lambda_term(wo.z, alpha));
}

// ---- Anisotropic GGX (KHR_materials_anisotropy) ----------------------------------------------------------------
#ifndef GGX_HAS_ANISOTROPY
#define GGX_HAS_ANISOTROPY true
#endif

// A GGX lobe's roughness: alpha_t along `direction` (a unit vector in the local xy-plane), alpha across it. The
// extension stretches the tangent's way only: alpha_t = mix(alpha, 1, strength^2) >= alpha. alpha_t == alpha is
// the isotropic lobe, evaluated by the isotropic functions above (the same bits). Stages compiled without
// EFFECT_ANISOTROPY define GGX_HAS_ANISOTROPY false, which leaves only the isotropic code.
struct GgxRoughness {
    float alpha;     // across the direction (the isotropic alpha)
    float alpha_t;   // along it
    vec2 direction;
};

GgxRoughness make_isotropic_roughness(float alpha) {
    GgxRoughness r;
    r.alpha = alpha;
    r.alpha_t = alpha;
    r.direction = vec2(1.0f, 0.0f);
    return r;
}

bool is_anisotropic(GgxRoughness r) {
    return GGX_HAS_ANISOTROPY && r.alpha_t > r.alpha;
}

// w in the lobe's own frame: x along the direction, y across it, z the normal.
vec3 to_lobe_frame(GgxRoughness r, vec3 w) {
    return vec3(r.direction.x * w.x + r.direction.y * w.y, r.direction.x * w.y - r.direction.y * w.x, w.z);
}

vec3 from_lobe_frame(GgxRoughness r, vec3 w) {
    return vec3(r.direction.x * w.x - r.direction.y * w.y, r.direction.y * w.x + r.direction.x * w.y, w.z);
}

// D(h) = 1 / (pi ax ay ((h.x / ax)^2 + (h.y / ay)^2 + h.z^2)^2) (Heitz 2014 eq. 85 for a unit h), in the lobe frame.
float ggx_d_lobe(GgxRoughness r, vec3 h) {
    if (!is_anisotropic(r)) {
        return ggx_d(h, r.alpha);
    }
    vec3 m = to_lobe_frame(r, h);
    float t = (m.x * m.x) / (r.alpha_t * r.alpha_t) + (m.y * m.y) / (r.alpha * r.alpha) + m.z * m.z;
    return 1.0f / (PI * r.alpha_t * r.alpha * t * t);
}

// The anisotropic ggx_lambda_term: cos sqrt(1 + alpha(phi)^2 tan^2) = sqrt(z^2 + (ax x)^2 + (ay y)^2) for a unit w
// (Heitz 2014 eq. 86: the projected roughness alpha(phi)^2 = ax^2 cos^2 phi + ay^2 sin^2 phi). Sign-free in z.
float ggx_lambda_term_lobe(GgxRoughness r, vec3 w) {
    vec3 m = to_lobe_frame(r, w);
    float x = r.alpha_t * m.x;
    float y = r.alpha * m.y;
    return sqrt(m.z * m.z + x * x + y * y);
}

// alpha(phi) = sqrt(ax^2 cos^2 phi + ay^2 sin^2 phi) for the azimuth phi from the direction, given cos^2 phi.
float projected_alpha_at(GgxRoughness r, float cos2_phi) {
    return sqrt(r.alpha_t * r.alpha_t * cos2_phi + r.alpha * r.alpha * (1.0f - cos2_phi));
}

// The projected roughness alpha(phi) = sqrt(ax^2 cos^2 phi + ay^2 sin^2 phi) of w's azimuth phi (the isotropic alpha
// that masks w as the lobe does); at the normal, where phi is undefined, the root mean square of the two.
float projected_alpha(GgxRoughness r, vec3 w) {
    vec3 m = to_lobe_frame(r, w);
    float s2 = m.x * m.x + m.y * m.y;
    if (!(s2 > 0.0f)) {
        return sqrt(0.5f * (r.alpha_t * r.alpha_t + r.alpha * r.alpha));
    }
    return projected_alpha_at(r, m.x * m.x / s2);
}

// V(wo, wi) cos(theta_i) as ggx_v_cos, for wo.z > 0 and wi.z > 0 (a transmitted wi: pass -wi).
float ggx_v_cos_lobe(GgxRoughness r, vec3 wo, vec3 wi) {
    if (!is_anisotropic(r)) {
        return ggx_v_cos(wo.z, wi.z, r.alpha);
    }
    if (!(wo.z > 0.0f && wi.z > 0.0f)) {
        return 0.0f;
    }
    return 0.5f / (ggx_lambda_term_lobe(r, wo) + (wo.z / wi.z) * ggx_lambda_term_lobe(r, wi));
}

// A microfacet normal from the visible normals of the lobe (sample_ggx_vndf stretched by (alpha_t, alpha)).
vec3 sample_ggx_vndf_lobe(GgxRoughness r, vec3 wo, vec2 u) {
    if (!is_anisotropic(r)) {
        return sample_ggx_vndf(wo, r.alpha, u);
    }
    return from_lobe_frame(r, sample_ggx_vndf_stretched(to_lobe_frame(r, wo), vec2(r.alpha_t, r.alpha), u));
}

// pdf_ggx_vndf_reflection of the lobe: D(h) G1(wo) / (4 wo.z) = D(h) 0.5 / (wo.z + lambda_term(wo)).
float pdf_ggx_vndf_reflection_lobe(GgxRoughness r, vec3 wo, vec3 h) {
    if (!is_anisotropic(r)) {
        return pdf_ggx_vndf_reflection(wo, h, r.alpha);
    }
    if (!(wo.z > 0.0f)) {
        return 0.0f;
    }
    return ggx_d_lobe(r, h) * 0.5f / (wo.z + ggx_lambda_term_lobe(r, wo));
}

#endif
