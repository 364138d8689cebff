// KHR_materials_anisotropy (shaders/lib/bsdf/ggx.glsl, bsdf.glsl) on the CPU: strength 0 changes no bit; the
// anisotropic GGX is a distribution (its projected area is 1, its visible normals integrate to cos theta_o); the
// BSDF turns with its direction; the isotropic table bounds the anisotropic specular albedo, so a white dielectric
// never gains energy; reflection is reciprocal; and sample_bsdf follows pdf_bsdf (chi-square over both hemispheres,
// beside glass and a clear coat).
#include <gtest/gtest.h>

#include <random>

// The single-scattering lobes whose albedo the diffuse scaling bounds: the metal's multiple-scattering lobe, anisotropic
// too, is tested in test_bsdf_ggx_multiscatter.cpp.
#define BSDF_HAS_GGX_MULTISCATTER false
#include "bsdf_test_setup.h"

namespace {
using namespace fh::test;

// Anisotropy is tested on the first five layer bases of bsdf_test_setup.h: dielectric, metal, glass (thin and
// volume) and coated.
const int ANISO_KIND_COUNT = COATED_BASE + 1;

const vec2 DIRECTION(std::cos(0.4f), std::sin(0.4f));

TEST(Anisotropy, ZeroStrengthOrFullRoughnessChangesNoBit) {
    for (int kind = 0; kind < ANISO_KIND_COUNT; ++kind) {
        const BsdfParams p = make_layer_base(LayerBase(kind), 0.3f);
        expect_identical_bsdfs(p, with_anisotropy(p, 0.0f, DIRECTION), 3 + kind, 85.0f);
        const BsdfParams rough = make_layer_base(LayerBase(kind), 1.0f);
        expect_identical_bsdfs(rough, with_anisotropy(rough, 1.0f, DIRECTION), 13 + kind, 85.0f);
    }
}

TEST(Anisotropy, StretchesAlongTheDirectionAsTheExtensionSays) {
    const BsdfParams p = with_anisotropy(make_layer_base(METAL_BASE, 0.4f), 0.5f, 3.0f * DIRECTION);
    EXPECT_FLOAT_EQ(p.roughness.alpha, 0.16f);
    EXPECT_FLOAT_EQ(p.roughness.alpha_t, 0.16f + (1.0f - 0.16f) * 0.25f);  // mix(alpha, 1, strength^2)
    EXPECT_NEAR(p.roughness.direction.x, DIRECTION.x, 1e-6f);
    EXPECT_NEAR(p.roughness.direction.y, DIRECTION.y, 1e-6f);
    EXPECT_TRUE(has_anisotropy(p));
}

// int D(h) h.z dh = 1 (the microfacets' projected area), and the visible normals integrate to cos theta_o:
// int G1(wo) max(0, wo.h) D(h) dh = wo.z, i.e. the VNDF pdf integrates to 1 (pdf_ggx_vndf_reflection times the
// reflection Jacobian 4 wo.h, over h).
TEST(Anisotropy, DistributionAndVisibleNormalsAreNormalised) {
    for (float roughness : {0.2f, 0.5f})
        for (float strength : {0.5f, 1.0f}) {
            const GgxRoughness r = with_anisotropy(make_layer_base(METAL_BASE, roughness), strength, DIRECTION).roughness;
            ASSERT_TRUE(is_anisotropic(r));
            const double area = integrate_hemisphere(vec3(0.0f, 0.0f, 1.0f), [&](vec3 h) { return ggx_d_lobe(r, h) * h.z; });
            EXPECT_NEAR(area, 1.0, 2e-3) << "roughness " << roughness << " strength " << strength;
            for (float deg : {0.0f, 45.0f, 80.0f}) {
                const vec3 wo = outgoing(deg);
                const double visible = integrate_hemisphere(vec3(0.0f, 0.0f, 1.0f), [&](vec3 h) {
                    const float cos_oh = dot(wo, h);
                    return cos_oh > 0.0f ? pdf_ggx_vndf_reflection_lobe(r, wo, h) * 4.0f * cos_oh : 0.0f;
                });
                EXPECT_NEAR(visible, 1.0, 3e-3) << "roughness " << roughness << " strength " << strength << " at " << deg;
            }
        }
}

// Turning the direction by an angle and both directions by the same angle gives the same value.
TEST(Anisotropy, TurnsWithItsDirection) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    const BsdfParams base = make_layer_base(COATED_BASE, 0.3f);
    for (int i = 0; i < 500; ++i) {
        const float turn = 6.2831853f * uniform(rng);
        auto rotate = [&](vec3 w) { return turn_about_normal(w, turn); };
        const vec3 wo = outgoing(85.0f * uniform(rng)), wi = rotate(outgoing(85.0f * uniform(rng)));
        const BsdfParams a = with_anisotropy(base, 0.8f, DIRECTION);
        const vec3 d = rotate(vec3(DIRECTION, 0.0f));
        const BsdfParams b = with_anisotropy(base, 0.8f, vec2(d.x, d.y));
        const vec3 fa = eval_bsdf(a, wo, wi), fb = eval_bsdf(b, rotate(wo), rotate(wi));
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(fa[c], fb[c], 2e-4f * std::max(fa[c], 1.0f));
        ASSERT_NEAR(pdf_bsdf(a, wo, wi), pdf_bsdf(b, rotate(wo), rotate(wi)), 2e-4f * std::max(pdf_bsdf(a, wo, wi), 1.0f));
    }
    // And the lobe is anisotropic: turning only the light changes the value.
    const BsdfParams a = with_anisotropy(make_layer_base(METAL_BASE, 0.2f), 1.0f, vec2(1.0f, 0.0f));
    const vec3 wo = vec3(0.5f, 0.0f, 0.8660254f);
    EXPECT_GT(eval_bsdf(a, wo, vec3(-0.6f, 0.0f, 0.8f)).x, 1.5f * eval_bsdf(a, wo, vec3(-0.5f, -0.3316625f, 0.8f)).x);
}

// The albedo-scaling bound E' = f0 A' + f90 B' (bsdf.glsl, specular_albedo): linear in (f0, f90) with 0 <= f0 <= f90
// <= 1, so it bounds every material's specular albedo when it bounds the two corners: f0 = 0, f90 = 1 (B: metal of
// base colour 0) and f0 = f90 = 1 (A + B: metal of base colour 1). Quadrature of eval_bsdf over strengths,
// roughnesses, angles to 89.5 deg and azimuths; prints the margin the data need (ANISOTROPY_ALBEDO_MARGIN's value).
TEST(Anisotropy, SpecularAlbedoBoundHolds) {
    double needed = 0.0, slack = 1.0;
    for (float roughness : {0.02f, 0.2f, 0.5f, 0.8f})
        for (float strength : {0.3f, 0.7f, 1.0f})
            for (float deg : {0.0f, 70.0f, 85.0f, 89.5f})
                for (float azimuth : {0.0f, 0.7f, 1.5707963f}) {
                    if (deg == 0.0f && azimuth != 0.0f) continue;
                    const float t = glm::radians(deg);
                    const vec3 wo(std::sin(t) * std::cos(azimuth), std::sin(t) * std::sin(azimuth), std::cos(t));
                    auto metal = [&](float base) {
                        return with_anisotropy(make_bsdf_params(make_material(vec3(base), 1.0f, roughness)), strength,
                                               vec2(1.0f, 0.0f));
                    };
                    const BsdfParams white = metal(1.0f), black = metal(0.0f);
                    const double a_plus_b = integrate_hemisphere(wo, [&](vec3 wi) { return eval_bsdf(white, wo, wi).x; });
                    const double b = integrate_hemisphere(wo, [&](vec3 wi) { return eval_bsdf(black, wo, wi).x; });
                    const vec2 bound = specular_albedo(white, wo);
                    if (deg == 0.0f && strength == 1.0f)
                        std::printf("[albedo] white anisotropic metal, roughness %.2f, strength 1, head-on keeps %.4f\n",
                                    roughness, a_plus_b);
                    EXPECT_LE(b, bound.y + 1e-3) << roughness << " " << strength << " " << deg << " " << azimuth;
                    EXPECT_LE(a_plus_b, bound.x + bound.y + 1e-3) << roughness << " " << strength << " " << deg << " " << azimuth;
                    const double w = schlick_weight(wo.z), margin = ANISOTROPY_ALBEDO_MARGIN * w;
                    if (w > 1e-3)
                        needed = std::max({needed, (b - (bound.y - margin)) / w,
                                           (a_plus_b - (bound.x + bound.y - 2.0 * margin)) / (2.0 * w)});
                    slack = std::min(slack, bound.y - b);
                }
    std::printf("[bound] margin the data need: %.4f (used %.4f); least slack of B: %.5f\n", needed,
                double(ANISOTROPY_ALBEDO_MARGIN), slack);
}

// A white dielectric (Lambert under an anisotropic specular layer) keeps at most what it receives, at every angle
// and azimuth; printed: how much the bound loses.
TEST(Anisotropy, WhiteDielectricNeverGainsEnergy) {
    uint32_t seed = 100;
    for (float roughness : {0.05f, 0.3f, 0.7f})
        for (float strength : {0.5f, 1.0f})
            for (float deg : INCIDENCES)
                for (float azimuth : {0.0f, 1.5707963f}) {
                    const float t = glm::radians(deg);
                    const vec3 wo(std::sin(t) * std::cos(azimuth), std::sin(t) * std::sin(azimuth), std::cos(t));
                    const BsdfParams p = with_anisotropy(make_bsdf_params(make_material(vec3(1.0f), 0.0f, roughness)),
                                                         strength, vec2(1.0f, 0.0f));
                    const Albedo a = estimate_albedo(p, wo, 40000, seed++);
                    if (deg == 0.0f || deg == 80.0f)
                        std::printf("[furnace] white dielectric, roughness %.2f, anisotropy %.1f, %2.0f deg, azimuth %.2f: "
                                    "%.4f (+- %.4f)\n", roughness, strength, deg, azimuth, a.mean, a.standard_error);
                    EXPECT_LT(a.mean, 1.0 + 4.0 * a.standard_error + 1e-3)
                        << roughness << " " << strength << " " << deg << " " << azimuth;
                }
}

TEST(Anisotropy, ReflectionIsReciprocal) {
    expect_reciprocal_reflection(with_anisotropy(make_layer_base(DIELECTRIC_BASE, 0.3f), 0.9f, DIRECTION), 5, 2000,
                                 "anisotropic dielectric");
}

// ---- Chi-square over both hemispheres ------------------------------------------------------------------
struct AnisoCase {
    LayerBase kind;
    float degrees;
    float azimuth;  // of wo, from the direction
};

class AnisotropyChiSquare : public ::testing::TestWithParam<AnisoCase> {};

TEST_P(AnisotropyChiSquare, SamplesFollowPdf) {
    const AnisoCase c = GetParam();
    const BsdfParams p = with_anisotropy(make_layer_base(c.kind, 0.35f), 0.8f, vec2(1.0f, 0.0f));
    const float t = glm::radians(c.degrees);
    const vec3 wo(std::sin(t) * std::cos(c.azimuth), std::sin(t) * std::sin(c.azimuth), std::cos(t));
    vec3 peak(-wo.x, -wo.y, wo.z);
    if (c.kind == VOLUME_GLASS_BASE) {
        const float sin2_t = (1.0f - wo.z * wo.z) / (p.glass.eta * p.glass.eta);
        peak = vec3(-wo.x / p.glass.eta, -wo.y / p.glass.eta, std::sqrt(1.0f - sin2_t));
    }
    const TwoSidedChiSquare r = check_sampling_both_hemispheres(
        p, wo, peak, 500000, 3001 + 1000 * int(c.kind) + int(c.degrees) + int(10.0f * c.azimuth));
    std::printf("[chi2] anisotropic %-11s at %2.0f deg, azimuth %.2f: chi2 %8.1f dof %5d p %.4f, int pdf %.6f\n",
                LAYER_BASE_NAMES[c.kind], c.degrees, c.azimuth, r.result.statistic, r.result.dof, r.result.p_value,
                r.pdf_integral);
}

std::vector<AnisoCase> aniso_cases() {
    std::vector<AnisoCase> cases;
    for (LayerBase k : {DIELECTRIC_BASE, METAL_BASE, THIN_GLASS_BASE, VOLUME_GLASS_BASE, COATED_BASE})
        for (float d : {0.0f, 60.0f})
            for (float azimuth : {0.3f, 1.2f}) {
                if (d == 0.0f && azimuth != 0.3f) continue;  // at normal incidence the azimuth does not matter
                cases.push_back({k, d, azimuth});
            }
    return cases;
}

INSTANTIATE_TEST_SUITE_P(Cases, AnisotropyChiSquare, ::testing::ValuesIn(aniso_cases()),
                         [](const ::testing::TestParamInfo<AnisoCase>& info) {
                             return std::string(LAYER_BASE_NAMES[info.param.kind]) + "_deg" +
                                    std::to_string(int(info.param.degrees)) + "_az" +
                                    std::to_string(int(10.0f * info.param.azimuth));
                         });

}  // namespace
