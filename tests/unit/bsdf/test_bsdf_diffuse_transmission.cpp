// KHR_materials_diffuse_transmission (shaders/lib/bsdf/bsdf.glsl) on the CPU: a factor of 0 changes no bit; a white
// Lambert sheet keeps exactly all the energy, split between reflection and transmission by the factor; under a
// specular layer nothing gains energy; the BTDF is symmetric (thin-walled, reciprocal); and sample_bsdf follows
// pdf_bsdf (chi-square over both hemispheres, with glass, sheen and a clear coat beside it).
#include <gtest/gtest.h>

#include <random>

#include "bsdf_test_setup.h"

namespace {
using namespace fh::test;

enum DiffuseKind { LAMBERT, DIELECTRIC_BASE, GLASS, SHEEN, COATED, DIFFUSE_KIND_COUNT };
const char* const DIFFUSE_KIND_NAMES[] = {"lambert", "dielectric", "glass", "sheen", "coated"};

BsdfParams make_base(DiffuseKind kind) {
    switch (kind) {
        case LAMBERT: return make_bsdf_params(make_material(vec3(1.0f), 0.0f, 0.5f, 0.0f));
        case DIELECTRIC_BASE: return make_bsdf_params(make_material(vec3(1.0f), 0.0f, 0.4f));
        case GLASS: return with_transmission(make_bsdf_params(make_material(vec3(1.0f), 0.0f, 0.3f)), 0.5f, 1.5f, 1u);
        case SHEEN: return with_sheen(make_bsdf_params(make_material(vec3(0.8f, 0.6f, 0.4f), 0.0f, 0.4f)), vec3(0.5f), 0.6f);
        default:
            return with_clearcoat(make_bsdf_params(make_material(vec3(0.8f, 0.6f, 0.4f), 0.2f, 0.4f)), 0.7f, 0.2f,
                                  vec3(0.0f, 0.0f, 1.0f));
    }
}

BsdfParams make_case(DiffuseKind kind, float factor, vec3 color) {
    return with_diffuse_transmission(make_base(kind), factor, color);
}

TEST(DiffuseTransmission, ZeroFactorChangesNoBit) {
    for (int kind = 0; kind < DIFFUSE_KIND_COUNT; ++kind)
        expect_identical_bsdfs(make_base(DiffuseKind(kind)), make_case(DiffuseKind(kind), 0.0f, vec3(0.3f)), 3 + kind,
                               85.0f);
}

// A white Lambert sheet (no specular) with a white transmission colour keeps all the energy at every angle, a
// share `factor` of it sent through.
TEST(DiffuseTransmission, WhiteLambertSheetKeepsAllTheEnergy) {
    uint32_t seed = 10;
    for (float factor : {0.3f, 1.0f})
        for (float deg : INCIDENCES) {
            const Albedo a = estimate_albedo(make_case(LAMBERT, factor, vec3(1.0f)), outgoing(deg), 100000, seed++);
            EXPECT_NEAR(a.mean, 1.0, 1e-4) << "factor " << factor << " at " << deg << " deg";
            EXPECT_NEAR(a.transmitted, factor, 5.0 * std::sqrt(factor * (1.0 - factor) / 100000.0) + 1e-3);
        }
}

// Under a specular layer, with glass, sheen or a coat beside it: nothing exceeds 1, and a white dielectric sheet
// that sends half its diffuse light through keeps as much as the same dielectric without (the table's accuracy).
TEST(DiffuseTransmission, NeverGainsEnergy) {
    uint32_t seed = 100;
    for (int kind = 1; kind < DIFFUSE_KIND_COUNT; ++kind)
        for (float deg : INCIDENCES) {
            const vec3 wo = outgoing(deg);
            const Albedo a = estimate_albedo(make_case(DiffuseKind(kind), 0.5f, vec3(1.0f)), wo, 60000, seed++);
            const Albedo base = estimate_albedo(make_base(DiffuseKind(kind)), wo, 60000, seed++);
            std::printf("[furnace] diffuse transmission 0.5 beside %-10s at %2.0f deg keeps %.4f (+- %.4f), %.3f through; "
                        "without %.4f\n",
                        DIFFUSE_KIND_NAMES[kind], deg, a.mean, a.standard_error, a.transmitted, base.mean);
            EXPECT_LT(a.mean, 1.0 + 4.0 * a.standard_error + 1e-3) << DIFFUSE_KIND_NAMES[kind] << " at " << deg << " deg";
            if (kind == DIELECTRIC_BASE)
                EXPECT_NEAR(a.mean, base.mean, 4.0 * std::hypot(a.standard_error, base.standard_error) + 2e-3);
        }
}

// Thin-walled: light from wo above to wi below carries what light from wi's side to wo's does, each direction
// seen from its own side (z mirrored).
TEST(DiffuseTransmission, IsReciprocal) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    const BsdfParams p = make_case(DIELECTRIC_BASE, 0.7f, vec3(0.9f, 0.5f, 0.2f));
    for (int i = 0; i < 2000; ++i) {
        const vec3 wo = outgoing(89.0f * uniform(rng)), up = outgoing(89.0f * uniform(rng));
        const vec3 wi(up.x * std::cos(2.0f) - up.y * std::sin(2.0f), up.x * std::sin(2.0f) + up.y * std::cos(2.0f), -up.z);
        const vec3 a = eval_bsdf(p, wo, wi) / -wi.z;
        const vec3 b = eval_bsdf(p, vec3(wi.x, wi.y, -wi.z), vec3(wo.x, wo.y, -wo.z)) / wo.z;
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(a[c], b[c], 1e-5f * std::max(a[c], 1.0f));
        ASSERT_GT(a.x, 0.0f);
    }
}

// ---- Chi-square over both hemispheres ------------------------------------------------------------------
struct DiffuseCase {
    DiffuseKind kind;
    float degrees;
};

class DiffuseTransmissionChiSquare : public ::testing::TestWithParam<DiffuseCase> {};

TEST_P(DiffuseTransmissionChiSquare, SamplesFollowPdf) {
    const DiffuseCase c = GetParam();
    const BsdfParams p = make_case(c.kind, 0.6f, vec3(0.7f, 0.8f, 0.9f));
    const vec3 wo = outgoing(c.degrees);
    const TwoSidedChiSquare r =
        check_sampling_both_hemispheres(p, wo, vec3(-wo.x, -wo.y, wo.z), 500000, 901 + 1000 * int(c.kind) + int(c.degrees));
    std::printf("[chi2] diffuse transmission beside %-10s at %2.0f deg: chi2 %8.1f dof %5d p %.4f, int pdf %.6f\n",
                DIFFUSE_KIND_NAMES[c.kind], c.degrees, r.result.statistic, r.result.dof, r.result.p_value, r.pdf_integral);
}

std::vector<DiffuseCase> diffuse_cases() {
    std::vector<DiffuseCase> cases;
    for (DiffuseKind k : {DIELECTRIC_BASE, GLASS, SHEEN, COATED})
        for (float d : {0.0f, 50.0f, 80.0f}) cases.push_back({k, d});
    return cases;
}

INSTANTIATE_TEST_SUITE_P(Cases, DiffuseTransmissionChiSquare, ::testing::ValuesIn(diffuse_cases()),
                         [](const ::testing::TestParamInfo<DiffuseCase>& info) {
                             return std::string(DIFFUSE_KIND_NAMES[info.param.kind]) + "_deg" +
                                    std::to_string(int(info.param.degrees));
                         });

}  // namespace
