// The metal's multiple-scattering lobe (shaders/lib/bsdf/ggx_multiscatter.glsl, --microfacet compensated): a white
// rough metal keeps all the energy it receives, coloured metals never gain, the lobe is reciprocal and sampled without
// bias, and where there is nothing to give back (roughness 0, no metal) the BSDF keeps its bits. The chi-square cases
// of test_bsdf_chi_square.cpp (metal and half-metal at roughness 0.05 to 1) sample the lobe too, and those of
// test_bsdf_clearcoat.cpp the clear coat's.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

namespace fh::test {
inline bool ggx_multiscatter = true;  // switched per test: compensated or the spec's single scattering
}  // namespace fh::test
#define BSDF_HAS_GGX_MULTISCATTER fh::test::ggx_multiscatter
#include "bsdf_test_setup.h"

namespace {
using namespace fh::test;

struct Compensated {
    explicit Compensated(bool on) { ggx_multiscatter = on; }
    ~Compensated() { ggx_multiscatter = true; }
};

// int f(wo, wi) cos(wi) dwi of channel c of the spec's single-scattering BSDF, by adaptive quadrature over the
// hemisphere (with the lobe's table kinks in the integrand that quadrature crawls, so the lobe is integrated apart).
double single_albedo(const fh::gpu::Material& m, float degrees, int c = 0) {
    Compensated scope(false);
    const BsdfParams p = make_bsdf_params(m);
    const vec3 wo = outgoing(degrees);
    return integrate_hemisphere(wo, [&](vec3 wi) { return eval_bsdf(p, wo, wi)[c]; });
}

// What compensation adds to the albedo, channel c, where it depends on theta_i alone (an isotropic lobe):
// 2 pi int (f_compensated - f_single) cos dmu_i, by the midpoint rule (4096 steps) at one azimuth.
double added_albedo(const BsdfParams& single, const BsdfParams& compensated, vec3 wo, int c) {
    const int n = 4096;
    double sum = 0.0;
    for (int k = 0; k < n; ++k) {
        const float mu = (float(k) + 0.5f) / float(n);
        const vec3 wi = turn_about_normal(vec3(std::sqrt(1.0f - mu * mu), 0.0f, mu), 2.4f);
        ggx_multiscatter = true;
        const double with = eval_bsdf(compensated, wo, wi)[c];
        ggx_multiscatter = false;
        sum += with - eval_bsdf(single, wo, wi)[c];
    }
    ggx_multiscatter = true;
    return 2.0 * 3.14159265358979 * sum / n;  // d omega = d mu d phi
}

// The multiple-scattering lobe's albedo, channel c (added_albedo of the material with and without it).
double lobe_albedo(const fh::gpu::Material& m, float degrees, int c = 0) {
    BsdfParams single, compensated;
    {
        Compensated scope(false);
        single = make_bsdf_params(m);
    }
    Compensated scope(true);
    compensated = make_bsdf_params(m);
    return added_albedo(single, compensated, outgoing(degrees), c);
}

BsdfParams metal(vec3 color, float roughness, bool compensated) {
    Compensated scope(compensated);
    return make_bsdf_params(make_material(color, 1.0f, roughness));
}

// The albedo with the lobe: single scattering's plus the lobe's.
double albedo(const fh::gpu::Material& m, float degrees, int c = 0) {
    return single_albedo(m, degrees, c) + lobe_albedo(m, degrees, c);
}

const float ROUGH[] = {0.05f, 0.2f, 0.5f, 1.0f};
const float ANGLES[] = {0.0f, 60.0f, 80.0f, 89.0f};

// A white metal gives back exactly what the table says single scattering loses; the table's nodes are raised (it
// never underestimates the single-scattering albedo), so the sum stays at most 1 and falls short by the table's
// overestimate. The single-scattering albedo is printed beside it (glTF's default material, roughness 1, normal
// incidence: about 0.4).
TEST(GgxMultiscatter, WhiteRoughMetalConservesEnergy) {
    double lowest = 2.0;
    for (float r : ROUGH)
        for (float degrees : ANGLES) {
            const fh::gpu::Material white = make_material(vec3(1.0f), 1.0f, r);
            const double single = single_albedo(white, degrees), lobe = lobe_albedo(white, degrees);
            const double compensated = single + lobe;
            std::printf("[furnace] roughness %.2f at %2.0f deg: single %.4f compensated %.4f\n", r, degrees, single,
                        compensated);
            EXPECT_LE(compensated, 1.0 + 1e-3) << r << " " << degrees;
            EXPECT_NEAR(compensated, 1.0, 1.5e-2) << r << " " << degrees;
            EXPECT_GE(lobe, 0.0) << r << " " << degrees;
            lowest = std::min(lowest, compensated);
        }
    std::printf("[furnace] lowest compensated white metal: %.5f\n", lowest);
}

// Coloured and grey metals never reflect more than they receive, per channel.
TEST(GgxMultiscatter, ColouredMetalsNeverGain) {
    for (vec3 color : {vec3(1.0f, 0.78f, 0.34f), vec3(0.5f)})
        for (float r : {0.2f, 1.0f})
            for (float degrees : {0.0f, 80.0f})
                for (int c = 0; c < 3; ++c)
                    EXPECT_LE(albedo(make_material(color, 1.0f, r), degrees, c), 1.0 + 1e-3) << r << " " << degrees;
}

// What an anisotropic material keeps of the light from `degrees` (the direction at `azimuth`, strength given): single
// scattering by adaptive quadrature, and with the multiple-scattering lobe, which has the table's kinks, integrated
// apart on a 256 x 256 midpoint grid over (mu_i, phi_i).
struct KeptLight {
    double single, compensated;
};
KeptLight anisotropic_kept(const fh::gpu::Material& m, float strength, float azimuth, float degrees) {
    auto make = [&](bool compensated) {
        Compensated scope(compensated);
        return with_anisotropy(make_bsdf_params(m), strength, vec2(std::cos(azimuth), std::sin(azimuth)));
    };
    const BsdfParams single = make(false), compensated = make(true);
    const vec3 wo = outgoing(degrees);
    Compensated scope(false);
    const double kept = integrate_hemisphere(wo, [&](vec3 wi) { return eval_bsdf(single, wo, wi).x; });
    const int n = 256;
    double lobe = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const float mu = (i + 0.5f) / n, phi = 6.2831853f * (j + 0.5f) / n;
            const float st = std::sqrt(1.0f - mu * mu);
            const vec3 wi(st * std::cos(phi), st * std::sin(phi), mu);
            ggx_multiscatter = true;
            const double with = eval_bsdf(compensated, wo, wi).x;
            ggx_multiscatter = false;
            lobe += with - eval_bsdf(single, wo, wi).x;
        }
    return {kept, kept + lobe * 2.0 * 3.14159265358979 / (double(n) * n)};
}

// An anisotropic lobe (the metal's, or the specular layer's: a material of f0 = 1 over black loses and gets back what
// a white metal does) follows the anisotropic table (ggx_anisotropic_albedo.glsl), whose E depends on the azimuth
// too: it keeps all the light at every angle and azimuth, within what the table overestimates; the sampled estimate
// agrees with the quadrature.
void expect_anisotropic_lobe_conserves_energy(const char* name, float metallic, vec3 base, float ior) {
    double lowest = 2.0, lowest_single = 2.0;
    for (float strength : {0.5f, 1.0f})
        for (float r : {0.05f, 0.3f, 0.7f})
            for (float degrees : {0.0f, 60.0f, 80.0f})
                for (float azimuth : {0.0f, 0.8f, 1.57f}) {
                    if (degrees == 0.0f && azimuth > 0.0f) continue;
                    const fh::gpu::Material m = make_material(base, metallic, r, 1.0f, vec3(1.0f), ior);
                    const KeptLight kept = anisotropic_kept(m, strength, azimuth, degrees);
                    EXPECT_LE(kept.compensated, 1.0 + 1e-3) << name << " " << strength << " " << r << " " << degrees << " " << azimuth;
                    EXPECT_NEAR(kept.compensated, 1.0, 2.5e-2) << name << " " << strength << " " << r << " " << degrees << " " << azimuth;
                    if (degrees == 0.0f || degrees == 80.0f)
                        std::printf("[anisotropy] %s, strength %.1f, roughness %.2f, %2.0f deg, azimuth %.2f: "
                                    "single %.4f compensated %.4f\n", name, strength, r, degrees, azimuth, kept.single,
                                    kept.compensated);
                    lowest = std::min(lowest, kept.compensated);
                    lowest_single = std::min(lowest_single, kept.single);
                    if (r == 0.3f && azimuth == 0.8f) {
                        Compensated scope(true);
                        const BsdfParams p = with_anisotropy(make_bsdf_params(m), strength,
                                                             vec2(std::cos(azimuth), std::sin(azimuth)));
                        const Albedo a = estimate_albedo(p, outgoing(degrees), 200000, 31);
                        EXPECT_NEAR(a.mean, kept.compensated, 5.0 * a.standard_error + 2e-3) << name << " " << strength
                                                                                             << " " << degrees;
                    }
                }
    std::printf("[anisotropy] lowest %s albedo: %.4f compensated, %.4f single scattering\n", name, lowest,
                lowest_single);
}

TEST(GgxMultiscatter, AnisotropicWhiteMetalConservesEnergy) {
    expect_anisotropic_lobe_conserves_energy("white metal", 1.0f, vec3(1.0f), 1.5f);
}

TEST(GgxMultiscatter, AnisotropicSpecularLayerConservesEnergy) {
    expect_anisotropic_lobe_conserves_energy("f0 = 1 layer over black", 0.0f, vec3(0.0f), 0.0f);
}

// sample_bsdf follows pdf_bsdf for anisotropic metals, whose multiple-scattering lobe carries up to half the light.
TEST(GgxMultiscatter, AnisotropicLobeSamplesFollowPdf) {
    Compensated scope(true);
    for (float r : {0.05f, 0.5f})
        for (float degrees : {0.0f, 60.0f}) {
            const BsdfParams p = with_anisotropy(make_bsdf_params(make_material(vec3(0.9f, 0.7f, 0.4f), 1.0f, r)),
                                                 1.0f, vec2(0.6f, 0.8f));
            const vec3 wo = outgoing(degrees);
            const TwoSidedChiSquare c = check_sampling_both_hemispheres(p, wo, vec3(-wo.x, -wo.y, wo.z), 500000,
                                                                        71 + int(degrees) + int(100 * r));
            std::printf("[chi2] anisotropic metal, roughness %.2f at %2.0f deg: chi2 %8.1f dof %5d p %.4f\n", r, degrees,
                        c.result.statistic, c.result.dof, c.result.p_value);
        }
}

// Coloured anisotropic metals never gain, per channel (sampled).
TEST(GgxMultiscatter, AnisotropicColouredMetalsNeverGain) {
    Compensated scope(true);
    for (vec3 color : {vec3(1.0f, 0.78f, 0.34f), vec3(0.5f)})
        for (float degrees : {0.0f, 80.0f}) {
            const BsdfParams p = with_anisotropy(make_bsdf_params(make_material(color, 1.0f, 0.1f)), 1.0f,
                                                 vec2(1.0f, 0.0f));
            const Albedo a = estimate_albedo(p, outgoing(degrees), 100000, 33);
            EXPECT_LE(a.mean, 1.0 + 5.0 * a.standard_error + 1e-3) << degrees;
        }
}

// The dielectric's specular layer gets the lobe too, with its own F_ms. At f0 = 1 (ior 0, white specular colour: a
// specular-glossiness material of specular 1) over a black base it loses all of single scattering's loss, as a white
// metal does, and gets it all back; a white base under a 0.04 layer keeps every bit of the light either way (the
// diffuse lobe's scaling counts the lobe), and a coloured one never gains.
TEST(GgxMultiscatter, DielectricLayerConservesEnergy) {
    double lowest_mirror = 2.0, lowest_white = 2.0, highest = 0.0;
    for (float r : ROUGH)
        for (float degrees : ANGLES) {
            const fh::gpu::Material mirror = make_material(vec3(0.0f), 0.0f, r, 1.0f, vec3(1.0f), 0.0f);
            const double single = single_albedo(mirror, degrees), compensated = single + lobe_albedo(mirror, degrees);
            EXPECT_LE(compensated, 1.0 + 1e-3) << r << " " << degrees;
            EXPECT_GE(compensated, single) << r << " " << degrees;
            lowest_mirror = std::min(lowest_mirror, compensated);
            Compensated scope(true);
            const Albedo white = estimate_albedo(make_bsdf_params(make_material(vec3(1.0f), 0.0f, r)),
                                                 outgoing(degrees), 100000, 41);
            EXPECT_NEAR(white.mean, 1.0, 5.0 * white.standard_error + 5e-3) << r << " " << degrees;
            lowest_white = std::min(lowest_white, white.mean);
            // Coloured bases, and a white one under the f0 = 1 layer (whose lobe gives back nearly all of the loss: the
            // diffuse lobe must not be handed it too).
            for (const fh::gpu::Material& m : {make_material(vec3(0.9f, 0.3f, 0.1f), 0.0f, r),
                                               make_material(vec3(0.05f), 0.0f, r),
                                               make_material(vec3(1.0f), 0.0f, r, 1.0f, vec3(1.0f), 0.0f)}) {
                const Albedo a = estimate_albedo(make_bsdf_params(m), outgoing(degrees), 50000, 43);
                EXPECT_LE(a.mean, 1.0 + 5.0 * a.standard_error + 1e-3) << r << " " << degrees;
                highest = std::max(highest, a.mean);
            }
        }
    EXPECT_GT(lowest_mirror, 0.99);
    std::printf("[dielectric] lowest f0 = 1 layer over black: %.5f; white base: %.4f; the others at most %.4f\n",
                lowest_mirror, lowest_white, highest);
}

// A clear coat (f0 0.04, f90 1) gets a lobe of its own. Over a black base only the coat reflects, and what
// compensation adds depends on theta_i alone: by the midpoint rule it must be clearcoat F_ms (1 - E(mu_o)), where F_ms
// is Kulla and Conty's for the coat's Schlick Fresnel; clearcoat_albedo, which weighs the base, must count it; and a
// white base under a rough coat must still keep what it receives, no more.
TEST(GgxMultiscatter, ClearCoatGivesBackWhatItsLobeLoses) {
    const fh::gpu::Material black = make_material(vec3(0.0f), 0.0f, 0.5f, 0.0f);
    const float weight = 0.8f;
    auto coated = [&](const fh::gpu::Material& base, float r, bool compensated) {
        Compensated scope(compensated);
        return with_clearcoat(make_bsdf_params(base), weight, r, vec3(0.0f, 0.0f, 1.0f));
    };
    double most = 0.0;
    for (float r : {0.2f, 0.5f, 1.0f}) {
        const float alpha = r * r;
        const float e_average = white_ggx_albedo(ggx_albedo_average(alpha));
        const double f_average = CLEARCOAT_F0 + (1.0 - CLEARCOAT_F0) / 21.0;
        const double f_ms = f_average * f_average * e_average / (1.0 - f_average * (1.0 - e_average));
        const BsdfParams single = coated(black, r, false), compensated = coated(black, r, true);
        for (float degrees : ANGLES) {
            const vec3 wo = outgoing(degrees);
            const double lobe = added_albedo(single, compensated, wo, 0);
            const double expected = weight * f_ms * (1.0 - white_ggx_albedo(ggx_albedo(wo.z, alpha)));
            EXPECT_NEAR(lobe, expected, 2e-3 * expected + 1e-7) << r << " " << degrees;
            EXPECT_NEAR(clearcoat_albedo(compensated, wo.z) - clearcoat_albedo(single, wo.z), expected, 1e-6)
                << r << " " << degrees;
            most = std::max(most, lobe);
        }
        Compensated scope(true);
        for (float degrees : {0.0f, 80.0f}) {
            const Albedo white = estimate_albedo(coated(make_material(vec3(1.0f), 0.0f, 0.5f), r, true),
                                                 outgoing(degrees), 100000, 61);
            EXPECT_NEAR(white.mean, 1.0, 5.0 * white.standard_error + 5e-3) << r << " " << degrees;
            EXPECT_LT(white.mean, 1.0 + 5.0 * white.standard_error + 1e-3) << r << " " << degrees;
        }
    }
    std::printf("[coat] the coat's lobe gives back at most %.5f of the light (weight %.1f)\n", most, weight);
}

// Light tracing and BDPT evaluate the BSDF with its arguments swapped: the lobe is symmetric.
TEST(GgxMultiscatter, IsReciprocal) {
    Compensated scope(true);
    for (float r : {0.1f, 0.5f, 1.0f}) {
        expect_reciprocal_reflection(metal(vec3(1.0f, 0.78f, 0.34f), r, true), 11, 2000, "gold");
        expect_reciprocal_reflection(make_bsdf_params(make_material(vec3(0.5f, 0.8f, 0.6f), 0.5f, r)), 12, 2000,
                                     "half-metal");
        expect_reciprocal_reflection(with_sheen(metal(vec3(0.9f), r, true), vec3(0.5f), 0.4f), 13, 2000, "sheen");
        expect_reciprocal_reflection(with_anisotropy(metal(vec3(0.9f, 0.7f, 0.5f), r, true), 0.8f, vec2(0.6f, 0.8f)), 15,
                                     2000, "anisotropic metal");
        expect_reciprocal_reflection(make_bsdf_params(make_material(vec3(0.3f, 0.6f, 0.2f), 0.0f, r, 1.0f,
                                                                    vec3(1.0f, 0.8f, 0.5f), 0.0f)),
                                     14, 2000, "f0 = 1 dielectric");
    }
}

// The estimator's mean is the quadrature's albedo: the lobe's uniform sampling is unbiased (and its weights bounded).
TEST(GgxMultiscatter, SampledAlbedoMatchesQuadrature) {
    for (float r : {0.05f, 0.3f, 1.0f})
        for (float degrees : {0.0f, 60.0f, 89.0f}) {
            const fh::gpu::Material white = make_material(vec3(1.0f), 1.0f, r);
            const double exact = albedo(white, degrees, 1);
            Compensated scope(true);
            const Albedo a = estimate_albedo(make_bsdf_params(white), outgoing(degrees), 200000, 21);
            std::printf("[sampled] roughness %.2f at %2.0f deg: %.4f +- %.4f, quadrature %.4f\n", r, degrees, a.mean,
                        a.standard_error, exact);
            EXPECT_NEAR(a.mean, exact, 5.0 * a.standard_error + 2e-3) << r << " " << degrees;
        }
}

// No lobe where nothing is lost (roughness 0) or there is no GGX lobe (a Lambertian dielectric, specularFactor 0): the
// same bits whether compensated or not.
TEST(GgxMultiscatter, NothingToGiveBackKeepsTheBits) {
    for (const fh::gpu::Material& m : {make_material(vec3(0.9f), 1.0f, 0.0f), make_material(vec3(0.7f), 0.0f, 0.0f),
                                       make_material(vec3(0.2f, 0.5f, 0.9f), 0.0f, 1.0f, 0.0f)}) {
        const BsdfParams single = [&] {
            Compensated scope(false);
            return make_bsdf_params(m);
        }();
        Compensated scope(true);
        const BsdfParams compensated = make_bsdf_params(m);
        EXPECT_EQ(compensated.multiscatter_norm, 0.0f);
        expect_identical_bsdfs(single, compensated, 5, 89.0f);
    }
}

}  // namespace
