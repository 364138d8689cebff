// The energy a GGX lobe (the metal's, the dielectric's specular layer, the clear coat) loses to light that bounces between microfacets
// before leaving, given back as a diffuse-like lobe (Kulla & Conty 2017, "Revisiting Physically Based Shading at
// Imageworks"), so that a white rough metal reflects all the light it receives (`--microfacet compensated`,
// EFFECT_GGX_MULTISCATTER). Shared GLSL/C++.
//
//   f_ms cos = F_ms (1 - E(mu_o)) (1 - E(mu_i)) mu_i / (pi (1 - E_avg))
//   E(mu) = A(mu) + B(mu): the white lobe's single-scattering albedo (ggx_albedo.glsl, F = 1), E_avg = A_avg + B_avg
//   F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg)),  F_avg = f0 + (f90 - f0) / 21 (Schlick's cosine-weighted mean;
//   f90 = 1 for a metal, the specular layer's f90 for a dielectric, whose lobe is tiny at f0 0.04 and all the loss at 1)
// f_ms is symmetric in wo and wi (light tracing and BDPT evaluate it with the two swapped), integrates to
// F_ms (1 - E(mu_o)), exactly what single scattering lost for F = 1, and F_ms <= 1 per channel, so a coloured metal
// never gains (F_ms sums the series of bounces, each tinted by F_avg, that Kulla and Conty derive). The table's nodes
// are raised (E_table >= E_true), so the lobe gives back at most what was lost. An anisotropic lobe's E depends on
// the azimuth too: it reads ggx_anisotropic_albedo.glsl's table (bsdf.glsl). A thin film (KHR_materials_iridescence)
// leaves F_ms at the base colour's. Sampled uniformly over the hemisphere: the lobe's weight (1 - E(mu_i)) mu_i
// vanishes at both ends, so uniform directions keep the sample weight bounded where cosine ones would not.
#ifndef FH_GGX_MULTISCATTER_GLSL
#define FH_GGX_MULTISCATTER_GLSL
#include "lib/bsdf/ggx_albedo.glsl"

// The white lobe's single-scattering albedo A + B from the table's terms (ggx_albedo or ggx_albedo_average).
float white_ggx_albedo(vec2 albedo) {
    return min(albedo.x + albedo.y, 1.0f);
}

// The white GGX lobe's single-scattering albedo at cos theta = mu.
float ggx_white_albedo(float mu, float alpha) {
    return white_ggx_albedo(ggx_albedo(mu, alpha));
}

// F_ms of a lobe whose Fresnel is Schlick's from f0 to f90 (see the top of the file), given E_avg: a metal's (f0 its
// colour, f90 1) or a dielectric specular layer's.
vec3 ggx_multiscatter_fresnel(vec3 f0, float f90, float e_average) {
    vec3 f_average = f0 + (vec3(f90) - f0) * (1.0f / 21.0f);
    return f_average * f_average * e_average / (vec3(1.0f) - f_average * (1.0f - e_average));
}

// Smallest 1 - E_avg with a lobe: below it (alpha near its minimum) single scattering loses nothing worth a lobe.
const float GGX_MULTISCATTER_MIN_LOSS = 1.0e-6f;

// f_ms cos / F_ms for light from wi_z towards wo_z (local frame), `norm` = 1 / (pi (1 - E_avg)).
float eval_ggx_multiscatter(float wo_z, float wi_z, float alpha, float norm) {
    return (1.0f - ggx_white_albedo(wo_z, alpha)) * (1.0f - ggx_white_albedo(wi_z, alpha)) * wi_z * norm;
}
#endif
