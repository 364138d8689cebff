// Directional albedo of the GGX specular lobe for any Schlick Fresnel, looked up in the precomputed table
// of ggx_albedo_table.glsl: the lobe with F = f0 + (f90 - f0) (1 - v.h)^5 reflects f0 A + f90 B of the
// light arriving from cos theta = mu (Schlick is linear in f0 and f90). Shared GLSL/C++ subset.
#ifndef FH_GGX_ALBEDO_GLSL
#define FH_GGX_ALBEDO_GLSL

#include "lib/tables/ggx_albedo_table.glsl"

// Table entry i (see ggx_albedo_table.glsl for the order). On the GPU the table is a uniform buffer and
// bindings.glsl defines this accessor; the C++ tests read the arrays directly.
#ifdef __cplusplus
inline float ggx_albedo_entry(int i) {
    if (i < GGX_ALBEDO_B_OFFSET) return GGX_ALBEDO_A[i];
    if (i < GGX_ALBEDO_AVERAGE_A_OFFSET) return GGX_ALBEDO_B[i - GGX_ALBEDO_B_OFFSET];
    if (i < GGX_ALBEDO_AVERAGE_B_OFFSET) return GGX_ALBEDO_AVERAGE_A[i - GGX_ALBEDO_AVERAGE_A_OFFSET];
    return GGX_ALBEDO_AVERAGE_B[i - GGX_ALBEDO_AVERAGE_B_OFFSET];
}
#endif

vec2 ggx_albedo_node(int k) {
    return vec2(ggx_albedo_entry(GGX_ALBEDO_A_OFFSET + k), ggx_albedo_entry(GGX_ALBEDO_B_OFFSET + k));
}

vec2 ggx_albedo_average_node(int j) {
    return vec2(ggx_albedo_entry(GGX_ALBEDO_AVERAGE_A_OFFSET + j), ggx_albedo_entry(GGX_ALBEDO_AVERAGE_B_OFFSET + j));
}

// alpha's table coordinate in [0, 1]: log-spaced from GGX_ALBEDO_ALPHA_MIN (and below it the first row) to 1.
float ggx_albedo_alpha_coordinate(float alpha) {
    return clamp(log(alpha / GGX_ALBEDO_ALPHA_MIN) * GGX_ALBEDO_INV_LOG_ALPHA_RANGE, 0.0f, 1.0f);
}

// Table coordinates: mu^(1/3) puts nodes where the albedo falls off at grazing angles (mu ~ alpha) and
// log(alpha) resolves that fall-off equally for every alpha (at 32 x 32, max interpolation error 3e-3, against
// 6e-2 for a table uniform in mu). alpha below GGX_ALBEDO_ALPHA_MIN reads the first row.
struct GgxAlbedoCell {
    int index;   // of the lower corner: alpha row * GGX_ALBEDO_MU_SIZE + mu column
    vec2 frac;   // position inside the cell, (mu, alpha)
};

GgxAlbedoCell ggx_albedo_cell(float mu, float alpha) {
    float x = pow(clamp(mu, 0.0f, 1.0f), 1.0f / 3.0f) * float(GGX_ALBEDO_MU_SIZE - 1);
    float y = ggx_albedo_alpha_coordinate(alpha) * float(GGX_ALBEDO_ALPHA_SIZE - 1);
    int i = min(int(x), GGX_ALBEDO_MU_SIZE - 2);
    int j = min(int(y), GGX_ALBEDO_ALPHA_SIZE - 2);
    GgxAlbedoCell c;
    c.index = j * GGX_ALBEDO_MU_SIZE + i;
    c.frac = vec2(x - float(i), y - float(j));
    return c;
}

// vec2(A, B) at (mu, alpha), bilinear. The table's nodes are raised so that this never underestimates B, nor
// A except by <= 1.2e-3 where A + B is capped at 1 (small alpha): the energy-conserving BSDF needs
// E_table >= E_true (see bsdf.glsl and tests/unit/bsdf/test_ggx_albedo_table.cpp).
vec2 ggx_albedo(float mu, float alpha) {
    GgxAlbedoCell c = ggx_albedo_cell(mu, alpha);
    int k = c.index;
    int n = GGX_ALBEDO_MU_SIZE;
    vec2 lower = mix(ggx_albedo_node(k), ggx_albedo_node(k + 1), c.frac.x);
    vec2 upper = mix(ggx_albedo_node(k + n), ggx_albedo_node(k + n + 1), c.frac.x);
    return mix(lower, upper, c.frac.y);
}

// vec2(A_avg, B_avg) = 2 int_0^1 ggx_albedo(mu, alpha) mu dmu: the cosine-weighted hemispherical average,
// exact for the interpolated table (linear in alpha's coordinate, as ggx_albedo is).
vec2 ggx_albedo_average(float alpha) {
    float y = ggx_albedo_alpha_coordinate(alpha) * float(GGX_ALBEDO_ALPHA_SIZE - 1);
    int j = min(int(y), GGX_ALBEDO_ALPHA_SIZE - 2);
    return mix(ggx_albedo_average_node(j), ggx_albedo_average_node(j + 1), y - float(j));
}

#endif
