// The energy the glass lobe's single scattering loses (light that bounces between microfacets before leaving),
// given back as a diffuse-like lobe on either side (Kulla & Conty 2017, "Revisiting Physically Based Shading at
// Imageworks", the dielectric case), so that white rough glass conserves energy. Shared GLSL/C++ subset.
//
// E_s(mu) is the single-scattering energy albedo of white glass (reflection plus transmission, transmission counted
// as energy, without the radiance scaling 1 / eta^2) seen from side s at cos theta = mu; E_avg its cosine-weighted
// average (glass_albedo_table.glsl, made by tests/unit/bsdf/test_glass_albedo_table.cpp; nodes raised so that E_table >=
// E_true, hence the lobe below never gives back more than was lost). For light from side o into side i:
//   reflected   f cos = (1 - t_o) (1 - E_o(mu_o)) (1 - E_o(mu_i)) mu_i / (pi (1 - E_avg_o))
//   transmitted f cos = K (1 - E_o(mu_o)) (1 - E_i(mu_i)) |mu_i| / min(eta, 1)^2        (radiance, eta = n_i / n_o)
// The reflected part integrates to (1 - t_o) (1 - E_o(mu_o)); the transmitted part, as energy (times eta^2), to
// t_o (1 - E_o(mu_o)) with t_o = max(eta, 1)^2 K pi (1 - E_avg_i). Together: exactly what single scattering lost.
// One K serves both sides, so f(wo, wi) / n_o^2 = f(wi, wo) / n_i^2 (generalised reciprocity) holds exactly; K is
// chosen per (roughness, ior) so that light from outside passes in the share a smooth interface passes on average,
// t_out = 1 - F_avg, unless that would make t_in > 1 (then t_in = 1).
// Thin-walled glass keeps no medium: its single-scattering energy is the white GGX mirror's, A + B
// (ggx_albedo.glsl), and t = 1 - F_avg on both sides (symmetric, hence reciprocal).
// Reflections are tinted by the glass's specular colour times specularFactor, transmissions by the base colour
// (as single scattering tints them). Anisotropic glass uses its smaller alpha (less loss assumed: never a gain).
// An ior beyond the table (above 3) gets no compensation, nor does smooth glass (alpha at GLASS_SMOOTH_ALPHA, where single
// scattering loses under 1e-4): a roughness of 0 renders the same bits with or without the lobe.
#ifndef FH_GLASS_MULTISCATTER_GLSL
#define FH_GLASS_MULTISCATTER_GLSL

#include "lib/sampling/sampling.glsl"
#include "lib/bsdf/ggx_albedo.glsl"
#include "lib/tables/glass_albedo_table.glsl"

// Table entry i (see glass_albedo_table.glsl for the order). On the GPU the table is a storage buffer read through
// this accessor, defined by bindings.glsl; the C++ tests read the arrays directly.
#ifdef __cplusplus
inline float glass_albedo_entry(int i) {
    if (i < GLASS_ALBEDO_IN_OFFSET) return GLASS_ALBEDO_OUT[i];
    if (i < GLASS_ALBEDO_AVERAGE_OUT_OFFSET) return GLASS_ALBEDO_IN[i - GLASS_ALBEDO_IN_OFFSET];
    if (i < GLASS_ALBEDO_AVERAGE_IN_OFFSET) return GLASS_ALBEDO_AVERAGE_OUT[i - GLASS_ALBEDO_AVERAGE_OUT_OFFSET];
    if (i < GLASS_ALBEDO_K_OFFSET) return GLASS_ALBEDO_AVERAGE_IN[i - GLASS_ALBEDO_AVERAGE_IN_OFFSET];
    if (i < GLASS_ALBEDO_F_AVERAGE_OFFSET) return GLASS_ALBEDO_K[i - GLASS_ALBEDO_K_OFFSET];
    return GLASS_ALBEDO_F_AVERAGE[i - GLASS_ALBEDO_F_AVERAGE_OFFSET];
}
#endif

// Where (alpha, eta) falls in the table: the lower corner of the (roughness, eta) cell and the position inside it.
// Table coordinates: sqrt(alpha) (the perceptual roughness) and (n - 1) / (n + 1) for n = max(eta, 1 / eta), the same
// for both sides of an interface.
struct GlassTableCell {
    int index;   // roughness row j, eta slice k: k * GLASS_ALBEDO_ROUGHNESS_SIZE + j
    vec2 frac;   // (roughness, eta)
    uint valid;  // 0: eta beyond the table (no compensation)
};

GlassTableCell glass_table_cell(float alpha, float eta) {
    GlassTableCell c;
    float n = eta >= 1.0f ? eta : 1.0f / max(eta, 1.0e-4f);
    float z = (n - 1.0f) / (n + 1.0f) / GLASS_ALBEDO_ETA_COORD_MAX * float(GLASS_ALBEDO_ETA_SIZE - 1);
    float y = clamp(sqrt(alpha), 0.0f, 1.0f) * float(GLASS_ALBEDO_ROUGHNESS_SIZE - 1);
    int j = min(int(y), GLASS_ALBEDO_ROUGHNESS_SIZE - 2);
    int k = min(int(z), GLASS_ALBEDO_ETA_SIZE - 2);
    c.index = k * GLASS_ALBEDO_ROUGHNESS_SIZE + j;
    c.frac = vec2(y - float(j), z - float(k));
    c.valid = z <= float(GLASS_ALBEDO_ETA_SIZE - 1) ? 1u : 0u;
    return c;
}

// A per-(roughness, eta) value at `offset`, bilinear in the cell.
float glass_table_2d(GlassTableCell c, int offset) {
    int n = GLASS_ALBEDO_ROUGHNESS_SIZE;
    float lower = mix(glass_albedo_entry(offset + c.index), glass_albedo_entry(offset + c.index + 1), c.frac.x);
    float upper = mix(glass_albedo_entry(offset + c.index + n), glass_albedo_entry(offset + c.index + n + 1), c.frac.x);
    return mix(lower, upper, c.frac.y);
}

// The table's mu coordinate in [0, 1]: sqrt(mu) from outside; from inside, where total internal reflection puts a kink
// at the critical angle's cosine mu_c (which moves with the index), the kink is pinned to 0.5: 0.5 sqrt(mu / mu_c)
// below it, linear above, so that interpolating between indices does not smear it.
float glass_table_mu_coordinate(float mu, float critical_mu) {
    float m = clamp(mu, 0.0f, 1.0f);
    if (critical_mu < 0.0f) {
        return sqrt(m);
    }
    if (m <= critical_mu) {
        return 0.5f * sqrt(m / max(critical_mu, 1.0e-8f));
    }
    return min(0.5f + 0.5f * (m - critical_mu) / max(1.0f - critical_mu, 1.0e-8f), 1.0f);
}

// mu_c = sqrt(1 - 1 / n^2) of the interface of index ratio max(eta, 1 / eta).
float glass_critical_mu(float eta) {
    float n = eta >= 1.0f ? eta : 1.0f / max(eta, 1.0e-4f);
    return sqrt(max(1.0f - 1.0f / (n * n), 0.0f));
}

// E_s(mu) of the side whose table starts at `offset` (GLASS_ALBEDO_OUT_OFFSET or _IN_OFFSET), trilinear in the mu
// coordinate above (critical_mu: the interface's, used from inside).
float glass_table_energy(GlassTableCell c, int offset, float mu, float critical_mu) {
    float x = glass_table_mu_coordinate(mu, offset == GLASS_ALBEDO_IN_OFFSET ? critical_mu : -1.0f) *
              float(GLASS_ALBEDO_MU_SIZE - 1);
    int i = min(int(x), GLASS_ALBEDO_MU_SIZE - 2);
    float fx = x - float(i);
    int m = GLASS_ALBEDO_MU_SIZE;
    int row = offset + c.index * m + i;  // (k * rough_size + j) * mu_size + i
    int n = GLASS_ALBEDO_ROUGHNESS_SIZE * m;
    float e00 = mix(glass_albedo_entry(row), glass_albedo_entry(row + 1), fx);
    float e10 = mix(glass_albedo_entry(row + m), glass_albedo_entry(row + m + 1), fx);
    float e01 = mix(glass_albedo_entry(row + n), glass_albedo_entry(row + n + 1), fx);
    float e11 = mix(glass_albedo_entry(row + n + m), glass_albedo_entry(row + n + m + 1), fx);
    return mix(mix(e00, e10, c.frac.x), mix(e01, e11, c.frac.x), c.frac.y);
}

// What the lobe needs of wo: its side's loss and how the lost energy splits.
struct GlassMultiscatter {
    GlassTableCell cell;
    int side_offset;      // the table of wo's side (refraction), or -1 (thin-walled: the GGX mirror's albedo)
    int beyond_offset;    // the table of the other side (refraction)
    float critical_mu;    // the interface's critical angle cosine (the inside table's mu coordinate)
    float loss;           // 1 - E_o(mu_o): what single scattering loses, the lobe's energy
    float transmit;       // t_o: the share of it that passes through
    float reflect_norm;   // (1 - t_o) / (pi (1 - E_avg_o)): the reflected part's constant
    float transmit_norm;  // the transmitted part's: K / min(eta, 1)^2, or thin-walled t / (pi (1 - E_avg))
};

// The white GGX mirror's albedo A + B (what a thin wall's single scattering keeps), at most 1.
float thin_glass_energy(float mu, float alpha) {
    vec2 e = ggx_albedo(mu, alpha);
    return min(e.x + e.y, 1.0f);
}

// The smallest GGX alpha (bsdf.glsl BSDF_MIN_ALPHA, roughness 0): glass that smooth gets no lobe.
const float GLASS_SMOOTH_ALPHA = 1.0e-3f;

// Floor of 1 - E_avg: below it the lobe has no energy to give (a smooth interface).
const float GLASS_MIN_AVERAGE_LOSS = 1.0e-6f;

GlassMultiscatter make_glass_multiscatter(float alpha, float eta, uint thin_walled, float mu_o) {
    GlassMultiscatter s;
    s.cell = glass_table_cell(alpha, eta);
    s.side_offset = -1;
    s.beyond_offset = -1;
    s.critical_mu = glass_critical_mu(eta);
    s.loss = 0.0f;
    s.transmit = 0.0f;
    s.reflect_norm = 0.0f;
    s.transmit_norm = 0.0f;
    if (s.cell.valid == 0u || !(alpha > GLASS_SMOOTH_ALPHA)) {
        return s;  // beyond the table, or smooth glass (roughness 0: nothing to give back, exactly)
    }
    float f_average = mix(glass_albedo_entry(GLASS_ALBEDO_F_AVERAGE_OFFSET + s.cell.index / GLASS_ALBEDO_ROUGHNESS_SIZE),
                          glass_albedo_entry(GLASS_ALBEDO_F_AVERAGE_OFFSET + s.cell.index / GLASS_ALBEDO_ROUGHNESS_SIZE + 1),
                          s.cell.frac.y);
    if (thin_walled != 0u) {
        vec2 average = ggx_albedo_average(alpha);
        float loss_average = 1.0f - min(average.x + average.y, 1.0f);
        if (!(loss_average > GLASS_MIN_AVERAGE_LOSS)) {
            return s;
        }
        s.loss = 1.0f - thin_glass_energy(mu_o, alpha);
        s.transmit = clamp(1.0f - f_average, 0.0f, 1.0f);
        s.reflect_norm = (1.0f - s.transmit) * INV_PI / loss_average;
        s.transmit_norm = s.transmit * INV_PI / loss_average;
        return s;
    }
    bool outside = eta >= 1.0f;
    s.side_offset = outside ? GLASS_ALBEDO_OUT_OFFSET : GLASS_ALBEDO_IN_OFFSET;
    s.beyond_offset = outside ? GLASS_ALBEDO_IN_OFFSET : GLASS_ALBEDO_OUT_OFFSET;
    float loss_average = 1.0f - glass_table_2d(s.cell, outside ? GLASS_ALBEDO_AVERAGE_OUT_OFFSET : GLASS_ALBEDO_AVERAGE_IN_OFFSET);
    float loss_beyond = 1.0f - glass_table_2d(s.cell, outside ? GLASS_ALBEDO_AVERAGE_IN_OFFSET : GLASS_ALBEDO_AVERAGE_OUT_OFFSET);
    if (!(loss_average > GLASS_MIN_AVERAGE_LOSS && loss_beyond > GLASS_MIN_AVERAGE_LOSS)) {
        return s;
    }
    float k = max(glass_table_2d(s.cell, GLASS_ALBEDO_K_OFFSET), 0.0f);
    float n = max(eta, 1.0f);
    float m = min(eta, 1.0f);
    s.loss = max(1.0f - glass_table_energy(s.cell, s.side_offset, mu_o, s.critical_mu), 0.0f);
    // t_o <= 1 holds at the table's nodes; where interpolation passes it, the transmitted part is scaled back to
    // the loss (energy first: reciprocity then holds only to that rounding).
    float transmit = n * n * k * PI * loss_beyond;
    s.transmit = min(transmit, 1.0f);
    s.reflect_norm = (1.0f - s.transmit) * INV_PI / loss_average;
    s.transmit_norm = k / (m * m) / max(transmit, 1.0f);
    return s;
}

// 1 - E(mu) on the side of wi: wo's side for a reflection, the other side for a transmission (a thin wall has one).
float glass_multiscatter_loss_at(GlassMultiscatter s, float alpha, vec3 wi) {
    float mu = abs(wi.z);
    if (s.side_offset < 0) {
        return 1.0f - thin_glass_energy(mu, alpha);
    }
    return max(1.0f - glass_table_energy(s.cell, wi.z > 0.0f ? s.side_offset : s.beyond_offset, mu, s.critical_mu), 0.0f);
}

// f cos(theta_i) of the lobe without its tints, for wi on either side (wo.z > 0).
float eval_glass_multiscatter(GlassMultiscatter s, float alpha, vec3 wi) {
    if (!(s.loss > 0.0f) || wi.z == 0.0f) {
        return 0.0f;
    }
    float norm = wi.z > 0.0f ? s.reflect_norm : s.transmit_norm;
    return s.loss * glass_multiscatter_loss_at(s, alpha, wi) * abs(wi.z) * norm;
}

// Solid-angle pdf of sample_glass_multiscatter: cosine-weighted on the side picked with the energy shares.
float pdf_glass_multiscatter(GlassMultiscatter s, vec3 wi) {
    float share = wi.z > 0.0f ? 1.0f - s.transmit : s.transmit;
    return share * abs(wi.z) * INV_PI;
}

// u.x < t_o: through (cosine-weighted below), else back (above); u.yz pick the direction.
vec3 sample_glass_multiscatter(GlassMultiscatter s, vec3 u) {
    vec3 w = sample_cosine_hemisphere(vec2(u.y, u.z));
    if (u.x < s.transmit) {
        w.z = -w.z;
    }
    return w;
}

#endif
