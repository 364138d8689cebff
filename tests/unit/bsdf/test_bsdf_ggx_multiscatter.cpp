// The metal's multiple-scattering lobe (shaders/lib/bsdf/ggx_multiscatter.glsl, --microfacet compensated): a white
// rough metal keeps all the energy it receives, coloured metals never gain, the lobe is reciprocal and sampled without
// bias, and where there is nothing to give back (roughness 0, no metal) the BSDF keeps its bits. The chi-square cases
// of test_bsdf_chi_square.cpp (metal and half-metal at roughness 0.05 to 1) sample the lobe too.
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

// The multiple-scattering lobe's albedo, channel c: what eval_bsdf adds to the single-scattering BSDF depends on
// theta_i alone, so 2 pi int f_ms cos dmu_i, by the midpoint rule (4096 steps).
double lobe_albedo(const fh::gpu::Material& m, float degrees, int c = 0) {
    BsdfParams single, compensated;
    {
        Compensated scope(false);
        single = make_bsdf_params(m);
    }
    Compensated scope(true);
    compensated = make_bsdf_params(m);
    const vec3 wo = outgoing(degrees);
    const int n = 4096;
    double sum = 0.0;
    for (int k = 0; k < n; ++k) {
        const float mu = (float(k) + 0.5f) / float(n);
        const vec3 wi = turn_about_normal(vec3(std::sqrt(1.0f - mu * mu), 0.0f, mu), 2.4f);
        ggx_multiscatter = true;
        const double with = eval_bsdf(compensated, wo, wi)[c];
        ggx_multiscatter = false;
        const double without = eval_bsdf(single, wo, wi)[c];
        sum += with - without;  // f_ms cos: the same at every azimuth
    }
    return 2.0 * 3.14159265358979 * sum / n;  // d omega = d mu d phi
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

// The stretched lobe loses more than the isotropic one of the smaller alpha: given back by that one, it never gains
// (sampled estimate: the anisotropic lobe's albedo depends on the azimuth).
TEST(GgxMultiscatter, AnisotropicWhiteMetalNeverGains) {
    Compensated scope(true);
    double lowest = 2.0;
    for (float strength : {0.5f, 1.0f})
        for (float r : {0.05f, 0.5f})
            for (float degrees : {0.0f, 80.0f})
                for (float azimuth : {0.0f, 1.57f}) {
                    const BsdfParams p = with_anisotropy(make_bsdf_params(make_material(vec3(1.0f), 1.0f, r)),
                                                         strength, vec2(std::cos(azimuth), std::sin(azimuth)));
                    const Albedo a = estimate_albedo(p, outgoing(degrees), 100000, 31);
                    EXPECT_LE(a.mean, 1.0 + 5.0 * a.standard_error + 1e-3)
                        << strength << " " << r << " " << degrees << " " << azimuth;
                    lowest = std::min(lowest, a.mean);
                }
    std::printf("[anisotropy] lowest white metal albedo: %.4f (what the stretched lobe loses beyond the isotropic)\n",
                lowest);
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

// Light tracing and BDPT evaluate the BSDF with its arguments swapped: the lobe is symmetric.
TEST(GgxMultiscatter, IsReciprocal) {
    Compensated scope(true);
    for (float r : {0.1f, 0.5f, 1.0f}) {
        expect_reciprocal_reflection(metal(vec3(1.0f, 0.78f, 0.34f), r, true), 11, 2000, "gold");
        expect_reciprocal_reflection(make_bsdf_params(make_material(vec3(0.5f, 0.8f, 0.6f), 0.5f, r)), 12, 2000,
                                     "half-metal");
        expect_reciprocal_reflection(with_sheen(metal(vec3(0.9f), r, true), vec3(0.5f), 0.4f), 13, 2000, "sheen");
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
