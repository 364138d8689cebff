// The glTF 2.0 metallic-roughness BRDF (glTF 2.0 spec, Appendix B) with KHR_materials_specular and
// KHR_materials_ior, made energy conserving: evaluation, pdf and importance sampling. Shared GLSL/C++ subset.
//
// Directions live in the local shading frame (z = shading normal); wo and wi both point away from the
// surface. Reflection only: wo.z <= 0 or wi.z <= 0 gives f = 0 and pdf = 0.
//   f = mix(dielectric_brdf, metal_brdf, metallic)                                  (as the spec)
//   metal_brdf = (base_color + (1 - base_color) (1 - |v.h|)^5) * specular          (as the spec)
//   dielectric_brdf = F_d * specular + base_color / pi * (1 - E(mu_o)) (1 - E(mu_i)) / (1 - E_avg)
//       F_d = f0 + (f90 - f0) (1 - |v.h|)^5, f0 = min(((ior-1)/(ior+1))^2 specularColor, 1) specular,
//       f90 = specular (KHR_materials_specular, "Implementation")
//   specular = D(h) V(wo, wi): Trowbridge-Reitz/GGX D, height-correlated Smith V, alpha = roughness^2.
//
// DEVIATION from the spec, whose dielectric weights Lambert by 1 - max_value(F_d(v.h)): that is not energy
// conserving (a white dielectric reflects 1.03x what it receives at 60 deg, 1.35x at 80, 1.85x at 89). We
// weight Lambert by the energy the specular layer leaves instead, "albedo scaling" (Kelemen & Szirmay-Kalos
// 2001, "A Microfacet Based Coupled Specular-Matte BRDF Model with Importance Sampling"; also Autodesk
// Standard Surface, OpenPBR and Dassault Enterprise PBR): E(mu) = max_value(f0) A(mu) + f90 B(mu) is the
// specular layer's albedo, E_avg = 2 int E mu dmu (ggx_albedo.glsl). The albedo is then E_c(mu_o) +
// base_color (1 - E(mu_o)) <= 1 per channel, and f stays reciprocal. specularFactor 0 (f0 = f90 = 0, E = 0)
// gives exactly Lambert; metallic 1 gives exactly the spec's metal with --microfacet single.
//
// DEVIATION (--microfacet compensated, the default): the spec's metal is single-scattering GGX, which loses the light
// that bounces between microfacets (a white metal of roughness 1 reflects 0.4 of it at normal incidence). A lobe of
// ggx_multiscatter.glsl gives it back (Kulla & Conty 2017; Cycles' multiscatter GGX and Filament do the same), so a
// white rough metal conserves energy; reciprocal (shaders/lib/bsdf/README.md "Rough metal conserves energy"). The
// dielectric's specular layer gets the same lobe with its own F_ms (from f0 and f90: small for f0 0.04, all of the
// loss for f0 1), and the diffuse lobe's albedo scaling counts it in E(mu): E += max(F_ms) (1 - E_white(mu)). Not
// under a thin film, whose albedo bound the diffuse lobe is normalised by leaves it out. An anisotropic lobe (metal
// or specular layer) reads the white anisotropic lobe's albedo by azimuth (ggx_anisotropic_albedo.glsl), and
// the clear coat gets a lobe of its own (f0 0.04, f90 1), which its albedo E_c counts.
//
// KHR_materials_transmission replaces a fraction `transmission` of the dielectric by the glass lobe of
// dielectric.glsl (its own exact-Fresnel reflection and the refraction or thin-walled pass-through):
//   dielectric = mix(F_d specular + albedo-scaled Lambert, glass, transmission)
// a convex mix of two energy-conserving, reciprocal BSDFs (the glass lobe conserves energy with the multiple-
// scattering lobe of glass_multiscatter.glsl, EFFECT_GLASS_MULTISCATTER; BSDF_HAS_GLASS_MULTISCATTER false leaves
// single scattering, which loses energy on rough glass). Stages compiled without EFFECT_TRANSMISSION define
// BSDF_HAS_TRANSMISSION false, and none of the glass code is left in them.
//
// KHR_materials_diffuse_transmission sends a fraction `diffuse_transmission` of the diffuse lobe through the
// surface instead, as a Lambert lobe of colour diffuseTransmissionColor on the other side, under the same albedo
// scaling (with |mu_i|), so reflected + transmitted stays 1 - E(mu_o) times the colours and the BTDF is symmetric
// in wo and wi: thin-walled (shaders/lib/bsdf/README.md "Diffuse transmission"). Without EFFECT_DIFFUSE_TRANSMISSION,
// BSDF_HAS_DIFFUSE_TRANSMISSION is false.
//
// KHR_materials_clearcoat puts a white GGX coat (ior 1.5: f0 = 0.04, f90 = 1; its own roughness and normal)
// over all of the above, layered as the extension's fresnel_coat does, with the coat's albedo in place of
// its Fresnel term:
//   f = clearcoat F_c(v.h) D_c V_c + f_base (1 - clearcoat E_c(mu_o))      mu_o: cos theta_o about the coat normal
// E_c = 0.04 A + B (ggx_albedo.glsl) is the coat lobe's albedo (with --microfacet compensated plus its multiple-
// scattering lobe's, F_ms (1 - E_white(mu_o))), so the albedo is clearcoat E_c + (1 - clearcoat
// E_c) albedo_base <= 1: energy conserving, exactly 1 over a white dielectric. DEVIATION: like the spec's
// (whose weight is Fresnel at n.v) this attenuates the base on the viewer's side only, so the coated BSDF is
// not reciprocal; weighting both sides, (1 - E_c(mu_o)) (1 - E_c(mu_i)), is reciprocal but darkens a coated
// white base by the coat's average albedo (about 9% at normal incidence), and normalising that product as the
// diffuse lobe does gains energy over a specular base (shaders/lib/bsdf/README.md "Clear coat"). Stages without EFFECT_CLEARCOAT
// define BSDF_HAS_CLEARCOAT false.
//
// KHR_materials_sheen lays the Charlie sheen lobe of sheen.glsl (colour sheenColor, its own roughness, about the
// base's shading normal) over everything under the coat, with the extension's albedo scaling:
//   f_under_coat = f_sheen + f_base min(1 - max(sheenColor) E_s(mu_o), 1 - max(sheenColor) E_s(mu_i))
// E_s = min(sheen_albedo, 1) >= the lobe's albedo (the table bounds it from above), so the albedo is at most
// sheenColor E_s + (1 - max(sheenColor) E_s) albedo_base <= 1, and the whole stays reciprocal. Stages without
// EFFECT_SHEEN define BSDF_HAS_SHEEN false.
//
// KHR_materials_anisotropy stretches the GGX of the base's specular lobes (dielectric and metal reflection, and
// the glass lobe) along a direction in the tangent plane: alpha_t = mix(alpha, 1, strength^2) along it, alpha across
// (ggx.glsl, GgxRoughness). The albedo scaling then needs the anisotropic lobe's albedo, which depends on the
// azimuth and which no isotropic albedo bounds at grazing angles (light from a grazing viewer meets microfacets
// tilted sideways at steeper angles: more Fresnel). We bound it with the isotropic table's terms at the two alphas
// plus a margin m = ANISOTROPY_ALBEDO_MARGIN (1 - mu)^5 that grows as Schlick's weight does: A' = max(A(alpha),
// A(alpha_t)) + m, B' = B(alpha(phi)) + m with the projected roughness of the light's azimuth phi (ggx.glsl,
// projected_alpha), E' = f0 A' + f90 B', a function of the direction (so still reciprocal; linear in f0 <= f90, so
// checking f0 = 0 and f0 = f90 = 1 checks every material: tests/unit/bsdf/test_bsdf_anisotropy.cpp, over strengths,
// roughnesses, angles to 89.5 deg and azimuths). The diffuse lobe stays under what the specular leaves, so nothing
// gains energy; it loses what the bound overestimates (shaders/lib/bsdf/README.md "Anisotropy"). Stages without EFFECT_ANISOTROPY
// define BSDF_HAS_ANISOTROPY false, leaving only the isotropic code.
//
// KHR_materials_iridescence puts a thin film (thin_film.glsl) on the base's specular lobes: their Fresnel term
// becomes mix(F, F_film(|v.h|), iridescence), F_film from the dielectric's f0 (the extension's
// iridescent_dielectric_layer with KHR_materials_specular) or from base_color (iridescent_conductor_layer), and the
// glass lobe's reflectance likewise (dielectric.glsl). The diffuse lobe's albedo scaling needs the film's albedo,
// bounded from a Schlick-shaped envelope of its Fresnel: F_film(c) <= a (1 - w) + b w, w = (1 - c)^5, for every
// angle and every thickness the material can have, (a, b) computed on the host (engine/scene/thin_film_bound.cpp,
// checked off its grid by tests/unit/bsdf/test_bsdf_iridescence.cpp). Its albedo is then at most a A + b B, and E mixes
// the two: E = mix(max(f0) A + f90 B, a A + b B, iridescence), a function of the direction alone (reciprocal).
// With b > 1 (the film's interference persists to grazing angles, where its F leaves Schlick's curve, and b > 1
// lets a stay near the film's reflectance at normal incidence) E can pass 1 at grazing angles, where
// diffuse_transmittance clamps 1 - E at 0; the normalisation 1 / (1 - E_avg) then takes E_avg from below, with b
// replaced by 1 (a A + B <= A + B <= 1 needs no clamp): min(E, 1) >= mix(..., a A + B, ...), so the diffuse lobe
// keeps at most 1 - min(E(mu_o), 1) and nothing gains energy (shaders/lib/bsdf/README.md "Iridescence"). Stages without
// EFFECT_IRIDESCENCE define BSDF_HAS_IRIDESCENCE false.
#ifndef FH_BSDF_GLSL
#define FH_BSDF_GLSL

#ifdef __cplusplus
using fh::gpu::Material;  // C++: include shaders/shared/layout.h at global scope before this file
#else
#include "shared/layout.h"
#endif
#include "lib/sampling/sampling.glsl"
#ifndef BSDF_HAS_ANISOTROPY
#define BSDF_HAS_ANISOTROPY true
#endif
#define GGX_HAS_ANISOTROPY BSDF_HAS_ANISOTROPY
#ifndef BSDF_HAS_IRIDESCENCE
#define BSDF_HAS_IRIDESCENCE true
#endif
#define GLASS_HAS_IRIDESCENCE BSDF_HAS_IRIDESCENCE
#ifndef BSDF_HAS_GLASS_MULTISCATTER
#define BSDF_HAS_GLASS_MULTISCATTER true
#endif
#define GLASS_HAS_MULTISCATTER BSDF_HAS_GLASS_MULTISCATTER
// --microfacet compensated: the metal's multiple-scattering lobe (ggx_multiscatter.glsl, EFFECT_GGX_MULTISCATTER);
// false (--microfacet single) leaves the spec's single-scattering metal, bit for bit.
#ifndef BSDF_HAS_GGX_MULTISCATTER
#define BSDF_HAS_GGX_MULTISCATTER true
#endif
#include "lib/bsdf/ggx.glsl"
#include "lib/bsdf/ggx_albedo.glsl"
#include "lib/bsdf/ggx_multiscatter.glsl"
#include "lib/bsdf/ggx_anisotropic_albedo.glsl"
#include "lib/bsdf/dielectric.glsl"
#include "lib/bsdf/sheen.glsl"

#ifndef BSDF_HAS_TRANSMISSION
#define BSDF_HAS_TRANSMISSION true
#endif
// The base's GGX reflection lobe (dielectric specular layer and metal). Stages compiled without EFFECT_SPECULAR (every
// visible material has metallic 0 and specularFactor 0: Lambertian) define it false: the BSDF is then Lambert alone,
// with the same bits, and no table lookup or GGX code is left.
#ifndef BSDF_HAS_SPECULAR
#define BSDF_HAS_SPECULAR true
#endif
#ifndef BSDF_HAS_CLEARCOAT
#define BSDF_HAS_CLEARCOAT true
#endif
#ifndef BSDF_HAS_SHEEN
#define BSDF_HAS_SHEEN true
#endif
#ifndef BSDF_HAS_DIFFUSE_TRANSMISSION
#define BSDF_HAS_DIFFUSE_TRANSMISSION true
#endif

// KHR_materials_clearcoat: the coat's Fresnel at normal incidence, ((1.5 - 1) / (1.5 + 1))^2.
const float CLEARCOAT_F0 = 0.04f;

// Smallest GGX alpha: roughness 0 becomes a very sharp but finite lobe (D <= 1 / (pi 1e-6) = 3.2e5), never
// a delta, so every path stays a plain (non-delta) sample with a finite pdf.
const float BSDF_MIN_ALPHA = 1.0e-3f;
// Range of the specular lobe's selection probability when both lobes are present, so that neither lobe is
// starved (the lobe albedos below ignore how the two lobes are distributed over wi).
const float BSDF_MIN_LOBE_PROBABILITY = 0.05f;

struct BsdfParams {
    vec3 base_color;
    float metallic;
    float alpha;            // GGX alpha = roughness^2, at least BSDF_MIN_ALPHA
    GgxRoughness roughness; // the specular lobes' GGX: alpha, stretched along a direction by KHR_materials_anisotropy
    vec3 f0_dielectric;     // dielectric Fresnel at normal incidence (includes specularFactor)
    float f90_dielectric;   // dielectric Fresnel at grazing incidence = specularFactor
    float diffuse_scale;    // 1 / (1 - E_avg) of the dielectric's specular layer (see the top of the file)
    float transmission;     // KHR_materials_transmission: the glass lobe's share of the dielectric
    GlassParams glass;
    float clearcoat;        // KHR_materials_clearcoat: the coat's weight (0: no coat)
    float clearcoat_alpha;  // the coat's GGX alpha, at least BSDF_MIN_ALPHA
    vec3 clearcoat_normal;  // the coat's normal in the local frame (z: the base's shading normal)
    float clearcoat_multiscatter;       // F_ms of the coat's multiple-scattering lobe (f0 0.04, f90 1); 0: none
    float clearcoat_multiscatter_norm;  // its 1 / (pi (1 - E_avg)) at the coat's alpha
    vec3 sheen_color;       // KHR_materials_sheen: the sheen's colour (0: no sheen)
    float sheen_roughness;  // perceptual, at least SHEEN_MIN_ROUGHNESS
    float diffuse_transmission;       // KHR_materials_diffuse_transmission: the diffuse lobe's share sent through
    vec3 diffuse_transmission_color;  // the colour it takes on the way
    // KHR_materials_iridescence: the film is glass.film (the glass lobe's and the opaque lobes' alike), and
    vec2 film_albedo_bound; // (a, b) of its Fresnel envelope a (1 - w) + b w (see the top of the file)
    vec3 metal_multiscatter;  // F_ms of the metal's multiple-scattering lobe (ggx_multiscatter.glsl); 0: none
    vec3 dielectric_multiscatter;  // F_ms of the dielectric specular layer's (f0, f90 of the layer); 0: none
    float multiscatter_norm;  // their 1 / (pi (1 - E_avg))
};

// Floor of 1 - E_avg (approached only by f0 = f90 = 1 at small alpha): loses energy, never adds it.
const float BSDF_MIN_DIFFUSE_TRANSMITTANCE = 1.0e-4f;

bool has_ggx_multiscatter(BsdfParams p) {
    return BSDF_HAS_GGX_MULTISCATTER && p.multiscatter_norm > 0.0f;
}

bool has_iridescence(BsdfParams p) {
    return BSDF_HAS_IRIDESCENCE && p.glass.film.weight > 0.0f;
}

// The weights (of A, of B) of the dielectric's specular albedo E = max(f0) A + f90 B; under a film, mixed with the
// film's envelope (a, b). For E_avg's lower bound, the diffuse lobe's normalisation (`for_average`), the film's b
// is replaced by 1 (see the top of the file).
vec2 specular_albedo_weights(BsdfParams p, bool for_average) {
    vec2 weights = vec2(max_value(p.f0_dielectric), p.f90_dielectric);
    if (has_iridescence(p)) {
        vec2 film = for_average ? vec2(p.film_albedo_bound.x, 1.0f) : p.film_albedo_bound;
        weights = mix(weights, film, p.glass.film.weight);
    }
    return weights;
}

// Sets the diffuse lobe's normalisation 1 / (1 - E_avg) from the specular layer's hemispherical averages (A_avg,
// B_avg) = `average` (see the top of the file) and, with the layer's multiple-scattering lobe, the white lobe's
// average loss 1 - E_avg that the lobe gives back (the isotropic table's, or the anisotropic table's).
BsdfParams normalise_diffuse(BsdfParams p, vec2 average, float white_loss_average) {
    vec2 weights = specular_albedo_weights(p, true);
    float e_average = weights.x * average.x + weights.y * average.y;
    if (has_ggx_multiscatter(p)) e_average += max_value(p.dielectric_multiscatter) * white_loss_average;
    p.diffuse_scale = 1.0f / max(1.0f - e_average, BSDF_MIN_DIFFUSE_TRANSMITTANCE);
    return p;
}

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
    p.transmission = 0.0f;
    p.glass.transmission_tint = p.base_color;
    p.roughness = make_isotropic_roughness(p.alpha);
    p.glass.roughness = p.roughness;
    p.glass.specular_color = max(vec3(m.specular_color), vec3(0.0f));
    p.glass.specular = specular;
    p.glass.eta = max(m.ior, 1.0e-4f);
    p.glass.thin_walled = 1u;
    p.clearcoat = 0.0f;
    p.clearcoat_alpha = BSDF_MIN_ALPHA;
    p.clearcoat_normal = vec3(0.0f, 0.0f, 1.0f);
    p.clearcoat_multiscatter = 0.0f;
    p.clearcoat_multiscatter_norm = 0.0f;
    p.sheen_color = vec3(0.0f);
    p.sheen_roughness = SHEEN_MIN_ROUGHNESS;
    p.diffuse_transmission = 0.0f;
    p.diffuse_transmission_color = vec3(1.0f);
    p.film_albedo_bound = vec2(0.0f);
    p.glass.film = make_no_film();
    p.metal_multiscatter = vec3(0.0f);
    p.dielectric_multiscatter = vec3(0.0f);
    p.multiscatter_norm = 0.0f;
    if (!BSDF_HAS_SPECULAR) {
        // Lambert alone (--disable-effect specular on a scene with a specular lobe leaves it out: metal is black).
        p.f0_dielectric = vec3(0.0f);
        p.f90_dielectric = 0.0f;
        p.diffuse_scale = 1.0f;
        return p;
    }
    vec2 average = ggx_albedo_average(p.alpha);
    if (BSDF_HAS_GGX_MULTISCATTER && p.alpha > BSDF_MIN_ALPHA) {
        // The multiple-scattering lobes; roughness 0 (alpha at its minimum) loses nothing and gets none.
        float e_average = white_ggx_albedo(average);
        bool dielectric_layer = p.metallic < 1.0f && p.f90_dielectric > 0.0f;
        if (1.0f - e_average > GGX_MULTISCATTER_MIN_LOSS && (p.metallic > 0.0f || dielectric_layer)) {
            if (p.metallic > 0.0f) p.metal_multiscatter = ggx_multiscatter_fresnel(p.base_color, 1.0f, e_average);
            if (dielectric_layer)
                p.dielectric_multiscatter = ggx_multiscatter_fresnel(p.f0_dielectric, p.f90_dielectric, e_average);
            p.multiscatter_norm = INV_PI / (1.0f - e_average);
        }
    }
    return normalise_diffuse(p, average, 1.0f - white_ggx_albedo(average));
}

// Schlick 1994's weight (1 - cos)^5.
float schlick_weight(float cos_theta) {
    float m = clamp(1.0f - cos_theta, 0.0f, 1.0f);
    float m2 = m * m;
    return m2 * m2 * m;
}

// The margin of the anisotropic albedo bound (see the top of the file): at least the largest (B - B(alpha(phi))) /
// (1 - mu)^5 and (A + B - max(A(alpha), A(alpha_t)) - B(alpha(phi))) / (2 (1 - mu)^5) that
// tests/unit/bsdf/test_bsdf_anisotropy.cpp measures, with room to spare.
const float ANISOTROPY_ALBEDO_MARGIN = 0.1f;

bool has_anisotropy(BsdfParams p) {
    return is_anisotropic(p.roughness);
}

// Whether the multiple-scattering lobe (the metal's and the specular layer's) follows the anisotropic table
// (ggx_anisotropic_albedo.glsl): an anisotropic lobe.
bool has_anisotropic_multiscatter(BsdfParams p) {
    return BSDF_HAS_GGX_MULTISCATTER && has_anisotropy(p);
}

// The white anisotropic lobe's loss 1 - E(w) (w in the local frame, above the surface), given the lobe's slice of
// the table, ggx_anisotropic_cell(p.alpha, p.roughness.alpha_t).
float anisotropic_multiscatter_loss(BsdfParams p, GgxAnisotropicCell cell, vec3 w) {
    return 1.0f - ggx_anisotropic_white_albedo(cell, to_lobe_frame(p.roughness, w));
}

// The specular layer's albedo terms (A, B) = ggx_albedo for light from direction w (local frame; its z's sign is
// ignored); anisotropic, their bound (see the top of the file). Isotropic: ggx_albedo's bits.
vec2 specular_albedo(BsdfParams p, vec3 w) {
    if (!BSDF_HAS_SPECULAR) {
        return vec2(0.0f);
    }
    float mu = abs(w.z);
    vec2 albedo = ggx_albedo(mu, p.alpha);
    if (has_anisotropy(p)) {
        albedo.x = max(albedo.x, ggx_albedo(mu, p.roughness.alpha_t).x);
        albedo.y = ggx_albedo(mu, projected_alpha(p.roughness, w)).y;
        albedo += vec2(ANISOTROPY_ALBEDO_MARGIN * schlick_weight(mu));
    }
    return albedo;
}

// `p` with its specular lobes stretched by KHR_materials_anisotropy of strength `strength` along `direction` (local
// xy-plane; need not be unit length). Strength 0 (or no direction) leaves `p` as it is. The diffuse lobe's
// normalisation 1 / (1 - E_avg) needs the bound's hemispherical average, f0 A'_avg + f90 B'_avg, from below (so that
// the diffuse lobe can lose a little energy, never gain it): A'_avg >= max(A_avg(alpha), A_avg(alpha_t)) (the
// average of a maximum is at least the maximum of the averages); B'_avg = the azimuths' mean of B_avg(alpha(phi));
// both plus the margin's 2 int mu (1 - mu)^5 dmu = 1 / 21. The mean is taken as a lower sum over ANISOTROPY_AZIMUTH_STEPS steps
// of [0, pi/2] (B_avg falls as alpha grows, and alpha(phi) falls as phi grows: each step's left end is its least).
const int ANISOTROPY_AZIMUTH_STEPS = 4;

BsdfParams with_anisotropy(BsdfParams p, float strength, vec2 direction) {
    float s = clamp(strength, 0.0f, 1.0f);
    float len = length(direction);
    if (!(s > 0.0f && len > 0.0f) || isinf(len)) {
        return p;
    }
    p.roughness.alpha_t = mix(p.alpha, 1.0f, s * s);
    p.roughness.direction = direction / len;
    p.glass.roughness = p.roughness;
    if (has_anisotropy(p)) {
        vec2 average = vec2(max(ggx_albedo_average(p.alpha).x, ggx_albedo_average(p.roughness.alpha_t).x), 0.0f);
        for (int k = 0; k < ANISOTROPY_AZIMUTH_STEPS; ++k) {
            float cos_phi = cos(0.5f * PI * float(k) / float(ANISOTROPY_AZIMUTH_STEPS));  // phi from the direction
            average.y += ggx_albedo_average(projected_alpha_at(p.roughness, cos_phi * cos_phi)).y;
        }
        average.y /= float(ANISOTROPY_AZIMUTH_STEPS);
        average += vec2(ANISOTROPY_ALBEDO_MARGIN / 21.0f);
        float white_loss_average = 0.0f;
        if (has_anisotropic_multiscatter(p)) {
            // The lobes give back what the anisotropic table says single scattering loses (also at roughness 0,
            // where the stretched lobe is rough along the direction); its E_avg integrates that table. The specular
            // layer's lobe takes its energy from the diffuse lobe, as the isotropic one does (diffuse_transmittance):
            // the bound above still covers single scattering, so nothing gains. Under a thin film the film's envelope
            // bounds the layer without it (with_iridescence).
            float e_average = ggx_anisotropic_white_albedo_average(ggx_anisotropic_cell(p.alpha, p.roughness.alpha_t));
            bool loses = 1.0f - e_average > GGX_MULTISCATTER_MIN_LOSS;
            bool layer = p.metallic < 1.0f && p.f90_dielectric > 0.0f && !has_iridescence(p);
            p.metal_multiscatter = loses && p.metallic > 0.0f ? ggx_multiscatter_fresnel(p.base_color, 1.0f, e_average)
                                                              : vec3(0.0f);
            p.dielectric_multiscatter = loses && layer ? ggx_multiscatter_fresnel(p.f0_dielectric, p.f90_dielectric,
                                                                                  e_average)
                                                       : vec3(0.0f);
            p.multiscatter_norm = loses ? INV_PI / (1.0f - e_average) : 0.0f;
            white_loss_average = 1.0f - e_average;
        }
        p = normalise_diffuse(p, average, white_loss_average);
    }
    return p;
}

// `p` under a thin film (KHR_materials_iridescence) of weight `iridescence`, `thickness` nm and index `ior`, whose
// Fresnel envelope is a (1 - w) + b w with (a, b) = `albedo_bound` (MaterialLayers.iridescence_albedo_f0, _f90). A
// film of weight 0 or thickness 0 is no film: `p` as it is (the extension's film would fade into Schlick's curve of
// the air | film interface, not into the base's Fresnel). Call before with_anisotropy, which renormalises the diffuse
// lobe with the anisotropic averages.
BsdfParams with_iridescence(BsdfParams p, float iridescence, float thickness, float ior, vec2 albedo_bound) {
    float weight = clamp(iridescence, 0.0f, 1.0f);
    if (!(weight > 0.0f && thickness > 0.0f)) {
        return p;
    }
    p.glass.film.weight = weight;
    p.glass.film.thickness = thickness;
    p.glass.film.ior = ior;
    p.film_albedo_bound = max(albedo_bound, vec2(0.0f));
    if (has_iridescence(p)) {
        p.dielectric_multiscatter = vec3(0.0f);  // the film's envelope bounds the layer without it
        vec2 average = ggx_albedo_average(p.alpha);
        p = normalise_diffuse(p, average, 1.0f - white_ggx_albedo(average));
    }
    return p;
}

// `p` with a fraction `transmission` of its dielectric made glass: thin-walled (eta = the ior) or the surface
// of a volume (eta = n beyond the surface / n on the viewer's side).
BsdfParams with_transmission(BsdfParams p, float transmission, float eta, uint thin_walled) {
    p.transmission = clamp(transmission, 0.0f, 1.0f);
    p.glass.thin_walled = thin_walled;
    p.glass.eta = thin_walled != 0u ? max(eta, 1.0e-4f) : refraction_eta(eta);
    return p;
}

bool has_glass(BsdfParams p) {
    return BSDF_HAS_TRANSMISSION && p.transmission > 0.0f && p.metallic < 1.0f;
}

// `p` with a fraction `factor` of its diffuse lobe transmitted, tinted by `color`.
BsdfParams with_diffuse_transmission(BsdfParams p, float factor, vec3 color) {
    p.diffuse_transmission = clamp(factor, 0.0f, 1.0f);
    p.diffuse_transmission_color = clamp(color, vec3(0.0f), vec3(1.0f));
    return p;
}

bool has_diffuse_transmission(BsdfParams p) {
    return BSDF_HAS_DIFFUSE_TRANSMISSION && p.diffuse_transmission > 0.0f && p.metallic < 1.0f;
}

// Whether any lobe sends light through the surface (glass or diffuse transmission).
bool has_transmission_lobe(BsdfParams p) {
    return has_glass(p) || has_diffuse_transmission(p);
}

// `p` under a clear coat of weight `clearcoat`, perceptual roughness `roughness` and unit normal `normal`
// (local frame, on the viewer's side).
BsdfParams with_clearcoat(BsdfParams p, float clearcoat, float roughness, vec3 normal) {
    p.clearcoat = clamp(clearcoat, 0.0f, 1.0f);
    float r = clamp(roughness, 0.0f, 1.0f);
    p.clearcoat_alpha = max(r * r, BSDF_MIN_ALPHA);
    p.clearcoat_normal = normal;
    p.clearcoat_multiscatter = 0.0f;
    p.clearcoat_multiscatter_norm = 0.0f;
    if (BSDF_HAS_GGX_MULTISCATTER && p.clearcoat_alpha > BSDF_MIN_ALPHA) {
        // The coat loses light between its microfacets as the base's lobes do (ggx_multiscatter.glsl): given back
        // by a lobe of its own, F_ms from the coat's Schlick Fresnel (small: 0.003 at roughness 1).
        float e_average = white_ggx_albedo(ggx_albedo_average(p.clearcoat_alpha));
        if (1.0f - e_average > GGX_MULTISCATTER_MIN_LOSS) {
            p.clearcoat_multiscatter = ggx_multiscatter_fresnel(vec3(CLEARCOAT_F0), 1.0f, e_average).x;
            p.clearcoat_multiscatter_norm = INV_PI / (1.0f - e_average);
        }
    }
    return p;
}

bool has_clearcoat(BsdfParams p) {
    return BSDF_HAS_CLEARCOAT && p.clearcoat > 0.0f;
}

// `p` under a sheen of colour `color` and perceptual roughness `roughness`.
BsdfParams with_sheen(BsdfParams p, vec3 color, float roughness) {
    p.sheen_color = clamp(color, vec3(0.0f), vec3(1.0f));
    p.sheen_roughness = clamp(roughness, SHEEN_MIN_ROUGHNESS, 1.0f);
    return p;
}

bool has_sheen(BsdfParams p) {
    return BSDF_HAS_SHEEN && max_value(p.sheen_color) > 0.0f;
}

// What the sheen leaves to the layers below for light from cos theta = mu: 1 - max(sheenColor) E_s(mu).
float sheen_transmittance(BsdfParams p, float mu) {
    return 1.0f - max_value(p.sheen_color) * min(sheen_albedo(abs(mu), p.sheen_roughness), 1.0f);
}

// The sheen lobe's share of the albedo for outgoing cos theta `cos_o` (a luminance, for picking lobes).
float estimate_sheen_albedo(BsdfParams p, float cos_o) {
    return luminance(p.sheen_color) * min(sheen_albedo(cos_o, p.sheen_roughness), 1.0f);
}

// Fraction of the light from cos theta = mu that the dielectric's specular layer lets through to the
// diffuse base: 1 - E(mu), E = max_value(f0) A + f90 B (specular_albedo_weights), given ggx_albedo(mu, alpha) = (A, B),
// plus what the layer's multiple-scattering lobe gives back, from the white lobe's loss there (white_lobe_losses).
float diffuse_transmittance(BsdfParams p, vec2 albedo, float white_loss) {
    vec2 weights = specular_albedo_weights(p, false);
    float e = weights.x * albedo.x + weights.y * albedo.y;
    if (has_ggx_multiscatter(p)) e += max_value(p.dielectric_multiscatter) * white_loss;
    return max(1.0f - e, 0.0f);
}

// What single scattering of the white GGX lobe loses, 1 - E, for light from wo and from wi (local frame, either
// side), given the layer's albedo terms there: the anisotropic table's where the multiple-scattering lobe follows it,
// else the isotropic table's. The multiple-scattering lobe's weights, and the diffuse lobe's share beside it.
vec2 white_lobe_losses(BsdfParams p, vec3 wo, vec3 wi, vec2 albedo_o, vec2 albedo_i) {
    if (has_anisotropic_multiscatter(p) && has_ggx_multiscatter(p)) {
        GgxAnisotropicCell cell = ggx_anisotropic_cell(p.alpha, p.roughness.alpha_t);
        return vec2(anisotropic_multiscatter_loss(p, cell, vec3(wo.x, wo.y, abs(wo.z))),
                    anisotropic_multiscatter_loss(p, cell, vec3(wi.x, wi.y, abs(wi.z))));
    }
    return vec2(1.0f - white_ggx_albedo(albedo_o), 1.0f - white_ggx_albedo(albedo_i));
}

// The diffuse lobe's transmittances at wo and wi times its normalisation (see the top of the file), given the white
// lobe's losses there.
float diffuse_transmittances(BsdfParams p, vec2 albedo_o, vec2 albedo_i, vec2 white_loss) {
    return diffuse_transmittance(p, albedo_o, white_loss.x) * diffuse_transmittance(p, albedo_i, white_loss.y) *
           p.diffuse_scale;
}

// The opaque lobes' shares of the albedo for outgoing cos theta `cos_o` (luminances): the specular layers'
// mix(opaque (f0 A + f90 B), base_color A + B, metallic) and the diffuse lobe's (1 - metallic) opaque base_color
// (1 - E(cos_o)); `opaque` = 1 - transmission, the part of the dielectric that is not glass.
struct LobeAlbedos {
    float specular;
    float diffuse;
    float through;  // the diffusely transmitted share (KHR_materials_diffuse_transmission)
    float multiscatter;  // the metal's multiple-scattering lobe (exact: F_ms (1 - E(cos_o)))
};

LobeAlbedos estimate_lobe_albedos(BsdfParams p, float cos_o, float opaque) {
    // An estimate, to pick lobes by: isotropic will do.
    vec2 albedo = BSDF_HAS_SPECULAR ? ggx_albedo(cos_o, p.alpha) : vec2(0.0f);
    LobeAlbedos a;
    float white_loss = 1.0f - white_ggx_albedo(albedo);
    a.diffuse = (1.0f - p.metallic) * opaque * diffuse_transmittance(p, albedo, white_loss) * luminance(p.base_color);
    a.through = 0.0f;
    if (has_diffuse_transmission(p)) {
        float below = (1.0f - p.metallic) * opaque * diffuse_transmittance(p, albedo, white_loss);
        a.through = below * p.diffuse_transmission * luminance(p.diffuse_transmission_color);
        a.diffuse *= 1.0f - p.diffuse_transmission;
    }
    vec3 e_dielectric = p.f0_dielectric * albedo.x + vec3(p.f90_dielectric * albedo.y);
    vec3 e_metal = p.base_color * albedo.x + vec3(albedo.y);
    a.specular = BSDF_HAS_SPECULAR ? luminance(mix(e_dielectric * opaque, e_metal, p.metallic)) : 0.0f;
    a.multiscatter = 0.0f;
    if (has_ggx_multiscatter(p)) {
        // Anisotropic: for picking, the isotropic loss at the two alphas' root mean square will do (picking needs
        // no exact albedo, and this reads a quarter of the anisotropic table's loads).
        float loss = white_loss;
        if (has_anisotropic_multiscatter(p)) {
            float rms = sqrt(0.5f * (p.alpha * p.alpha + p.roughness.alpha_t * p.roughness.alpha_t));
            loss = 1.0f - ggx_white_albedo(cos_o, rms);
        }
        a.multiscatter = luminance(mix(p.dielectric_multiscatter * opaque, p.metal_multiscatter, p.metallic)) * loss;
    }
    return a;
}

// Probability of sampling the specular lobe without glass: its share of the albedo (estimate_lobe_albedos),
// clamped to [BSDF_MIN_LOBE_PROBABILITY, 1 - BSDF_MIN_LOBE_PROBABILITY] when both lobes exist, and exactly 0 (1)
// when the specular (diffuse) lobe is absent. Depends on wo only, so pdf_bsdf can recompute it.
float specular_probability(BsdfParams p, float cos_o) {
    bool has_specular = BSDF_HAS_SPECULAR &&
                        (p.metallic > 0.0f || p.f90_dielectric > 0.0f || max_value(p.f0_dielectric) > 0.0f);
    if (!has_specular) {
        return 0.0f;
    }
    LobeAlbedos a = estimate_lobe_albedos(p, cos_o, 1.0f);
    if (!(a.diffuse > 0.0f)) {
        return 1.0f;
    }
    float q = a.specular / (a.specular + a.diffuse);
    return clamp(q, BSDF_MIN_LOBE_PROBABILITY, 1.0f - BSDF_MIN_LOBE_PROBABILITY);
}

// f(wo, wi) * cos(theta_i) of everything under the coat (the whole BSDF without KHR_materials_clearcoat).
vec3 eval_base_bsdf(BsdfParams p, vec3 wo, vec3 wi) {
    if (!(wo.z > 0.0f && wi.z > 0.0f)) {
        vec3 through = vec3(0.0f);
        if (wo.z > 0.0f && wi.z < 0.0f) {
            if (has_diffuse_transmission(p)) {
                vec2 albedo_o = specular_albedo(p, wo), albedo_i = specular_albedo(p, wi);
                float transmittance = diffuse_transmittances(p, albedo_o, albedo_i,
                                                             white_lobe_losses(p, wo, wi, albedo_o, albedo_i));
                through = p.diffuse_transmission_color *
                          (INV_PI * -wi.z * transmittance * p.diffuse_transmission * (1.0f - p.metallic) *
                           (has_glass(p) ? 1.0f - p.transmission : 1.0f));
            }
            if (has_glass(p)) {
                through += eval_glass(p.glass, wo, wi) * ((1.0f - p.metallic) * p.transmission);
            }
        }
        return through;
    }
    vec3 h = normalize(wo + wi);  // |wo + wi| >= wo.z + wi.z > 0
    float w = schlick_weight(abs(dot(wo, h)));
    float specular = BSDF_HAS_SPECULAR ? ggx_d_lobe(p.roughness, h) * ggx_v_cos_lobe(p.roughness, wo, wi) : 0.0f;
    vec2 albedo_o = specular_albedo(p, wo), albedo_i = specular_albedo(p, wi);
    vec2 white_loss = white_lobe_losses(p, wo, wi, albedo_o, albedo_i);
    float transmittance = diffuse_transmittances(p, albedo_o, albedo_i, white_loss);
    vec3 diffuse = p.base_color * (INV_PI * wi.z * transmittance);
    if (has_diffuse_transmission(p)) {
        diffuse *= 1.0f - p.diffuse_transmission;
    }
    vec3 f_dielectric = p.f0_dielectric + (vec3(p.f90_dielectric) - p.f0_dielectric) * w;
    vec3 f_metal = p.base_color + (vec3(1.0f) - p.base_color) * w;
    if (has_iridescence(p)) {
        float cos_h = abs(dot(wo, h));
        if (p.metallic < 1.0f) {
            f_dielectric = mix_thin_film(f_dielectric, p.glass.film, cos_h, p.f0_dielectric);
        }
        if (p.metallic > 0.0f) {
            f_metal = mix_thin_film(f_metal, p.glass.film, cos_h, p.base_color);
        }
    }
    vec3 dielectric = diffuse + f_dielectric * specular;
    float multiscatter = 0.0f;
    if (has_anisotropic_multiscatter(p) && has_ggx_multiscatter(p)) {
        multiscatter = white_loss.x * white_loss.y * wi.z * p.multiscatter_norm;
    } else if (has_ggx_multiscatter(p)) {
        multiscatter = eval_ggx_multiscatter(wo.z, wi.z, p.alpha, p.multiscatter_norm);
    }
    dielectric += p.dielectric_multiscatter * multiscatter;
    if (has_glass(p)) {
        dielectric = mix(dielectric, eval_glass(p.glass, wo, wi), p.transmission);
    }
    vec3 metal = f_metal * specular + p.metal_multiscatter * multiscatter;
    return mix(dielectric, metal, p.metallic);
}

// Which lobe sample_bsdf draws from: specular reflection with probability `specular`, the glass lobe with
// `glass`, Lambert with the rest.
struct LobeChoice {
    float specular;
    float glass;
    float through;       // Lambert through the surface (KHR_materials_diffuse_transmission)
    float multiscatter;  // uniform over the hemisphere: the metal's multiple-scattering lobe
};

// The glass lobe's share of the albedo, estimated as F(cos_o) + (1 - F) luminance(base_color).
float estimate_glass_albedo(BsdfParams p, float cos_o) {
    float f = fresnel_dielectric(cos_o, p.glass.eta);
    return (1.0f - p.metallic) * p.transmission * (f + (1.0f - f) * luminance(p.base_color));
}

// Without glass, sheen or diffuse transmission: specular_probability. With them: each lobe's share of the albedo
// (the glass lobe's estimated as F(cos_o) + (1 - F) luminance(base_color); the sheen's counted with the
// cosine-sampled diffuse lobe; diffuse transmission as its own cosine lobe below), every lobe present at least
// BSDF_MIN_LOBE_PROBABILITY before renormalising. Depends on wo only.
LobeChoice choose_lobes(BsdfParams p, float cos_o) {
    LobeChoice c;
    c.glass = 0.0f;
    c.through = 0.0f;
    c.multiscatter = 0.0f;
    bool glassy = has_glass(p);
    if (!glassy && !has_sheen(p) && !has_diffuse_transmission(p) && !has_ggx_multiscatter(p)) {
        c.specular = specular_probability(p, cos_o);
        return c;
    }
    LobeAlbedos a = estimate_lobe_albedos(p, cos_o, glassy ? 1.0f - p.transmission : 1.0f);
    float glass = glassy ? estimate_glass_albedo(p, cos_o) : 0.0f;
    if (has_sheen(p)) {
        // The sheen is sampled as the diffuse lobe is (cosine-weighted): its share joins the diffuse one.
        float below = sheen_transmittance(p, cos_o);
        a.specular *= below;
        a.multiscatter *= below;
        glass *= below;
        a.diffuse = a.diffuse * below + estimate_sheen_albedo(p, cos_o);
        a.through *= below;
    }
    float total = a.specular + a.diffuse + glass + a.through + a.multiscatter;
    if (!(total > 0.0f)) {
        c.specular = 0.0f;
        c.glass = glassy ? 1.0f : 0.0f;
        c.through = glassy ? 0.0f : 1.0f;
        return c;
    }
    float q_specular = a.specular > 0.0f ? max(a.specular / total, BSDF_MIN_LOBE_PROBABILITY) : 0.0f;
    float q_diffuse = a.diffuse > 0.0f ? max(a.diffuse / total, BSDF_MIN_LOBE_PROBABILITY) : 0.0f;
    float q_glass = glass > 0.0f ? max(glass / total, BSDF_MIN_LOBE_PROBABILITY) : 0.0f;
    float q_through = a.through > 0.0f ? max(a.through / total, BSDF_MIN_LOBE_PROBABILITY) : 0.0f;
    float q_multiscatter = a.multiscatter / total;  // its albedo is exact: no floor
    float norm = q_specular + q_diffuse + q_glass + q_through + q_multiscatter;
    c.specular = q_specular / norm;
    c.glass = q_glass / norm;
    c.through = q_through / norm;
    c.multiscatter = q_multiscatter / norm;
    return c;
}

float pdf_bsdf_lobes(BsdfParams p, LobeChoice c, vec3 wo, vec3 wi) {
    if (!(wo.z > 0.0f && wi.z > 0.0f)) {
        float pdf = 0.0f;
        if (wo.z > 0.0f && wi.z < 0.0f) {
            if (c.glass > 0.0f) {
                pdf = c.glass * pdf_glass(p.glass, wo, wi);
            }
            if (c.through > 0.0f) {
                pdf += c.through * pdf_cosine_hemisphere(-wi.z);
            }
        }
        return pdf;
    }
    float pdf_specular = BSDF_HAS_SPECULAR && c.specular > 0.0f
                             ? pdf_ggx_vndf_reflection_lobe(p.roughness, wo, normalize(wo + wi))
                             : 0.0f;
    float pdf = c.specular * pdf_specular + (1.0f - c.specular - c.glass - c.through) * pdf_cosine_hemisphere(wi.z);
    if (BSDF_HAS_GGX_MULTISCATTER && c.multiscatter > 0.0f) {
        pdf += c.multiscatter * (INV_TWO_PI - pdf_cosine_hemisphere(wi.z));  // its share taken from the cosine lobe
    }
    if (c.glass > 0.0f) {
        pdf += c.glass * pdf_glass(p.glass, wo, wi);
    }
    return pdf;
}

bool has_clearcoat_multiscatter(BsdfParams p) {
    return BSDF_HAS_GGX_MULTISCATTER && p.clearcoat_multiscatter_norm > 0.0f;
}

// The albedo of the coat's multiple-scattering lobe, F_ms (1 - E(cos_c)) (exact), given ggx_albedo's terms at cos_c.
float clearcoat_multiscatter_albedo(BsdfParams p, vec2 albedo) {
    return has_clearcoat_multiscatter(p) ? p.clearcoat_multiscatter * (1.0f - white_ggx_albedo(albedo)) : 0.0f;
}

// The coat's albedo clearcoat E_c: its GGX lobe's and its multiple-scattering lobe's, given ggx_albedo's terms at
// the outgoing cos theta about the coat normal.
float clearcoat_albedo_of(BsdfParams p, vec2 albedo) {
    return p.clearcoat * min(CLEARCOAT_F0 * albedo.x + albedo.y + clearcoat_multiscatter_albedo(p, albedo), 1.0f);
}

// The coat's albedo clearcoat E_c(cos_c) for the outgoing cos theta about the coat normal (0 below it).
float clearcoat_albedo(BsdfParams p, float cos_c) {
    return cos_c > 0.0f ? clearcoat_albedo_of(p, ggx_albedo(cos_c, p.clearcoat_alpha)) : 0.0f;
}

// The coat lobe clearcoat F_c(v.h) D V cos(theta_i), directions in the coat's frame (z: its normal).
float eval_clearcoat(BsdfParams p, vec3 wo_c, vec3 wi_c) {
    if (!(wo_c.z > 0.0f && wi_c.z > 0.0f)) {
        return 0.0f;
    }
    vec3 h = normalize(wo_c + wi_c);
    float f = CLEARCOAT_F0 + (1.0f - CLEARCOAT_F0) * schlick_weight(abs(dot(wo_c, h)));
    float single = p.clearcoat * f * ggx_d(h, p.clearcoat_alpha) * ggx_v_cos(wo_c.z, wi_c.z, p.clearcoat_alpha);
    if (!has_clearcoat_multiscatter(p)) {
        return single;
    }
    float multiple = p.clearcoat_multiscatter *
                     eval_ggx_multiscatter(wo_c.z, wi_c.z, p.clearcoat_alpha, p.clearcoat_multiscatter_norm);
    return single + p.clearcoat * multiple;
}

// f(wo, wi) * cos(theta_i): the BSDF already multiplied by the cosine of the incident direction.
vec3 eval_bsdf(BsdfParams p, vec3 wo, vec3 wi) {
    vec3 f = eval_base_bsdf(p, wo, wi);
    if (has_sheen(p)) {
        f *= min(sheen_transmittance(p, wo.z), sheen_transmittance(p, wi.z));
        f += p.sheen_color * eval_sheen_lobe(wo, wi, p.sheen_roughness);
    }
    if (has_clearcoat(p)) {
        Frame coat = make_frame(p.clearcoat_normal);
        vec3 wo_c = to_local(coat, wo);
        float reflected = wo.z > 0.0f && wi.z > 0.0f ? eval_clearcoat(p, wo_c, to_local(coat, wi)) : 0.0f;
        f = f * (1.0f - clearcoat_albedo(p, wo_c.z)) + vec3(reflected);
    }
    return f;
}

// How sample_bsdf picks the coat: with `probability`, its share of the albedo (the base's estimated as in
// choose_lobes), clamped to [BSDF_MIN_LOBE_PROBABILITY, 1 - BSDF_MIN_LOBE_PROBABILITY]; 0 without a coat or
// with the viewer below it. Depends on wo only.
struct CoatChoice {
    float probability;
    float multiscatter;  // the share of the coat's directions from its multiple-scattering lobe (uniform)
    Frame frame;  // the coat's (z: its normal)
    vec3 wo;      // wo in that frame
};

CoatChoice choose_coat(BsdfParams p, vec3 wo, LobeChoice c) {
    CoatChoice coat;
    coat.probability = 0.0f;
    coat.multiscatter = 0.0f;
    coat.frame = make_frame(p.clearcoat_normal);
    coat.wo = to_local(coat.frame, wo);
    if (!(coat.wo.z > 0.0f)) {
        return coat;
    }
    vec2 albedo = ggx_albedo(coat.wo.z, p.clearcoat_alpha);  // read once for both of the coat's lobes
    float e = clearcoat_albedo_of(p, albedo);
    if (!(e > 0.0f)) {
        return coat;
    }
    if (has_clearcoat_multiscatter(p)) {
        coat.multiscatter = min(p.clearcoat * clearcoat_multiscatter_albedo(p, albedo) / e, 1.0f);
    }
    LobeAlbedos a = estimate_lobe_albedos(p, wo.z, 1.0f - (c.glass > 0.0f ? p.transmission : 0.0f));
    float base = a.specular + a.diffuse + a.through + a.multiscatter +
                 (c.glass > 0.0f ? estimate_glass_albedo(p, wo.z) : 0.0f);
    if (has_sheen(p)) {
        base = base * sheen_transmittance(p, wo.z) + estimate_sheen_albedo(p, wo.z);
    }
    float q = e / max(e + (1.0f - e) * base, 1.0e-30f);
    coat.probability = clamp(q, BSDF_MIN_LOBE_PROBABILITY, 1.0f - BSDF_MIN_LOBE_PROBABILITY);
    return coat;
}

// The pdf of sampling wi: the base's lobes mixed with the coat's visible normals (only above both the coat
// and the base's shading normal, where the coat sampler keeps its directions).
float pdf_bsdf_choice(BsdfParams p, LobeChoice c, CoatChoice coat, vec3 wo, vec3 wi) {
    float pdf = pdf_bsdf_lobes(p, c, wo, wi);
    if (coat.probability > 0.0f) {
        vec3 wi_c = to_local(coat.frame, wi);
        float pdf_coat = wi_c.z > 0.0f && wi.z > 0.0f
                             ? pdf_ggx_vndf_reflection(coat.wo, normalize(coat.wo + wi_c), p.clearcoat_alpha)
                             : 0.0f;
        if (coat.multiscatter > 0.0f && wi_c.z > 0.0f && wi.z > 0.0f) {
            pdf_coat = mix(pdf_coat, INV_TWO_PI, coat.multiscatter);  // its uniform share
        }
        pdf = mix(pdf, pdf_coat, coat.probability);
    }
    return pdf;
}

// Solid-angle pdf of sample_bsdf (one-sample MIS over the lobes: Veach 1997 sec. 9.2.4, "balance" mix).
float pdf_bsdf(BsdfParams p, vec3 wo, vec3 wi) {
    LobeChoice c = choose_lobes(p, wo.z);
    if (!has_clearcoat(p)) {
        return pdf_bsdf_lobes(p, c, wo, wi);
    }
    return pdf_bsdf_choice(p, c, choose_coat(p, wo, c), wo, wi);
}

// A direction from the base's lobes as `c` picks them with u.x (specular reflection, glass, Lambert through the
// surface, the metal's multiple scattering, Lambert), in xyz;
// w = 0 when there is none (a specular sample below the surface: not a reflection, nor, with glass, a
// transmission of this lobe).
vec4 sample_base_direction(BsdfParams p, LobeChoice c, vec3 wo, vec3 u) {
    vec3 wi;
    if (BSDF_HAS_SPECULAR && u.x < c.specular) {
        vec3 h = sample_ggx_vndf_lobe(p.roughness, wo, vec2(u.y, u.z));
        wi = 2.0f * dot(wo, h) * h - wo;  // reflect wo about h; h = 0 (degenerate) gives -wo, rejected below
        if (!(wi.z > 0.0f)) {
            return vec4(0.0f);
        }
    } else if (u.x < c.specular + c.glass) {
        float u_glass = min((u.x - c.specular) / c.glass, 0.99999994f);  // reused: reflect or refract
        wi = sample_glass(p.glass, wo, vec3(u_glass, u.y, u.z));
    } else if (u.x < c.specular + c.glass + c.through) {
        wi = sample_cosine_hemisphere(vec2(u.y, u.z));
        wi.z = -wi.z;
    } else if (BSDF_HAS_GGX_MULTISCATTER && u.x < c.specular + c.glass + c.through + c.multiscatter) {
        wi = sample_uniform_hemisphere(vec2(u.y, u.z));
    } else {
        wi = sample_cosine_hemisphere(vec2(u.y, u.z));
    }
    return vec4(wi, 1.0f);
}

struct BsdfSample {
    vec3 wi;
    float pdf;      // solid-angle pdf of wi, = pdf_bsdf(wo, wi)
    vec3 weight;    // eval_bsdf(wo, wi) / pdf: f cos / pdf of the whole BRDF (not per lobe), unbiased
    uint valid;     // 0: no direction (wo below the surface, or no lobe sends light that way)
};

// u.x picks the lobe (the coat with probability choose_coat's, then the base's as choose_lobes says), u.yz pick
// the direction: visible normals of GGX (Dupuy & Benyoub 2023) reflected about, the glass lobe, or the cosine-
// weighted hemisphere.
BsdfSample sample_bsdf(BsdfParams p, vec3 wo, vec3 u) {
    BsdfSample s;
    s.wi = vec3(0.0f, 0.0f, 1.0f);
    s.pdf = 0.0f;
    s.weight = vec3(0.0f);
    s.valid = 0u;
    if (!(wo.z > 0.0f)) {
        return s;
    }
    LobeChoice c = choose_lobes(p, wo.z);
    CoatChoice coat;
    coat.probability = 0.0f;
    coat.multiscatter = 0.0f;
    if (has_clearcoat(p)) {
        coat = choose_coat(p, wo, c);
    }
    vec3 wi;
    if (BSDF_HAS_CLEARCOAT && u.x < coat.probability) {  // a scene without coats keeps none of this branch
        vec3 wi_c;
        if (BSDF_HAS_GGX_MULTISCATTER && u.x < coat.probability * coat.multiscatter) {
            wi_c = sample_uniform_hemisphere(vec2(u.y, u.z));  // the coat's multiple-scattering lobe
        } else {
            vec3 h = sample_ggx_vndf(coat.wo, p.clearcoat_alpha, vec2(u.y, u.z));
            wi_c = 2.0f * dot(coat.wo, h) * h - coat.wo;
        }
        wi = to_world(coat.frame, wi_c);
        if (!(wi_c.z > 0.0f && wi.z > 0.0f)) {
            return s;  // below the coat or below the base's shading normal: no reflection of the coat
        }
    } else {
        if (coat.probability > 0.0f) {
            u.x = min((u.x - coat.probability) / (1.0f - coat.probability), 0.99999994f);  // reused for the base
        }
        vec4 base = sample_base_direction(p, c, wo, u);
        if (base.w == 0.0f) {
            return s;
        }
        wi = vec3(base);
    }
    float pdf = coat.probability > 0.0f ? pdf_bsdf_choice(p, c, coat, wo, wi) : pdf_bsdf_lobes(p, c, wo, wi);
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
