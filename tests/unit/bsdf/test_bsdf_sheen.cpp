// The sheen of KHR_materials_sheen (shaders/lib/bsdf/sheen.glsl, layered in bsdf.glsl) on the CPU: a black sheen
// changes no bit; over a black base the lobe reflects its reference albedo E (where the extension's lobe conserves
// energy) and never more than 1 (where it would not: smooth sheens at grazing angles); over any base the layering
// never gains energy; the sheened BSDF is reciprocal; and sample_bsdf follows pdf_bsdf (chi-square, both
// hemispheres, with glass and a clear coat around the sheen).
#include <gtest/gtest.h>

#include <random>

#include "bsdf_test_setup.h"
#include "sheen_albedo_reference.h"

namespace {
using namespace fh::test;

// The kinds of base under the sheen.
enum SheenKind { BLACK_BASE, WHITE_LAMBERT, WHITE_DIELECTRIC, COLOURED, WHITE_METAL, GLASS, COATED, SHEEN_KIND_COUNT };
const char* const SHEEN_KIND_NAMES[] = {"black", "lambert", "white", "coloured", "metal", "glass", "coated"};

BsdfParams make_base(SheenKind kind) {
    switch (kind) {
        case BLACK_BASE: return make_bsdf_params(make_material(vec3(0.0f), 0.0f, 0.5f, 0.0f));
        case WHITE_LAMBERT: return make_bsdf_params(make_material(vec3(1.0f), 0.0f, 0.5f, 0.0f));
        case WHITE_DIELECTRIC: return make_bsdf_params(make_material(vec3(1.0f), 0.0f, 0.4f));
        case COLOURED: return make_bsdf_params(make_material(vec3(0.7f, 0.2f, 0.1f), 0.3f, 0.4f));
        case WHITE_METAL: return make_bsdf_params(make_material(vec3(1.0f), 1.0f, 0.3f));
        case GLASS: return with_transmission(make_bsdf_params(make_material(vec3(1.0f), 0.0f, 0.3f)), 0.5f, 1.5f, 0u);
        default: return make_bsdf_params(make_material(vec3(0.7f, 0.2f, 0.1f), 0.0f, 0.4f));
    }
}

BsdfParams make_sheened(SheenKind kind, vec3 color, float roughness) {
    BsdfParams p = with_sheen(make_base(kind), color, roughness);
    return kind == COATED ? with_clearcoat(p, 0.8f, 0.2f, vec3(0.0f, 0.0f, 1.0f)) : p;
}

TEST(Sheen, BlackSheenChangesNoBit) {
    for (int kind = 0; kind < SHEEN_KIND_COUNT; ++kind) {
        BsdfParams plain = make_base(SheenKind(kind));
        if (kind == COATED) plain = with_clearcoat(plain, 0.8f, 0.2f, vec3(0.0f, 0.0f, 1.0f));
        expect_identical_bsdfs(plain, make_sheened(SheenKind(kind), vec3(0.0f), 0.0f), 3 + kind, 80.0f);
    }
}

// Over a black base only the sheen reflects. Where the extension's lobe conserves energy (roughness >= 0.5 at
// every angle) it is that lobe, exactly: its albedo is the reference's E. Smoother sheens at grazing angles would
// reflect up to 2.5x what they receive; ours keep at most all of it.
TEST(Sheen, OverABlackBaseReflectsTheLobesAlbedoAndNeverMore) {
    uint32_t seed = 10;
    for (float roughness : {0.0f, 0.1f, 0.2f, 0.3f, 0.5f, 0.8f, 1.0f})
        for (float deg : {0.0f, 30.0f, 60.0f, 80.0f, 85.0f, 89.0f, 89.9f}) {
            const BsdfParams p = make_sheened(BLACK_BASE, vec3(1.0f), roughness);
            const vec3 wo = outgoing(deg);
            const Albedo a = estimate_albedo(p, wo, 100000, seed++);
            const double e = fh::test::sheen_albedo::albedo(wo.z, std::max(roughness, SHEEN_MIN_ROUGHNESS));
            std::printf("[furnace] white sheen roughness %.1f at %4.1f deg over black: %.4f (+- %.4f), extension's lobe %.4f\n",
                        roughness, deg, a.mean, a.standard_error, e);
            EXPECT_LT(a.mean, 1.0 + 4.0 * a.standard_error + 1e-3) << "roughness " << roughness << " at " << deg << " deg";
            if (roughness >= 0.5f)
                EXPECT_NEAR(a.mean, e, 4.0 * a.standard_error + 2e-3) << "roughness " << roughness << " at " << deg << " deg";
        }
}

// Over every base the albedo never exceeds 1. A white sheen over a white Lambert base loses what the extension's
// min(1 - E_s(mu_o), 1 - E_s(mu_i)) scaling takes from the base beyond the sheen's own reflection: at most ~14%.
TEST(Sheen, LayeringNeverGainsEnergy) {
    uint32_t seed = 100;
    for (int kind = 1; kind < SHEEN_KIND_COUNT; ++kind)
        for (float roughness : {0.0f, 0.3f, 1.0f})
            for (float deg : INCIDENCES) {
                const vec3 wo = outgoing(deg);
                const BsdfParams p = make_sheened(SheenKind(kind), vec3(1.0f), roughness);
                const Albedo a = estimate_albedo(p, wo, 60000, seed++);
                std::printf("[furnace] white sheen roughness %.1f over %-8s at %2.0f deg keeps %.4f (+- %.4f)\n", roughness,
                            SHEEN_KIND_NAMES[kind], deg, a.mean, a.standard_error);
                EXPECT_LT(a.mean, 1.0 + 4.0 * a.standard_error + 1e-3)
                    << SHEEN_KIND_NAMES[kind] << " roughness " << roughness << " at " << deg << " deg";
                if (kind == WHITE_LAMBERT && deg <= 60.0f) EXPECT_GT(a.mean, 0.8);
            }
}

// Sheen lobe and albedo scaling are both symmetric, so the sheened BSDF (without a coat) is reciprocal.
TEST(Sheen, IsReciprocal) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (float roughness : {0.0f, 0.3f, 1.0f})
        for (int i = 0; i < 2000; ++i) {
            const vec3 wo = outgoing(89.0f * uniform(rng)), wi = outgoing(89.0f * uniform(rng));
            const vec3 wi_turned(wi.x * std::cos(2.0f) - wi.y * std::sin(2.0f), wi.x * std::sin(2.0f) + wi.y * std::cos(2.0f),
                                 wi.z);
            const BsdfParams p = make_sheened(COLOURED, vec3(0.9f, 0.5f, 0.2f), roughness);
            const vec3 a = eval_bsdf(p, wo, wi_turned) / wi_turned.z, b = eval_bsdf(p, wi_turned, wo) / wo.z;
            for (int c = 0; c < 3; ++c) ASSERT_NEAR(a[c], b[c], 1e-4f * std::max(a[c], 1.0f)) << "roughness " << roughness;
        }
}

// ---- Chi-square over both hemispheres ------------------------------------------------------------------
struct SheenCase {
    SheenKind kind;
    float roughness;
    float degrees;
};

class SheenChiSquare : public ::testing::TestWithParam<SheenCase> {};

TEST_P(SheenChiSquare, SamplesFollowPdf) {
    const SheenCase c = GetParam();
    const BsdfParams p = make_sheened(c.kind, vec3(0.9f, 0.6f, 0.3f), c.roughness);
    const vec3 wo = outgoing(c.degrees);
    const TwoSidedChiSquare r = check_sampling_both_hemispheres(
        p, wo, vec3(-wo.x, -wo.y, wo.z), 500000, 701 + 1000 * int(c.kind) + int(c.degrees) + int(100 * c.roughness));
    std::printf("[chi2] sheen roughness %.2f over %-8s at %2.0f deg: chi2 %8.1f dof %5d p %.4f, int pdf %.6f\n", c.roughness,
                SHEEN_KIND_NAMES[c.kind], c.degrees, r.result.statistic, r.result.dof, r.result.p_value, r.pdf_integral);
}

std::vector<SheenCase> sheen_cases() {
    std::vector<SheenCase> cases;
    for (SheenKind k : {COLOURED, WHITE_METAL, GLASS, COATED})
        for (float r : {0.1f, 0.6f})
            for (float d : {0.0f, 50.0f, 80.0f}) cases.push_back({k, r, d});
    return cases;
}

INSTANTIATE_TEST_SUITE_P(Cases, SheenChiSquare, ::testing::ValuesIn(sheen_cases()),
                         [](const ::testing::TestParamInfo<SheenCase>& info) {
                             return std::string(SHEEN_KIND_NAMES[info.param.kind]) + "_r" +
                                    std::to_string(int(info.param.roughness * 100)) + "_deg" +
                                    std::to_string(int(info.param.degrees));
                         });

}  // namespace
