// Directional albedo E of the white anisotropic GGX lobe (KHR_materials_anisotropy: alpha_t along the direction,
// alpha across it), looked up in the precomputed table of ggx_anisotropic_albedo_table.glsl, for the metal's and the
// specular layer's multiple-scattering lobe (ggx_multiscatter.glsl), which needs what single scattering loses, 1 - E, for every
// direction: an anisotropic lobe's E depends on the azimuth as well as on the angle, and no isotropic albedo bounds
// it (a white metal of roughness 0.02 stretched to alpha_t = 1 keeps 0.53 of the light head-on). The table's nodes
// are raised so that the interpolant never underestimates E (bsdf.glsl needs E_table >= E_true). Shared GLSL/C++.
#ifndef FH_GGX_ANISOTROPIC_ALBEDO_GLSL
#define FH_GGX_ANISOTROPIC_ALBEDO_GLSL

#include "lib/bsdf/ggx_albedo.glsl"
#include "lib/tables/ggx_anisotropic_albedo_table.glsl"

// Table entry i (see ggx_anisotropic_albedo_table.glsl for the order). On the GPU the table is a storage buffer
// (BINDING_ANISOTROPIC_ALBEDO, uploaded only for scenes with an anisotropic rough lobe) read through this accessor,
// which bindings.glsl defines; the C++ tests read the arrays directly.
#ifdef __cplusplus
inline float ggx_anisotropic_albedo_entry(int i) {
    if (i < GGX_ANISOTROPIC_ALBEDO_AVERAGE_OFFSET) return GGX_ANISOTROPIC_ALBEDO[i];
    return GGX_ANISOTROPIC_ALBEDO_AVERAGE[i - GGX_ANISOTROPIC_ALBEDO_AVERAGE_OFFSET];
}
#endif

// The lobe's slice of the table: alpha (log-spaced, as ggx_albedo.glsl's rows) and the stretch
// s = (alpha_t - alpha) / (1 - alpha) in [0, 1] (strength^2 as the extension defines alpha_t), bilinear between
// the four slices around it.
struct GgxAnisotropicCell {
    int index;  // of the lower corner slice: stretch * ALPHA_SIZE + alpha
    vec2 frac;  // position between the slices, (alpha, stretch)
};

GgxAnisotropicCell ggx_anisotropic_cell(float alpha, float alpha_t) {
    float z = ggx_albedo_alpha_coordinate(alpha) * float(GGX_ANISOTROPIC_ALBEDO_ALPHA_SIZE - 1);
    float stretch = alpha < 1.0f ? clamp((alpha_t - alpha) / (1.0f - alpha), 0.0f, 1.0f) : 0.0f;
    float w = stretch * float(GGX_ANISOTROPIC_ALBEDO_STRETCH_SIZE - 1);
    int k = min(int(z), GGX_ANISOTROPIC_ALBEDO_ALPHA_SIZE - 2);
    int l = min(int(w), GGX_ANISOTROPIC_ALBEDO_STRETCH_SIZE - 2);
    GgxAnisotropicCell c;
    c.index = l * GGX_ANISOTROPIC_ALBEDO_ALPHA_SIZE + k;
    c.frac = vec2(z - float(k), w - float(l));
    return c;
}

// Bilinear in (mu^(1/3), azimuth) on slice `slice`, at the lower corner `corner` of the (mu, azimuth) cell.
float ggx_anisotropic_slice(int slice, int corner, vec2 frac) {
    int base = slice * GGX_ANISOTROPIC_ALBEDO_MU_SIZE * GGX_ANISOTROPIC_ALBEDO_AZIMUTH_SIZE + corner;
    int n = GGX_ANISOTROPIC_ALBEDO_MU_SIZE;
    float lower = mix(ggx_anisotropic_albedo_entry(base), ggx_anisotropic_albedo_entry(base + 1), frac.x);
    float upper = mix(ggx_anisotropic_albedo_entry(base + n), ggx_anisotropic_albedo_entry(base + n + 1), frac.x);
    return mix(lower, upper, frac.y);
}

// E(w) of the white lobe for w in the lobe's frame (x along the direction, z the normal; w.z > 0): the azimuth is
// folded into [0, pi/2] (the lobe is symmetric about both of its axes) and the table read quadrilinearly.
float ggx_anisotropic_white_albedo(GgxAnisotropicCell c, vec3 w) {
    float x = pow(clamp(w.z, 0.0f, 1.0f), 1.0f / 3.0f) * float(GGX_ANISOTROPIC_ALBEDO_MU_SIZE - 1);
    float s2 = w.x * w.x + w.y * w.y;
    float phi = s2 > 0.0f ? atan(abs(w.y), abs(w.x)) : 0.0f;  // at the normal every azimuth reads the same
    float y = clamp(phi * (2.0f / PI), 0.0f, 1.0f) * float(GGX_ANISOTROPIC_ALBEDO_AZIMUTH_SIZE - 1);
    int i = min(int(x), GGX_ANISOTROPIC_ALBEDO_MU_SIZE - 2);
    int j = min(int(y), GGX_ANISOTROPIC_ALBEDO_AZIMUTH_SIZE - 2);
    int corner = j * GGX_ANISOTROPIC_ALBEDO_MU_SIZE + i;
    vec2 frac = vec2(x - float(i), y - float(j));
    int n = GGX_ANISOTROPIC_ALBEDO_ALPHA_SIZE;
    float lower = mix(ggx_anisotropic_slice(c.index, corner, frac), ggx_anisotropic_slice(c.index + 1, corner, frac),
                      c.frac.x);
    float upper = mix(ggx_anisotropic_slice(c.index + n, corner, frac),
                      ggx_anisotropic_slice(c.index + n + 1, corner, frac), c.frac.x);
    return mix(lower, upper, c.frac.y);  // the nodes are at most 1
}

// E_avg = (1 / pi) int E(w) cos dw over the hemisphere, of the interpolated table (exact for it up to float
// rounding: the table stores each slice's average, and the interpolant is bilinear in the slices).
float ggx_anisotropic_white_albedo_average(GgxAnisotropicCell c) {
    int base = GGX_ANISOTROPIC_ALBEDO_AVERAGE_OFFSET + c.index;
    int n = GGX_ANISOTROPIC_ALBEDO_ALPHA_SIZE;
    float lower = mix(ggx_anisotropic_albedo_entry(base), ggx_anisotropic_albedo_entry(base + 1), c.frac.x);
    float upper = mix(ggx_anisotropic_albedo_entry(base + n), ggx_anisotropic_albedo_entry(base + n + 1), c.frac.x);
    return mix(lower, upper, c.frac.y);
}
#endif
