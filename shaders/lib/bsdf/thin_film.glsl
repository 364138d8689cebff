// KHR_materials_iridescence: the reflectance of a thin dielectric film (the "iridescence" layer) lying on a
// surface, as the extension defines it from Belcour & Barla 2017, "A Practical Extension to Microfacet Theory for
// the Modeling of Varying Iridescence": two interfaces with Schlick reflectances (air | film, film | base, the base's
// index inferred from its F0, extinction ignored), their Airy sum of multiple reflections, and the integral over
// the visible spectrum done in Fourier space against Gaussian fits of the CIE XYZ matching functions (terms m = 1,
// 2), then XYZ -> linear Rec.709. Shared GLSL/C++ subset.
//
// DEVIATION: the extension clamps the result below at 0 only. The XYZ -> RGB matrix takes some interference
// colours out of gamut, above 1 in a channel (1.26 over a base of f0 0.9 at worst, on a grid of films of index 1 to
// 2.3 and 0 to 1200 nm: Iridescence.ClampKeepsTheFilmFromMakingLight prints it), and a reflectance above 1 makes light;
// eval_thin_film_fresnel clamps each channel to [0, 1].
#ifndef FH_THIN_FILM_GLSL
#define FH_THIN_FILM_GLSL

#include "lib/sampling/sampling.glsl"

// CIE XYZ -> linear Rec.709 (sRGB primaries, D65 white), column-major as GLSL's mat3.
const mat3 XYZ_TO_LINEAR_REC709 = mat3(3.2404542f, -0.9692660f, 0.0556434f, -1.5371385f, 1.8760108f, -0.2040259f,
                                       -0.4985314f, 0.0415560f, 1.0572252f);

// A film thinner than this (nm) fades out: its index goes to the outside's as the thickness goes to 0.
const float THIN_FILM_FADE_THICKNESS = 0.03f;

// Schlick's Fresnel with reflectance 1 at grazing incidence, per channel.
vec3 schlick_fresnel3(vec3 f0, float cos_theta) {
    float m = clamp(1.0f - cos_theta, 0.0f, 1.0f);
    float m2 = m * m;
    return f0 + (vec3(1.0f) - f0) * (m2 * m2 * m);
}

// ((n_t - n_i) / (n_t + n_i))^2 per channel.
vec3 normal_reflectance3(vec3 n_t, float n_i) {
    vec3 r = (n_t - vec3(n_i)) / (n_t + vec3(n_i));
    return r * r;
}

// The spectral integral of cos(2 pi OPD / lambda + shift) against the XYZ matching functions (each a Gaussian in
// wavenumber; x has a second lobe), normalised so that a zero path difference integrates to XYZ = 1, in linear
// Rec.709. `opd` in nm; `shift` per channel (the phase of each XYZ component's term).
vec3 integrate_film_phase(float opd, vec3 shift) {
    float phase = 2.0f * PI * opd * 1.0e-9f;
    vec3 amplitude = vec3(5.4856e-13f, 4.4201e-13f, 5.2481e-13f);
    vec3 centre = vec3(1.6810e+06f, 1.7953e+06f, 2.2084e+06f);
    vec3 variance = vec3(4.3278e+09f, 9.3046e+09f, 6.6121e+09f);
    vec3 xyz = amplitude * sqrt(2.0f * PI * variance) * cos(centre * phase + shift) *
               exp(-(phase * phase) * variance);
    xyz.x += 9.7470e-14f * sqrt(2.0f * PI * 4.5282e+09f) * cos(2.2399e+06f * phase + shift.x) *
             exp(-4.5282e+09f * (phase * phase));
    return XYZ_TO_LINEAR_REC709 * (xyz / 1.0685e-7f);
}

// A material's film: its weight (iridescenceFactor x texture; 0: no film), thickness in nm and index.
struct ThinFilm {
    float weight;
    float thickness;
    float ior;
};

ThinFilm make_no_film() {
    ThinFilm f;
    f.weight = 0.0f;
    f.thickness = 0.0f;
    f.ior = 1.0f;
    return f;
}

// The extension's reflectance (linear Rec.709, unclamped) of a film of `thickness` nm and index `film_ior` between
// air (index 1, where the light comes from at cos theta = `cos_theta` to the film's normal) and a base of
// reflectance `base_f0` at normal incidence.
vec3 sum_thin_film_fresnel(float cos_theta, float thickness, float film_ior, vec3 base_f0) {
    const float outside_ior = 1.0f;
    float c1 = clamp(cos_theta, 0.0f, 1.0f);
    float eta = mix(outside_ior, film_ior, smoothstep(0.0f, THIN_FILM_FADE_THICKNESS, thickness));
    float sin2_t = (outside_ior / eta) * (outside_ior / eta) * (1.0f - c1 * c1);
    if (sin2_t >= 1.0f) {
        return vec3(1.0f);  // total internal reflection at the film (a film of lower index than the outside)
    }
    float c2 = sqrt(1.0f - sin2_t);
    // Outside | film: reflectance R12 (= R21), transmittance T121 there and back, phases 0 or pi.
    float r0 = normal_reflectance3(vec3(eta), outside_ior).x;
    float r12 = schlick_fresnel3(vec3(r0), c1).x;
    float t121 = 1.0f - r12;
    float phi12 = eta < outside_ior ? PI : 0.0f;
    float phi21 = PI - phi12;
    // Film | base: the base's index from its F0 (as if seen from air), its reflectance R23 at the refracted angle.
    vec3 root_f0 = sqrt(clamp(base_f0, vec3(0.0f), vec3(0.9999f)));
    vec3 base_ior = (vec3(1.0f) + root_f0) / (vec3(1.0f) - root_f0);
    vec3 r23 = schlick_fresnel3(normal_reflectance3(base_ior, eta), c2);
    vec3 phi23 = vec3(base_ior.x < eta ? PI : 0.0f, base_ior.y < eta ? PI : 0.0f, base_ior.z < eta ? PI : 0.0f);
    // Airy sum: the incoherent part (m = 0) and the first two interference terms.
    float opd = 2.0f * eta * thickness * c2;
    vec3 phi = vec3(phi21) + phi23;
    vec3 r123 = clamp(r12 * r23, vec3(1.0e-5f), vec3(0.9999f));
    vec3 amplitude = sqrt(r123);
    vec3 rs = (t121 * t121) * r23 / (vec3(1.0f) - r123);
    vec3 reflectance = vec3(r12) + rs;
    vec3 cm = rs - vec3(t121);
    for (int m = 1; m <= 2; ++m) {
        cm *= amplitude;
        reflectance += cm * (2.0f * integrate_film_phase(float(m) * opd, float(m) * phi));
    }
    return reflectance;
}

// The film's reflectance as Fredholm uses it: each channel clamped to [0, 1] (see the top of the file).
vec3 eval_thin_film_fresnel(float cos_theta, float thickness, float film_ior, vec3 base_f0) {
    return clamp(sum_thin_film_fresnel(cos_theta, thickness, film_ior, base_f0), vec3(0.0f), vec3(1.0f));
}

// Fresnel term `f` of a lobe over a base of reflectance `base_f0`, under `film` seen at cos theta = `cos_theta`:
// mix(f, F_film, weight), the extension's iridescent layers.
vec3 mix_thin_film(vec3 f, ThinFilm film, float cos_theta, vec3 base_f0) {
    return mix(f, eval_thin_film_fresnel(cos_theta, film.thickness, film.ior, base_f0), film.weight);
}

#endif
