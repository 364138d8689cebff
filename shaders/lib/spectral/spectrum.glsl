// The spectral path (EFFECT_SPECTRAL): the four wavelengths a path carries (hero wavelength sampling, Wilkie et al.
// 2014, "Hero Wavelength Spectral Sampling"), the smooth spectrum of a linear Rec.709 colour, the film's linear
// Rec.709 of a path's four spectral values, and the index of refraction of a dispersive glass. The tables are in
// spectral_table.glsl (tests/unit/bsdf/make_spectral_table.py). Shared GLSL/C++ subset.
//
// Conventions: a colour c (reflectance, emission, absorption coefficient) is the spectrum B(lambda) . c, linear in c
// (B sums to 1, so white is the constant 1, and a reflectance in [0, 1] stays in [0, 1]); emitters are D65-white, and
// the film folds D65 into its weights, so a render whose light never meets a coloured surface twice gives the RGB
// render's image in expectation.
#ifndef FH_SPECTRUM_GLSL
#define FH_SPECTRUM_GLSL

#include "lib/tables/spectral_table.glsl"

// vec4 i of the table (node n: 2n is its basis, 2n + 1 its film weight). On the GPU the table is a uniform buffer
// and bindings.glsl defines this accessor; the C++ tests read the array directly.
#ifdef __cplusplus
inline vec4 spectral_table_vec4(int i) {
    return vec4(SPECTRAL_TABLE[4 * i], SPECTRAL_TABLE[4 * i + 1], SPECTRAL_TABLE[4 * i + 2], SPECTRAL_TABLE[4 * i + 3]);
}
#endif

const float VISIBLE_LAMBDA_MIN = 360.0f;  // nm: the range wavelengths are sampled from
const float VISIBLE_LAMBDA_MAX = 830.0f;

// A wavelength in [360, 830] nm with pdf proportional to 1 / cosh^2(0.0072 (lambda - 538)), which follows the
// luminance of visible light (pbrt-v4's SampleVisibleWavelengths; the constants normalise it on this range).
float sample_visible_wavelength(float u) {
    return 538.0f - 138.888889f * atanh(0.85691062f - 1.82750197f * u);
}

float pdf_visible_wavelength(float lambda) {
    if (lambda < VISIBLE_LAMBDA_MIN || lambda > VISIBLE_LAMBDA_MAX) return 0.0f;
    float c = cosh(0.0072f * (lambda - 538.0f));
    return 0.0039398042f / (c * c);
}

// A path's four wavelengths: the hero's at u and the others at u + k / 4 (mod 1), each distributed by the pdf
// above, so the film's average over the four is an unbiased estimate for every wavelength (Wilkie et al. 2014).
vec4 sample_wavelengths(float u) {
    vec4 lambda;
    for (int k = 0; k < 4; ++k) lambda[k] = sample_visible_wavelength(fract(u + 0.25f * float(k)));
    return lambda;
}

// What the spectral stages need of a path's four wavelengths: from_rgb * c is colour c's spectrum at them, and
// to_film * s the linear Rec.709 estimate of spectrum s (the film weight over four times the wavelength's pdf).
struct SpectralFrame {
    vec4 lambda;
    mat3x4 from_rgb;
    mat4x3 to_film;
};

SpectralFrame make_spectral_frame(float u) {
    SpectralFrame f;
    f.lambda = sample_wavelengths(u);
    for (int k = 0; k < 4; ++k) {
        float x = (f.lambda[k] - SPECTRAL_LAMBDA_MIN) / SPECTRAL_LAMBDA_STEP;
        int n = clamp(int(floor(x)), 0, SPECTRAL_NODE_COUNT - 2);
        float t = clamp(x - float(n), 0.0f, 1.0f);
        vec4 basis = mix(spectral_table_vec4(2 * n), spectral_table_vec4(2 * n + 2), t);
        vec4 film = mix(spectral_table_vec4(2 * n + 1), spectral_table_vec4(2 * n + 3), t);
        f.from_rgb[0][k] = basis.x;
        f.from_rgb[1][k] = basis.y;
        f.from_rgb[2][k] = basis.z;
        f.to_film[k] = vec3(film) / (4.0f * pdf_visible_wavelength(f.lambda[k]));
    }
    return f;
}

// Colour c's spectrum at the path's wavelengths.
vec4 upsample_rgb(SpectralFrame f, vec3 c) { return f.from_rgb * c; }

// The film's linear Rec.709 of spectral values s at the path's wavelengths.
vec3 integrate_film(SpectralFrame f, vec4 s) { return f.to_film * s; }

// After a dispersive refraction only the hero wavelength's direction is right: the others stop, and the hero
// stands for all four (its weight is the film's 1/4 of one wavelength, times 4), as pbrt-v4's TerminateSecondary.
vec4 terminate_secondary_wavelengths(vec4 throughput) { return vec4(4.0f * throughput.x, 0.0f, 0.0f, 0.0f); }

// KHR_materials_dispersion: the index at wavelength lambda (nm) of a glass of index `ior` at 587.6 nm and
// dispersion 20 / V_d, from the first two terms of Cauchy's equation fitted to the Abbe number, as the extension
// writes it: max(n_d + (n_d - 1) / V_d (523655 / lambda^2 - 1.5168), 1).
float eval_dispersive_ior(float ior, float dispersion, float lambda) {
    return max(ior + (ior - 1.0f) * (dispersion / 20.0f) * (523655.0f / (lambda * lambda) - 1.5168f), 1.0f);
}

#endif
