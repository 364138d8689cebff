// Checks shaders/lib/bsdf/bsdf.glsl (the glTF metallic-roughness BRDF) on the CPU: pdf normalization,
// reciprocity, energy, the estimator's mean, the Lambert limit of KHR_materials_specular, the material
// mapping, and finiteness of every sample down to grazing angles and the edges of u. The chi-square tests
// of the sampler are in test_bsdf_chi_square.cpp.
#include <gtest/gtest.h>

#include <random>

// The spec's single-scattering BSDF: the metal's multiple-scattering lobe (--microfacet compensated) has its own tests
// in test_bsdf_ggx_multiscatter.cpp (its table-shaped integrand makes the adaptive quadrature here crawl).
#define BSDF_HAS_GGX_MULTISCATTER false
#include "bsdf_test_setup.h"

namespace {
using namespace fh::test;

// ---- Normalization, reciprocity, energy -------------------------------------------------------------------
const float ALL_ROUGHNESSES[] = {0.0f, 0.05f, 0.2f, 0.5f, 1.0f};  // 0: alpha = BSDF_MIN_ALPHA

TEST(Bsdf, PdfIntegratesToOneAwayFromGrazing) {
    // Rough lobes lose a few percent below the horizon (checked against the sampler in the chi-square
    // cases); smooth ones at moderate angles must integrate to 1 - that loss.
    for (int k = 0; k < KIND_COUNT; ++k)
        for (float roughness : {0.0f, 0.05f})
            for (float degrees : {0.0f, 30.0f, 60.0f}) {
                const BsdfParams p = make_case(Kind(k), roughness);
                const vec3 wo = outgoing(degrees);
                const double total = integrate_hemisphere(wo, [&](vec3 wi) { return pdf_bsdf(p, wo, wi); });
                EXPECT_NEAR(total, 1.0, 1e-3) << KIND_NAMES[k] << " roughness " << roughness << " at " << degrees;
            }
    // Pure Lambert integrates to 1 at every angle.
    const BsdfParams lambert = make_bsdf_params(make_material(vec3(0.5f), 0.0f, 0.3f, 0.0f));
    for (float degrees : {0.0f, 60.0f, 89.0f, 89.99f}) {
        const vec3 wo = outgoing(degrees);
        EXPECT_NEAR(integrate_hemisphere(wo, [&](vec3 wi) { return pdf_bsdf(lambert, wo, wi); }), 1.0, 1e-5);
    }
}

TEST(Bsdf, IsReciprocal) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (float roughness : ALL_ROUGHNESSES)
        for (int k = 0; k < KIND_COUNT + 1; ++k) {
            const BsdfParams p = k < KIND_COUNT ? make_case(Kind(k), roughness)
                                                : make_bsdf_params(make_material(vec3(0.2f, 0.9f, 0.4f), 0.3f,
                                                                                 roughness, 0.7f, vec3(3, 1, 0.5f)));
            for (int i = 0; i < 20000; ++i) {
                vec3 a = sample_cosine_hemisphere(vec2(uniform(rng), uniform(rng)));
                vec3 b = sample_cosine_hemisphere(vec2(uniform(rng), uniform(rng)));
                if (i % 4 == 0) b = reflect(-a, vec3(0, 0, 1));  // near the specular peak
                if (!(a.z > 1e-3f && b.z > 1e-3f)) continue;
                const vec3 f_ab = eval_bsdf(p, a, b) / b.z, f_ba = eval_bsdf(p, b, a) / a.z;
                for (int c = 0; c < 3; ++c) ASSERT_NEAR(f_ab[c], f_ba[c], 2e-4f * std::max(f_ab[c], 1.0f));
            }
        }
}

// Directional albedo, int f(wo, wi) cos(wi) dwi, by quadrature, for white materials.
double white_albedo(float metallic, float roughness, float degrees, vec3 base = vec3(1.0f), float specular = 1.0f) {
    const BsdfParams p = make_bsdf_params(make_material(base, metallic, roughness, specular));
    const vec3 wo = outgoing(degrees);
    return integrate_hemisphere(wo, [&](vec3 wi) { return eval_bsdf(p, wo, wi).x; });
}

// White furnace: the albedo never exceeds 1, for white dielectric, half-metal and metal at every alpha and
// angle; each layer alone too (the metal: the single-scattering GGX albedo; the dielectric's specular layer
// alone, black base), and pure Lambert is exactly 1. The spec's literal dielectric gave 1.03 at 60 deg and
// 1.85 at 89 deg here; albedo scaling (bsdf.glsl) gives E + (1 - E) = 1 for the white dielectric, less only
// by how much the albedo table overestimates E (it is built never to underestimate it). 89.9 degrees is
// left out: there h = wo + wi cancels in float and a 1e-3 alpha lobe is noise to a few percent to quadrature.
TEST(Bsdf, WhiteFurnaceNeverGainsEnergy) {
    double largest = 0.0, smallest_dielectric = 2.0;
    for (float r : {0.0f, 0.01f, 0.05f, 0.1f, 0.2f, 0.5f, 1.0f})  // 0 and 0.01 (alpha 1e-4): alpha clamped to 1e-3
        for (float degrees : {0.0f, 30.0f, 60.0f, 75.0f, 80.0f, 85.0f, 88.0f, 89.0f}) {
            const double dielectric = white_albedo(0.0f, r, degrees), half_metal = white_albedo(0.5f, r, degrees),
                         metal = white_albedo(1.0f, r, degrees);
            std::printf("[albedo] roughness %.2f at %2.0f deg: dielectric %.4f half-metal %.4f metal %.4f\n", r, degrees,
                        dielectric, half_metal, metal);
            EXPECT_LE(dielectric, 1.0 + 1e-3) << "dielectric " << r << " " << degrees;
            EXPECT_LE(half_metal, 1.0 + 1e-3) << "half-metal " << r << " " << degrees;
            EXPECT_LE(metal, 1.0 + 1e-3) << "metal " << r << " " << degrees;
            EXPECT_NEAR(dielectric, 1.0, 1e-2) << "white dielectric " << r << " " << degrees;
            EXPECT_LE(white_albedo(0.0f, r, degrees, vec3(0.0f)), 1.0 + 1e-3) << "specular layer " << r << " " << degrees;
            EXPECT_NEAR(white_albedo(0.0f, r, degrees, vec3(1.0f), 0.0f), 1.0, 1e-4) << "Lambert";
            if (degrees == 0.0f || degrees == 60.0f || degrees == 89.0f) {
                // f0 = f90 = 1 (ior 0), where 1 - E_avg is smallest; a colored f0 (the bound holds per channel).
                const BsdfParams mirror = make_bsdf_params(make_material(vec3(1.0f), 0.0f, r, 1.0f, vec3(1.0f), 0.0f));
                const BsdfParams colored = make_bsdf_params(make_material(vec3(1.0f), 0.0f, r, 1.0f, vec3(20, 1, 0)));
                const vec3 wo = outgoing(degrees);
                if (degrees < 89.0f) {  // at 89 deg its large, noisy diffuse scale stalls the adaptive quadrature
                    EXPECT_LE(integrate_hemisphere(wo, [&](vec3 wi) { return eval_bsdf(mirror, wo, wi).x; }), 1.0 + 1e-3);
                }
                for (int c = 0; c < 3; ++c)
                    EXPECT_LE(integrate_hemisphere(wo, [&](vec3 wi) { return eval_bsdf(colored, wo, wi)[c]; }), 1.0 + 1e-3);
            }
            largest = std::max({largest, dielectric, half_metal, metal});
            smallest_dielectric = std::min(smallest_dielectric, dielectric);
        }
    std::printf("[albedo] largest %.5f, smallest white dielectric %.5f\n", largest, smallest_dielectric);
}

// The estimator weight = f cos / pdf averages to the albedo (invalid samples count as 0): sampling is unbiased.
TEST(Bsdf, WeightMeanMatchesQuadratureAlbedo) {
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    const int n = 100000;
    for (int k = 0; k < KIND_COUNT; ++k)
        for (float roughness : ALL_ROUGHNESSES)
            for (float degrees : {0.0f, 45.0f, 80.0f, 89.0f}) {
                const BsdfParams p = make_case(Kind(k), roughness);
                const vec3 wo = outgoing(degrees);
                double mean[3] = {0, 0, 0}, square[3] = {0, 0, 0};
                for (int i = 0; i < n; ++i) {
                    const BsdfSample s = sample_bsdf(p, wo, vec3(uniform(rng), uniform(rng), uniform(rng)));
                    for (int c = 0; c < 3 && s.valid != 0u; ++c) {
                        mean[c] += double(s.weight[c]) / n;
                        square[c] += double(s.weight[c]) * s.weight[c] / n;
                    }
                }
                for (int c = 0; c < 3; ++c) {
                    const double albedo = integrate_hemisphere(wo, [&](vec3 wi) { return eval_bsdf(p, wo, wi)[c]; });
                    const double sigma = std::sqrt(std::max(square[c] - mean[c] * mean[c], 0.0) / n);
                    EXPECT_NEAR(mean[c], albedo, 5.0 * sigma + 2e-3 * albedo)
                        << KIND_NAMES[k] << " roughness " << roughness << " at " << degrees << " channel " << c;
                }
            }
}

// ---- KHR_materials_specular and parameter mapping ---------------------------------------------------------
TEST(Bsdf, SpecularFactorZeroIsExactlyLambert) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    const vec3 base(0.8f, 0.3f, 0.1f);
    for (float roughness : ALL_ROUGHNESSES)
        for (float ior : {1.0f, 1.5f, 2.4f, 0.0f}) {
            const BsdfParams p = make_bsdf_params(make_material(base, 0.0f, roughness, 0.0f, vec3(2.0f), ior));
            for (int i = 0; i < 2000; ++i) {
                const vec3 wo = sample_cosine_hemisphere(vec2(uniform(rng), uniform(rng)));
                const vec3 wi = sample_cosine_hemisphere(vec2(uniform(rng), uniform(rng)));
                if (!(wo.z > 0.0f && wi.z > 0.0f)) continue;
                const vec3 f = eval_bsdf(p, wo, wi), lambert = base * (INV_PI * wi.z);
                for (int c = 0; c < 3; ++c) ASSERT_FLOAT_EQ(f[c], lambert[c]);
                ASSERT_FLOAT_EQ(pdf_bsdf(p, wo, wi), wi.z * INV_PI);  // only the cosine lobe is sampled
                const BsdfSample s = sample_bsdf(p, wo, vec3(uniform(rng), uniform(rng), uniform(rng)));
                if (s.valid == 0u) continue;
                for (int c = 0; c < 3; ++c) ASSERT_NEAR(s.weight[c], base[c], 1e-5f);
            }
        }
}

TEST(Bsdf, MaterialMapping) {
    BsdfParams p = make_bsdf_params(make_material(vec3(0.5f), 0.0f, 0.5f));
    EXPECT_NEAR(p.f0_dielectric.x, 0.04f, 1e-6f);  // ((1.5 - 1) / (1.5 + 1))^2
    EXPECT_EQ(p.f90_dielectric, 1.0f);
    EXPECT_FLOAT_EQ(p.alpha, 0.25f);
    EXPECT_EQ(make_bsdf_params(make_material(vec3(0.5f), 0.0f, 0.0f)).alpha, BSDF_MIN_ALPHA);
    p = make_bsdf_params(make_material(vec3(0.5f), 0.0f, 0.5f, 0.5f, vec3(2.0f, 100.0f, 0.0f)));
    EXPECT_NEAR(p.f0_dielectric.x, 0.04f, 1e-6f);  // min(0.04 * 2, 1) * 0.5
    EXPECT_NEAR(p.f0_dielectric.y, 0.5f, 1e-6f);   // clamped to 1 before the factor
    EXPECT_EQ(p.f0_dielectric.z, 0.0f);
    EXPECT_EQ(p.f90_dielectric, 0.5f);
    p = make_bsdf_params(make_material(vec3(0.5f), 0.0f, 0.5f, 1.0f, vec3(1.0f), 0.0f));
    EXPECT_NEAR(p.f0_dielectric.x, 1.0f, 1e-6f);  // KHR_materials_ior: ior 0 means f0 = 1
}

// ---- Finiteness ---------------------------------------------------------------------------------------------
TEST(Bsdf, EverySampleIsFiniteDownToGrazing) {
    std::vector<BsdfParams> materials;
    for (float roughness : {0.0f, 0.01f, 0.05f, 0.2f, 0.5f, 1.0f}) {
        for (int k = 0; k < KIND_COUNT; ++k) materials.push_back(make_case(Kind(k), roughness));
        materials.push_back(make_bsdf_params(make_material(vec3(0.0f), 1.0f, roughness)));  // black metal
        materials.push_back(make_bsdf_params(make_material(vec3(1.0f), 0.0f, roughness, 1.0f, vec3(1.0f), 0.0f)));
        materials.push_back(make_bsdf_params(make_material(vec3(1.0f), 0.0f, roughness, 0.0f)));  // Lambert
    }
    const float cosines[] = {1.0f, 0.5f, 1e-2f, 1e-4f, 1e-6f};
    const float edges[] = {0.0f, 1e-7f, 0.5f, 0.99f, ONE_MINUS_EPS};
    std::mt19937 rng(10);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    long checked = 0, valid = 0;
    for (const BsdfParams& p : materials)
        for (float cos_o : cosines) {
            const float sin_o = std::sqrt(1.0f - cos_o * cos_o);
            const vec3 wo(sin_o * 0.6f, sin_o * 0.8f, cos_o);
            std::vector<vec3> us;
            for (float a : edges)
                for (float b : edges)
                    for (float c : edges) us.push_back(vec3(a, b, c));
            for (int i = 0; i < 20000; ++i) us.push_back(vec3(uniform(rng), uniform(rng), uniform(rng)));
            for (vec3 u : us) {
                const BsdfSample s = sample_bsdf(p, wo, u);
                ++checked;
                ASSERT_TRUE(finite(s.weight) && std::isfinite(s.pdf) && finite(s.wi)) << u.x << " " << u.y << " " << u.z;
                ASSERT_GE(s.pdf, 0.0f);
                if (s.valid == 0u) continue;
                ++valid;
                ASSERT_GT(s.pdf, 0.0f);
                ASSERT_GT(s.wi.z, 0.0f);
                ASSERT_NEAR(length(s.wi), 1.0f, 1e-4f);
                ASSERT_TRUE(s.weight.x >= 0.0f && s.weight.y >= 0.0f && s.weight.z >= 0.0f);
                const float pdf = pdf_bsdf(p, wo, s.wi);
                ASSERT_TRUE(std::isfinite(pdf) && finite(eval_bsdf(p, wo, s.wi)));
                ASSERT_NEAR(pdf, s.pdf, 1e-3f * s.pdf);
                ASSERT_TRUE(finite(eval_bsdf(p, s.wi, wo)) && std::isfinite(pdf_bsdf(p, s.wi, wo)));  // swapped
            }
        }
    std::printf("finite: %ld samples (%ld valid)\n", checked, valid);
    // Below the surface, or exactly at the horizon: no direction, no value.
    const BsdfParams p = make_case(HALF_METAL, 0.5f);
    EXPECT_EQ(sample_bsdf(p, vec3(0.6f, 0.8f, 0.0f), vec3(0.5f)).valid, 0u);
    EXPECT_EQ(sample_bsdf(p, vec3(0.0f, 0.0f, -1.0f), vec3(0.5f)).valid, 0u);
    EXPECT_EQ(pdf_bsdf(p, vec3(0, 0, 1), vec3(0.6f, 0.8f, 0.0f)), 0.0f);
    EXPECT_EQ(eval_bsdf(p, vec3(0, 0, 1), vec3(0.6f, 0.0f, -0.8f)).x, 0.0f);
}

}  // namespace
