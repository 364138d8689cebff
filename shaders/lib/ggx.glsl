// The isotropic Trowbridge-Reitz (GGX) microfacet distribution in the local frame (z = normal): normal
// distribution, height-correlated Smith visibility, and visible-normal sampling with its pdf.
// Shared GLSL/C++ subset (see cpp_compat.h). All directions are unit vectors with z > 0 where it matters.
#ifndef FREDHOLM_LIB_GGX_GLSL
#define FREDHOLM_LIB_GGX_GLSL

#include "sampling.glsl"

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
// Returns vec3(0) in the measure-zero degenerate case where the stretched normal vanishes.
vec3 sample_ggx_vndf(vec3 wo, float alpha, vec2 u) {
    vec3 wo_std = normalize(vec3(alpha * wo.x, alpha * wo.y, wo.z));
    float phi = TWO_PI * u.x;
    float z = (1.0f - u.y) * (1.0f + wo_std.z) - wo_std.z;  // uniform in [-wo_std.z, 1]
    float sin_theta = sqrt(clamp(1.0f - z * z, 0.0f, 1.0f));
    vec3 h_std = vec3(sin_theta * cos(phi), sin_theta * sin(phi), z) + wo_std;
    vec3 h = vec3(alpha * h_std.x, alpha * h_std.y, max(h_std.z, 0.0f));
    float len = length(h);
    if (!(len > 1.0e-18f)) {
        return vec3(0.0f);
    }
    return h / len;
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

#endif
