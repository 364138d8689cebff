// Chi-square goodness-of-fit of sample_bsdf against pdf_bsdf (Mitsuba 3 style): 3 materials x 4 roughnesses
// x 5 incidence angles, each a histogram of 1e6 sampled directions on a (cos theta, phi) grid against the
// pdf integrated over every cell; also checks every sample's pdf and the mass lost below the horizon.
#include <gtest/gtest.h>

#include <random>

#include "bsdf_test_setup.h"

namespace {
using namespace fh::test;

// ---- Chi-square: sample_bsdf's directions are distributed as pdf_bsdf says ---------------------------------
struct ChiSquareCase {
    Kind kind;
    float roughness;
    float degrees;
};

class BsdfChiSquare : public ::testing::TestWithParam<ChiSquareCase> {};

TEST_P(BsdfChiSquare, SamplesFollowPdf) {
    const ChiSquareCase c = GetParam();
    const BsdfParams p = make_case(c.kind, c.roughness);
    const vec3 wo = outgoing(c.degrees);
    const int n = 1000000;
    HemisphereGrid grid;
    std::vector<double> observed(grid.cells(), 0.0);
    double invalid = 0.0;  // samples reflected below the horizon (or degenerate)
    std::mt19937 rng(1000 * c.kind + 10 * int(c.degrees) + int(20 * c.roughness));
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    int pdf_mismatches = 0;
    for (int i = 0; i < n; ++i) {
        const BsdfSample s = sample_bsdf(p, wo, vec3(uniform(rng), uniform(rng), uniform(rng)));
        if (s.valid == 0u) {
            invalid += 1.0;
            continue;
        }
        ASSERT_TRUE(finite(s.weight) && std::isfinite(s.pdf) && s.pdf > 0.0f && s.wi.z > 0.0f);
        const float pdf = pdf_bsdf(p, wo, s.wi);
        pdf_mismatches += std::abs(pdf - s.pdf) > 1e-3f * pdf;
        observed[grid.cell_of(s.wi.x, s.wi.y, s.wi.z)] += 1.0;
    }
    EXPECT_EQ(pdf_mismatches, 0) << "sample.pdf != pdf_bsdf(wi)";
    std::vector<double> expected = integrate_cells(grid, wo, [&](vec3 wi) { return pdf_bsdf(p, wo, wi); });
    const double total = sum(expected);
    // The pdf integrates to the fraction of valid samples: GGX's tail reflects some directions below the
    // horizon, so less than 1 for rough or grazing cases, never more.
    EXPECT_LT(total, 1.0 + 1e-4) << "pdf_bsdf integrates to more than 1";
    const double lost = std::max(1.0 - total, 1.0 / n);
    EXPECT_NEAR(invalid / n, 1.0 - total, 5.0 * std::sqrt(lost / n) + 1e-4) << "mass below the horizon";
    for (double& e : expected) e *= n;
    const auto r = fh::test::chi_square_test(observed, expected);
    ASSERT_TRUE(r.error.empty()) << r.error;
    EXPECT_GT(r.p_value, fh::test::corrected_significance(fh::test::UNIT_CHI_SQUARE_TESTS))
        << "chi2 = " << r.statistic << ", dof = " << r.dof;
    std::printf("[chi2] %-10s roughness %.2f at %2.0f deg: chi2 %8.1f dof %5d p %.4f, int pdf %.6f, invalid %.6f\n",
                KIND_NAMES[c.kind], c.roughness, c.degrees, r.statistic, r.dof, r.p_value, total, invalid / n);
}

std::vector<ChiSquareCase> chi_square_cases() {
    std::vector<ChiSquareCase> cases;
    for (int k = 0; k < KIND_COUNT; ++k)
        for (float r : ROUGHNESSES)
            for (float d : INCIDENCES) cases.push_back({Kind(k), r, d});
    return cases;
}

INSTANTIATE_TEST_SUITE_P(Cases, BsdfChiSquare, ::testing::ValuesIn(chi_square_cases()),
                         [](const ::testing::TestParamInfo<ChiSquareCase>& info) {
                             return std::string(KIND_NAMES[info.param.kind]) + "_r" +
                                    std::to_string(int(info.param.roughness * 100)) + "_deg" +
                                    std::to_string(int(info.param.degrees));
                         });

}  // namespace
