// KHR_materials_iridescence (shaders/lib/bsdf/thin_film.glsl, bsdf.glsl, dielectric.glsl, engine/scene/thin_film_bound.cpp)
// on the CPU: a film of weight or thickness 0 changes no bit; the film's Fresnel agrees with the reflectance of the
// two-interface film (the Airy sum, per wavelength) integrated against independent fits of the CIE 1931 matching
// functions; the host's envelope bounds the film's Fresnel off its grid; white materials under a film never gain
// energy (diffuse base, metal, glass); reflection stays reciprocal; sample_bsdf follows pdf_bsdf (chi-square).
#include <gtest/gtest.h>

#include <complex>
#include <random>

#include "bsdf_test_setup.h"
#include "scene/gltf/gltf_material.h"
#include "scene/thin_film_bound.h"

namespace {
using namespace fh::test;

// The layer bases of bsdf_test_setup.h a film is tested on (all but the coated one: the extension ignores the coat).
const LayerBase FILM_BASES[] = {DIELECTRIC_BASE, METAL_BASE, HALF_METAL_BASE, THIN_GLASS_BASE, VOLUME_GLASS_BASE};

// A dielectric material of `ior` under a film of index `film_ior`, `thickest` nm (and, with a thickness texture,
// down to `thinnest`), as the host sees it.
struct FilmMaterial {
    fh::gpu::Material material;
    fh::gpu::MaterialLayers layers;
};

FilmMaterial make_film_material(float ior, float film_ior, float thickest, float thinnest = -1.0f) {
    FilmMaterial f{make_material(vec3(0.8f), 0.0f, 0.5f, 1.0f, vec3(1.0f), ior), fh::gltf::make_default_layers()};
    f.layers.iridescence = 1.0f;
    f.layers.iridescence_ior = film_ior;
    f.layers.iridescence_thickness_max = thickest;
    if (thinnest >= 0.0f) {
        f.layers.iridescence_thickness_min = thinnest;
        f.layers.iridescence_thickness_texture = 0u;  // "has a thickness texture": the whole range
    }
    return f;
}

fh::FilmFresnelBound bound_for(float ior, float film_ior, float thickest) {
    const FilmMaterial f = make_film_material(ior, film_ior, thickest);
    return fh::bound_thin_film_fresnel(f.material, f.layers);
}

BsdfParams with_film(BsdfParams p, float weight, float thickness, float film_ior) {
    const fh::FilmFresnelBound bound = bound_for(1.5f, film_ior, thickness);
    return with_iridescence(p, weight, thickness, film_ior, vec2(bound.a, bound.b));
}

TEST(Iridescence, ZeroWeightOrThicknessChangesNoBit) {
    for (int kind = 0; kind < 5; ++kind) {
        const BsdfParams p = make_layer_base(FILM_BASES[kind], 0.3f);
        expect_identical_bsdfs(p, with_iridescence(p, 0.0f, 400.0f, 1.3f, vec2(0.3f, 1.2f)), 3 + kind, 85.0f);
        expect_identical_bsdfs(p, with_iridescence(p, 1.0f, 0.0f, 1.3f, vec2(0.3f, 1.2f)), 13 + kind, 85.0f);
    }
}

// ---- The film's Fresnel against the physics it approximates ---------------------------------------------------
// Wyman, Sloan & Shirley 2013, "Simple Analytic Approximations to the CIE XYZ Color Matching Functions" (the
// multi-lobe fit): independent of the Fourier-space Gaussians the extension integrates with.
double lobe(double lambda, double mu, double below, double above) {
    const double t = (lambda - mu) / (lambda < mu ? below : above);
    return std::exp(-0.5 * t * t);
}
glm::dvec3 cie_1931(double lambda) {
    return {1.056 * lobe(lambda, 599.8, 37.9, 31.0) + 0.362 * lobe(lambda, 442.0, 16.0, 26.7) -
                0.065 * lobe(lambda, 501.1, 20.4, 26.2),
            0.821 * lobe(lambda, 568.8, 46.9, 40.5) + 0.286 * lobe(lambda, 530.9, 16.3, 31.1),
            1.217 * lobe(lambda, 437.0, 11.8, 36.0) + 0.681 * lobe(lambda, 459.0, 26.0, 13.8)};
}

double schlick(double f0, double c) { return f0 + (1.0 - f0) * std::pow(1.0 - c, 5.0); }

// The film's two interfaces as the extension models them: Schlick reflectances at the angle of incidence (air |
// film) and of refraction (film | base), the base's index from its f0.
struct Interfaces {
    double c2, n_base, r12, r23;
};

Interfaces find_interfaces(double c1, double n_film, double f0) {
    Interfaces i;
    i.c2 = std::sqrt(1.0 - (1.0 - c1 * c1) / (n_film * n_film));
    i.n_base = (1.0 + std::sqrt(f0)) / (1.0 - std::sqrt(f0));
    i.r12 = schlick(std::pow((n_film - 1.0) / (n_film + 1.0), 2.0), c1);
    i.r23 = schlick(std::pow((i.n_base - n_film) / (i.n_base + n_film), 2.0), i.c2);
    return i;
}

// The film's reflectance at one wavelength: the amplitudes of every bounce between its two interfaces summed (Airy),
// with the extension's interface reflectances, phases (0 or pi) and base index.
double airy_reflectance(double lambda, double c1, double d, double n_film, double f0) {
    const Interfaces i = find_interfaces(c1, n_film, f0);
    const double r12 = i.r12, r23 = i.r23;
    const double phi12 = n_film < 1.0 ? M_PI : 0.0, phi21 = M_PI - phi12, phi23 = i.n_base < n_film ? M_PI : 0.0;
    const double delta = 2.0 * M_PI * 2.0 * n_film * d * i.c2 / lambda;
    using C = std::complex<double>;
    const C top = std::polar(std::sqrt(r12), phi12);
    const C down_up = (1.0 - r12) * std::polar(std::sqrt(r23), phi23 + delta);
    const C round_trip = std::polar(std::sqrt(r12 * r23), phi21 + phi23 + delta);
    return std::norm(top + down_up / (1.0 - round_trip));
}

// The extension's convention: the incoherent part (the mean over wavelengths, R12 + Rs) is white in RGB; the
// interference colours are XYZ -> linear Rec.709 of the rest, XYZ normalised by the integral of y-bar.
vec3 reference_film_fresnel(double c1, double d, double n_film, double f0) {
    glm::dvec3 xyz(0.0);
    double y_norm = 0.0;
    const Interfaces i = find_interfaces(c1, n_film, f0);
    const double mean = i.r12 + (1.0 - i.r12) * (1.0 - i.r12) * i.r23 / (1.0 - i.r12 * i.r23);
    for (double lambda = 360.0; lambda <= 830.0; lambda += 0.25) {
        const glm::dvec3 cmf = cie_1931(lambda);
        xyz += (airy_reflectance(lambda, c1, d, n_film, f0) - mean) * cmf;
        y_norm += cmf.y;
    }
    xyz /= y_norm;
    const glm::dvec3 rgb = glm::dmat3(XYZ_TO_LINEAR_REC709) * xyz + glm::dvec3(mean);
    return vec3(glm::clamp(rgb, 0.0, 1.0));
}

TEST(Iridescence, FresnelMatchesTheFilmIntegratedOverTheSpectrum) {
    double worst = 0.0, worst_dielectric = 0.0, mean_error = 0.0;
    int count = 0;
    for (float n_film : {1.3f, 1.8f})
        for (float f0 : {0.04f, 0.11f, 0.6f})
            for (float d : {150.0f, 300.0f, 500.0f, 800.0f})
                for (float c : {1.0f, 0.7f, 0.3f}) {
                    const vec3 ours = eval_thin_film_fresnel(c, d, n_film, vec3(f0));
                    const vec3 ref = reference_film_fresnel(c, d, n_film, f0);
                    for (int k = 0; k < 3; ++k) {
                        const double e = std::abs(double(ours[k]) - ref[k]);
                        worst = std::max(worst, e);
                        if (f0 < 0.5f) worst_dielectric = std::max(worst_dielectric, e);
                        mean_error += e;
                        ++count;
                        // Two fits of the matching functions differ by up to 0.025; over bright bases the Airy sum's terms past m = 2,
                        // which the extension leaves out, count too.
                        EXPECT_NEAR(ours[k], ref[k], f0 < 0.5f ? 0.025f : 0.06f)
                            << "film " << n_film << " f0 " << f0 << " " << d << " nm, cos " << c << " channel " << k;
                    }
                }
    std::printf("[spectral] film Fresnel against Airy x CIE 1931 (Wyman 2013 fit): mean |error| %.4f, worst %.4f "
                "(dielectric bases, f0 <= 0.11: %.4f)\n", mean_error / count, worst, worst_dielectric);
    // The interference is there: a 300 nm film of index 1.3 on glass is coloured (the channels differ), and its
    // colour changes with the angle.
    const vec3 head_on = eval_thin_film_fresnel(1.0f, 300.0f, 1.3f, vec3(0.04f));
    const vec3 oblique = eval_thin_film_fresnel(0.5f, 300.0f, 1.3f, vec3(0.04f));
    EXPECT_GT(max_value(head_on) - std::min({head_on.x, head_on.y, head_on.z}), 0.01f);
    EXPECT_GT(glm::length(head_on - oblique), 0.01f);
}

// At normal incidence a film of the outside's index, or of no thickness, leaves the base's reflectance. (Obliquely
// it does not: the extension's Schlick curve for the air | film interface reflects light even between equal indices,
// (1 - c)^5 of it; hence with_iridescence treats a film of thickness 0 as no film at all.)
TEST(Iridescence, FilmOfTheOutsideIndexOrNoThicknessIsTheBaseAtNormalIncidence) {
    for (float f0 : {0.04f, 0.5f}) {
        const vec3 no_index = eval_thin_film_fresnel(1.0f, 400.0f, 1.0f, vec3(f0));
        const vec3 no_thickness = eval_thin_film_fresnel(1.0f, 0.0f, 1.8f, vec3(f0));
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(no_index[k], f0, 0.01f) << f0;
            EXPECT_NEAR(no_thickness[k], f0, 0.01f) << f0;
        }
    }
    const vec3 oblique = eval_thin_film_fresnel(0.2f, 400.0f, 1.0f, vec3(0.04f));
    EXPECT_GT(std::abs(oblique.y - float(schlick(0.04, 0.2))), 0.0f);
}

// ---- The envelope the albedo scaling uses -----------------------------------------------------------------------
TEST(Iridescence, EnvelopeBoundsTheFilmOffItsGrid) {
    struct Film {
        float ior, film_ior, thickest, thinnest;
    };
    for (const Film f : {Film{1.5f, 1.3f, 400.0f, -1.0f}, Film{1.5f, 1.3f, 400.0f, 100.0f}, Film{2.0f, 1.33f, 400.0f, -1.0f},
                         Film{1.5f, 1.8f, 600.0f, 200.0f}, Film{1.2f, 2.3f, 1200.0f, 0.0f}, Film{1.5f, 1.0f, 300.0f, -1.0f},
                         Film{1.5f, 1.3f, 50000.0f, -1.0f}}) {
        const FilmMaterial film = make_film_material(f.ior, f.film_ior, f.thickest, f.thinnest);
        const fh::FilmFresnelBound bound = fh::bound_thin_film_fresnel(film.material, film.layers);
        const float excess = fh::measure_thin_film_excess(film.material, film.layers, bound, 4);
        const float f0 = std::pow((f.ior - 1.0f) / (f.ior + 1.0f), 2.0f);
        const vec3 head_on = eval_thin_film_fresnel(1.0f, f.thickest, f.film_ior, vec3(f0));
        std::printf("[envelope] base ior %.2f, film %.2f, %g..%g nm: a = %.4f, b = %.3f (film head-on %.4f, base %.4f), "
                    "excess on a 4x finer grid %.2e\n", f.ior, f.film_ior, f.thinnest < 0.0f ? f.thickest : f.thinnest,
                    f.thickest, bound.a, bound.b, max_value(head_on), f0, excess);
        EXPECT_LE(excess, 1e-4f);
        EXPECT_GE(bound.a, max_value(head_on));  // w(1) = 0: a alone bounds the film head-on
        EXPECT_LE(bound.a, 1.0f);
        EXPECT_GE(bound.b, 1.0f);  // F(0) = 1
    }
    // Without b > 1 the extension's default film on glass would need a much larger a: the least a with b = 1
    // (bisection on the same grid).
    const FilmMaterial film = make_film_material(1.5f, 1.3f, 400.0f);
    fh::FilmFresnelBound b1{0.0f, 1.0f}, high{1.0f, 1.0f};
    for (int step = 0; step < 24; ++step) {
        const fh::FilmFresnelBound mid{0.5f * (b1.a + high.a), 1.0f};
        (fh::measure_thin_film_excess(film.material, film.layers, mid, 1) > 0.0f ? b1 : high) = mid;
    }
    const fh::FilmFresnelBound used = fh::bound_thin_film_fresnel(film.material, film.layers);
    std::printf("[envelope] default film on glass with b = 1 needs a = %.4f; with b = %.3f, a = %.4f\n", high.a, used.b,
                used.a);
    EXPECT_LT(used.a, high.a);
    fh::gpu::MaterialLayers none = fh::gltf::make_default_layers();
    EXPECT_EQ(fh::bound_thin_film_fresnel(make_material(vec3(1.0f), 0.0f, 0.5f), none).a, 0.0f);
}

// The extension's RGB reflectance passes 1 over bright bases (out-of-gamut interference colours); Fredholm's is
// clamped, so no film makes light. Grid over bases of f0 0 to 0.99, films of index 1 to 2.3, 0 to 1200 nm.
TEST(Iridescence, ClampKeepsTheFilmFromMakingLight) {
    float largest = 0.0f, largest_f0 = 0.0f;
    for (float f0 : {0.0f, 0.04f, 0.1f, 0.3f, 0.6f, 0.9f, 0.99f})
        for (float n_film : {1.0f, 1.2f, 1.33f, 1.5f, 1.8f, 2.0f, 2.3f})
            for (int d = 0; d <= 1200; d += 5)
                for (int k = 1; k <= 100; ++k) {
                    const float c = float(k) / 100.0f;
                    const vec3 sum = sum_thin_film_fresnel(c, float(d), n_film, vec3(f0));
                    const vec3 clamped = eval_thin_film_fresnel(c, float(d), n_film, vec3(f0));
                    ASSERT_LE(max_value(clamped), 1.0f);
                    ASSERT_GE(std::min({clamped.x, clamped.y, clamped.z}), 0.0f);
                    if (max_value(sum) > largest) largest = max_value(sum), largest_f0 = f0;
                }
    std::printf("[clamp] the extension's film reflectance reaches %.3f (base f0 %.2f); clamped to 1\n", largest,
                largest_f0);
    EXPECT_GT(largest, 1.0f);  // the clamp is needed
}

// Every material under a film keeps at most what it receives (white base colours, glass counted with eta^2),
// at every angle; printed: what a white dielectric keeps, with and without the film.
TEST(Iridescence, WhiteMaterialsUnderAFilmNeverGainEnergy) {
    uint32_t seed = 300;
    for (float roughness : {0.05f, 0.3f, 0.8f})
        for (float thickness : {250.0f, 400.0f, 700.0f})
            for (float deg : INCIDENCES) {
                const vec3 wo = outgoing(deg);
                const BsdfParams bases[] = {
                    make_bsdf_params(make_material(vec3(1.0f), 0.0f, roughness)),
                    make_bsdf_params(make_material(vec3(1.0f), 1.0f, roughness)),
                    with_transmission(make_bsdf_params(make_material(vec3(1.0f), 0.0f, roughness)), 1.0f, 1.5f, 1u),
                    with_transmission(make_bsdf_params(make_material(vec3(1.0f), 0.0f, roughness)), 1.0f, 1.5f, 0u),
                    with_transmission(make_bsdf_params(make_material(vec3(1.0f), 0.0f, roughness)), 1.0f, 1.0f / 1.5f, 0u)};
                const char* names[] = {"dielectric", "metal", "thin glass", "glass entering", "glass leaving"};
                for (int b = 0; b < 5; ++b) {
                    const BsdfParams p = with_film(bases[b], 1.0f, thickness, 1.3f);
                    const Albedo a = estimate_albedo(p, wo, 20000, seed++);
                    EXPECT_LT(a.mean, 1.0 + 4.0 * a.standard_error + 1e-3)
                        << names[b] << " roughness " << roughness << " " << thickness << " nm at " << deg;
                    if (b == 0 && thickness == 400.0f && (deg == 0.0f || deg == 80.0f)) {
                        const Albedo bare = estimate_albedo(bases[b], wo, 20000, seed++);
                        std::printf("[furnace] white dielectric, roughness %.2f, %2.0f deg: %.4f under a 400 nm film of "
                                    "index 1.3, %.4f without\n", roughness, deg, a.mean, bare.mean);
                    }
                }
            }
}

TEST(Iridescence, ReflectionIsReciprocal) {
    for (LayerBase kind : {DIELECTRIC_BASE, METAL_BASE, HALF_METAL_BASE, THIN_GLASS_BASE})
        expect_reciprocal_reflection(with_film(make_layer_base(kind, 0.3f), 0.8f, 350.0f, 1.6f), 5 + kind, 1000,
                                     LAYER_BASE_NAMES[kind]);
}

// ---- Chi-square over both hemispheres ---------------------------------------------------------------------------
struct FilmCase {
    LayerBase kind;
    float degrees;
};

class IridescenceChiSquare : public ::testing::TestWithParam<FilmCase> {};

TEST_P(IridescenceChiSquare, SamplesFollowPdf) {
    const FilmCase c = GetParam();
    const BsdfParams p = with_film(make_layer_base(c.kind, 0.35f), 0.9f, 450.0f, 1.8f);
    const vec3 wo = outgoing(c.degrees);
    vec3 peak(-wo.x, -wo.y, wo.z);
    if (c.kind == VOLUME_GLASS_BASE) {
        const float sin2_t = (1.0f - wo.z * wo.z) / (p.glass.eta * p.glass.eta);
        peak = vec3(-wo.x / p.glass.eta, -wo.y / p.glass.eta, std::sqrt(1.0f - sin2_t));
    }
    const TwoSidedChiSquare r =
        check_sampling_both_hemispheres(p, wo, peak, 500000, 5001 + 1000 * int(c.kind) + int(c.degrees));
    std::printf("[chi2] film on %-11s at %2.0f deg: chi2 %8.1f dof %5d p %.4f, int pdf %.6f\n", LAYER_BASE_NAMES[c.kind],
                c.degrees, r.result.statistic, r.result.dof, r.result.p_value, r.pdf_integral);
}

std::vector<FilmCase> film_cases() {
    std::vector<FilmCase> cases;
    for (LayerBase k : FILM_BASES)
        for (float d : {0.0f, 60.0f}) cases.push_back({k, d});
    return cases;
}

INSTANTIATE_TEST_SUITE_P(Cases, IridescenceChiSquare, ::testing::ValuesIn(film_cases()),
                         [](const ::testing::TestParamInfo<FilmCase>& info) {
                             return std::string(LAYER_BASE_NAMES[info.param.kind]) + "_deg" +
                                    std::to_string(int(info.param.degrees));
                         });

}  // namespace
