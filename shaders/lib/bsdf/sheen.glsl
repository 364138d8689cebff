// KHR_materials_sheen's lobe: the "Charlie" sheen of Estevez & Kulla 2017 ("Production Friendly Microfacet
// Sheen BRDF"), as the extension and the Khronos sample viewer define it, and its directional albedo looked up in
// sheen_albedo_table.glsl. Shared GLSL/C++ subset; the layering over the base is in bsdf.glsl.
//
//   f_sheen = sheenColor D(h) V(wo, wi),  D = (2 + 1/alpha) sin(theta_h)^(1/alpha) / (2 pi),  alpha = roughness^2
//   V = 1 / ((1 + Lambda(mu_o) + Lambda(mu_i)) 4 mu_o mu_i)      (Lambda: Estevez & Kulla's fit, their eq. 3)
//
// DEVIATION: that lobe reflects more than it receives at grazing angles for smooth sheens (its albedo E reaches
// 1.15 at roughness 0.2 and 2.5 at 0.07 for mu = 0.01: the fitted Lambda is not the Smith Lambda of D there), so
// we divide it by max(1, E(mu_o), E(mu_i)): symmetric in wo and wi (reciprocal), at most 1 in albedo, and the
// extension's lobe itself wherever that one conserves energy (E <= 1 both ways: every mu for roughness >= 0.3,
// mu >= 0.1 for any roughness). shaders/lib/bsdf/README.md "Sheen" has the numbers.
#ifndef FH_SHEEN_GLSL
#define FH_SHEEN_GLSL

#include "lib/sampling/sampling.glsl"
#include "lib/tables/sheen_albedo_table.glsl"

// Smallest sheen roughness: sheenRoughnessFactor 0 (the extension's default) reads as this, a sharp but finite
// lobe (D <= 2e2 / (2 pi)), the first row of the albedo table.
const float SHEEN_MIN_ROUGHNESS = SHEEN_ALBEDO_ROUGHNESS_MIN;

const float SHEEN_MIN_COSINE = 3.3567183e-5f;  // (1 / 31)^3: the albedo table's first non-zero mu

// The Charlie distribution for cos theta_h = `cos_h`: normalised, int D cos(theta_h) dh = 1.
float eval_charlie_d(float cos_h, float alpha) {
    float inv_alpha = 1.0f / alpha;
    float sin2 = max(1.0f - cos_h * cos_h, 0.0f);
    return (2.0f + inv_alpha) * pow(sin2, 0.5f * inv_alpha) * (0.5f * INV_PI);
}

// Estevez & Kulla's fit L(x) of ln Lambda, interpolated between roughness 0 and 1 by (1 - alpha)^2.
float fit_sheen_lambda(float x, float alpha) {
    float t = (1.0f - alpha) * (1.0f - alpha);
    float a = mix(21.5473f, 25.3245f, t);
    float b = mix(3.82987f, 3.32435f, t);
    float c = mix(0.19823f, 0.16801f, t);
    float d = mix(-1.97760f, -1.27393f, t);
    float e = mix(-4.32054f, -4.85967f, t);
    return a / (1.0f + b * pow(x, c)) + d * x + e;
}

float eval_sheen_lambda(float cos_theta, float alpha) {
    float c = clamp(cos_theta, 0.0f, 1.0f);
    if (c < 0.5f) {
        return exp(fit_sheen_lambda(c, alpha));
    }
    return exp(2.0f * fit_sheen_lambda(0.5f, alpha) - fit_sheen_lambda(1.0f - c, alpha));
}

// D(h) V(wo, wi) cos(theta_i) = D G2 / (4 mu_o) of the extension's lobe with sheenColor 1 (local frame, both
// directions above the surface; 0 otherwise).
float eval_charlie_sheen(vec3 wo, vec3 wi, float alpha) {
    if (!(wo.z > 0.0f && wi.z > 0.0f)) {
        return 0.0f;
    }
    // The albedo grows without bound as mu_o -> 0 (the fitted Lambda grows more slowly than 1 / mu): cosines are
    // clamped at SHEEN_MIN_COSINE (89.998 deg), as the table's reference is, so the table bounds it at every angle.
    vec3 h = normalize(wo + wi);
    float mu_o = max(wo.z, SHEEN_MIN_COSINE);
    float g2 = 1.0f / (1.0f + eval_sheen_lambda(mu_o, alpha) + eval_sheen_lambda(max(wi.z, SHEEN_MIN_COSINE), alpha));
    return eval_charlie_d(h.z, alpha) * g2 / (4.0f * mu_o);
}

// Table entry i (sheen_albedo_table.glsl). On the GPU bindings.glsl defines it (a uniform buffer); C++ reads the array.
#ifdef __cplusplus
inline float sheen_albedo_entry(int i) { return SHEEN_ALBEDO[i]; }
#endif

// E(mu, roughness) of the extension's lobe with sheenColor 1, bilinear in (mu^(1/3), roughness); the nodes are
// raised so that it never underestimates E (tests/unit/bsdf/test_sheen_albedo_table.cpp).
float sheen_albedo(float mu, float roughness) {
    float x = pow(clamp(mu, 0.0f, 1.0f), 1.0f / 3.0f) * float(SHEEN_ALBEDO_MU_SIZE - 1);
    float y = clamp((roughness - SHEEN_ALBEDO_ROUGHNESS_MIN) / (1.0f - SHEEN_ALBEDO_ROUGHNESS_MIN), 0.0f, 1.0f) *
              float(SHEEN_ALBEDO_ROUGHNESS_SIZE - 1);
    int i = min(int(x), SHEEN_ALBEDO_MU_SIZE - 2);
    int j = min(int(y), SHEEN_ALBEDO_ROUGHNESS_SIZE - 2);
    int k = j * SHEEN_ALBEDO_MU_SIZE + i;
    int n = SHEEN_ALBEDO_MU_SIZE;
    float fx = x - float(i);
    float lower = mix(sheen_albedo_entry(k), sheen_albedo_entry(k + 1), fx);
    float upper = mix(sheen_albedo_entry(k + n), sheen_albedo_entry(k + n + 1), fx);
    return mix(lower, upper, y - float(j));
}

// The energy-conserving lobe of the top of the file for sheenColor 1: f cos(theta_i).
float eval_sheen_lobe(vec3 wo, vec3 wi, float roughness) {
    float r = max(roughness, SHEEN_MIN_ROUGHNESS);
    float f = eval_charlie_sheen(wo, wi, r * r);
    if (!(f > 0.0f)) {
        return 0.0f;
    }
    return f / max(1.0f, max(sheen_albedo(wo.z, r), sheen_albedo(wi.z, r)));
}

#endif
