// The clear coat of KHR_materials_clearcoat (shaders/lib/bsdf/bsdf.glsl) on the CPU: a coat of weight 0 changes no
// bit, over a black base it reflects its own albedo clearcoat E_c, over any base the layering keeps exactly
// clearcoat E_c + (1 - clearcoat E_c) x the base's albedo (so a white base stays white and nothing gains
// energy), the coat lobe is reciprocal, and sample_bsdf follows pdf_bsdf (chi-square, both hemispheres, with
// tilted coat normals and glass under the coat).
#include <gtest/gtest.h>

#include <random>

#include "bsdf_test_setup.h"

namespace {
using namespace fh::test;

// A unit normal tilted by `degrees` from +z towards +x (a coat normal map's).
vec3 tilted(float degrees) {
    const float t = glm::radians(degrees);
    return vec3(std::sin(t), 0.0f, std::cos(t));
}

// The kinds of base under the coat.
enum CoatKind { WHITE_DIELECTRIC, BLACK_BASE, WHITE_METAL, COLOURED, TILTED, GLASS, COAT_KIND_COUNT };
const char* const COAT_KIND_NAMES[] = {"white", "black", "metal", "coloured", "tilted", "glass"};

BsdfParams make_base(CoatKind kind, float roughness) {
    switch (kind) {
        case WHITE_DIELECTRIC:
        case TILTED: return make_bsdf_params(make_material(vec3(1.0f), 0.0f, roughness));
        case BLACK_BASE: return make_bsdf_params(make_material(vec3(0.0f), 0.0f, roughness, 0.0f));
        case WHITE_METAL: return make_bsdf_params(make_material(vec3(1.0f), 1.0f, roughness));
        case COLOURED: return make_bsdf_params(make_material(vec3(0.7f, 0.2f, 0.1f), 0.3f, roughness));
        default:
            return with_transmission(make_bsdf_params(make_material(vec3(1.0f), 0.0f, roughness)), 0.5f, 1.5f, 0u);
    }
}

BsdfParams make_coated(CoatKind kind, float base_roughness, float clearcoat, float coat_roughness) {
    return with_clearcoat(make_base(kind, base_roughness), clearcoat, coat_roughness,
                          kind == TILTED ? tilted(25.0f) : vec3(0.0f, 0.0f, 1.0f));
}


TEST(Clearcoat, ZeroWeightChangesNoBit) {
    for (int kind = 0; kind < COAT_KIND_COUNT; ++kind) {
        const BsdfParams base = make_base(CoatKind(kind), 0.4f);
        expect_identical_bsdfs(base, with_clearcoat(base, 0.0f, 0.2f, tilted(10.0f)), 3 + kind, 80.0f);
    }
}

// Over a black base (no Lambert, no specular) only the coat reflects: its albedo clearcoat (0.04 A + B), which
// is 0.04 x clearcoat for a smooth coat seen head-on.
TEST(Clearcoat, OverABlackBaseReflectsItsOwnAlbedo) {
    uint32_t seed = 10;
    for (float coat_roughness : {0.0f, 0.3f, 0.7f, 1.0f})
        for (float deg : INCIDENCES) {
            const BsdfParams p = make_coated(BLACK_BASE, 0.5f, 0.8f, coat_roughness);
            const vec3 wo = outgoing(deg);
            const Albedo a = estimate_albedo(p, wo, 100000, seed++);
            const double expected = clearcoat_albedo(p, wo.z);
            EXPECT_NEAR(a.mean, expected, 4.0 * a.standard_error + 3e-3)
                << "coat roughness " << coat_roughness << " at " << deg << " deg";
            if (coat_roughness == 0.0f && deg == 0.0f) EXPECT_NEAR(expected, 0.8 * 0.04, 2e-3);
        }
}

// The layering rule itself: albedo = clearcoat E_c(mu_o) + (1 - clearcoat E_c(mu_o)) x albedo of the base, for
// every kind of base; a white dielectric stays within the table's accuracy of white, and nothing exceeds 1.
TEST(Clearcoat, LayeringKeepsTheBaseShareAndNeverGainsEnergy) {
    uint32_t seed = 100;
    for (int kind = 0; kind < COAT_KIND_COUNT; ++kind)
        for (float coat_roughness : {0.0f, 0.3f, 1.0f})
            for (float deg : INCIDENCES) {
                const vec3 wo = outgoing(deg);
                const BsdfParams p = make_coated(CoatKind(kind), 0.4f, 1.0f, coat_roughness);
                const Albedo coated = estimate_albedo(p, wo, 60000, seed++);
                const Albedo base = estimate_albedo(make_base(CoatKind(kind), 0.4f), wo, 60000, seed++);
                std::printf("[furnace] coat over %-8s coat roughness %.1f at %2.0f deg keeps %.4f (+- %.4f); base "
                            "alone %.4f\n",
                            COAT_KIND_NAMES[kind], coat_roughness, deg, coated.mean, coated.standard_error, base.mean);
                EXPECT_LT(coated.mean, 1.0 + 4.0 * coated.standard_error + 1e-3)
                    << COAT_KIND_NAMES[kind] << " coat roughness " << coat_roughness << " at " << deg << " deg";
                if (kind == TILTED) continue;  // part of a tilted coat's lobe falls below the base: lost, not moved
                const double e = clearcoat_albedo(p, wo.z);
                const double sigma = std::hypot(coated.standard_error, base.standard_error);
                EXPECT_NEAR(coated.mean, e + (1.0 - e) * base.mean, 4.0 * sigma + 3e-3)
                    << COAT_KIND_NAMES[kind] << " coat roughness " << coat_roughness << " at " << deg << " deg";
                if (kind == WHITE_DIELECTRIC && deg <= 60.0f) EXPECT_GT(coated.mean, 0.985);
            }
}

// The coat lobe alone (over a black base) is symmetric in wo and wi; the coated BSDF is not, by design (the
// base is weighted on the viewer's side, as KHR_materials_clearcoat's fresnel_coat does; bsdf.glsl).
TEST(Clearcoat, CoatLobeIsReciprocal) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (float coat_roughness : {0.1f, 0.5f, 1.0f})
        for (int i = 0; i < 2000; ++i) {
            const vec3 wo = outgoing(85.0f * uniform(rng)), wi = outgoing(85.0f * uniform(rng));
            const vec3 wi_turned(wi.x * std::cos(2.0f) - wi.y * std::sin(2.0f),
                                 wi.x * std::sin(2.0f) + wi.y * std::cos(2.0f), wi.z);
            const BsdfParams p = with_clearcoat(make_base(BLACK_BASE, 0.5f), 1.0f, coat_roughness, tilted(15.0f));
            const float a = eval_bsdf(p, wo, wi_turned).y / wi_turned.z;
            const float b = eval_bsdf(p, wi_turned, wo).y / wo.z;
            // f cos is taken about the coat's normal: compare f = (f cos) / cos about that normal.
            const float ca = dot(wi_turned, tilted(15.0f)), cb = dot(wo, tilted(15.0f));
            if (ca <= 0.05f || cb <= 0.05f) continue;
            ASSERT_NEAR(a * wi_turned.z / ca, b * wo.z / cb, 1e-3f * std::max(a * wi_turned.z / ca, 1.0f));
        }
}

// ---- Chi-square over both hemispheres ------------------------------------------------------------------
struct CoatCase {
    CoatKind kind;
    float coat_roughness;
    float degrees;
};

class CoatChiSquare : public ::testing::TestWithParam<CoatCase> {};

TEST_P(CoatChiSquare, SamplesFollowPdf) {
    const CoatCase c = GetParam();
    const BsdfParams p = make_coated(c.kind, 0.5f, 0.7f, c.coat_roughness);
    const vec3 wo = outgoing(c.degrees);
    // The quadrature splits cells at the base's mirror direction (and its image below); a tilted coat's peak is
    // elsewhere, which only makes the quadrature work harder.
    const TwoSidedChiSquare r = check_sampling_both_hemispheres(
        p, wo, vec3(-wo.x, -wo.y, wo.z), 500000, 501 + 1000 * int(c.kind) + int(c.degrees) + int(100 * c.coat_roughness));
    std::printf("[chi2] coat over %-8s coat roughness %.2f at %2.0f deg: chi2 %8.1f dof %5d p %.4f, int pdf %.6f\n",
                COAT_KIND_NAMES[c.kind], c.coat_roughness, c.degrees, r.result.statistic, r.result.dof,
                r.result.p_value, r.pdf_integral);
}

std::vector<CoatCase> coat_cases() {
    std::vector<CoatCase> cases;
    for (CoatKind k : {COLOURED, WHITE_METAL, TILTED, GLASS})
        for (float r : {0.1f, 0.5f})
            for (float d : {0.0f, 50.0f, 80.0f}) cases.push_back({k, r, d});
    // A rough coat over black: its multiple-scattering lobe (uniform directions) is a few percent of what it samples.
    for (float d : {0.0f, 80.0f}) cases.push_back({BLACK_BASE, 1.0f, d});
    return cases;
}

INSTANTIATE_TEST_SUITE_P(Cases, CoatChiSquare, ::testing::ValuesIn(coat_cases()),
                         [](const ::testing::TestParamInfo<CoatCase>& info) {
                             return std::string(COAT_KIND_NAMES[info.param.kind]) + "_r" +
                                    std::to_string(int(info.param.coat_roughness * 100)) + "_deg" +
                                    std::to_string(int(info.param.degrees));
                         });

}  // namespace
