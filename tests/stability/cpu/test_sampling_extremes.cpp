// Chi-square tests (Mitsuba 3 style) of the warps of shaders/lib/sampling/sampling.glsl and ggx.glsl that
// tests/unit does not test on their own: the concentric disk, and GGX visible-normal sampling down to
// alpha = 1e-3 and wo at 89.9 degrees, histogrammed in the stretched space where every lobe is wide;
// and every warp finite at the edges of u (0, 2^-24, 1 - 2^-24, ...). The cosine hemisphere, the uniform
// triangle and the Gaussian filter have their chi-square tests in tests/unit/test_sampling.cpp; lights.glsl
// reads the stage bindings (and GLSL specialization constants), so it does not compile on the CPU.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "chi_square.h"
#include "stability_cpu.h"
#include "lib/core/cpp_compat.h"
namespace fh::glsl {
#include "lib/bsdf/ggx.glsl"
}  // namespace fh::glsl

namespace {
using namespace fh::glsl;
using namespace fh::test::stability;
using fh::test::chi_square_test;
using glm::dvec3;

constexpr int SAMPLES = 1000000;

// Chi-square of the histogram (rows x columns cells) and of its 8 x 8 blocks (stability_cpu.h, coarsen).
void expect_pass(const std::vector<double>& observed, const std::vector<double>& expected, int rows, int columns,
                 const std::string& what) {
    const double level = fh::test::corrected_significance(STABILITY_CHI_SQUARE_TESTS);
    for (int coarse = 0; coarse < 2; ++coarse) {
        const fh::test::ChiSquareResult r =
            coarse ? chi_square_test(coarsen(observed, rows, columns), coarsen(expected, rows, columns))
                   : chi_square_test(observed, expected);
        ASSERT_TRUE(r.error.empty()) << what << ": " << r.error;
        EXPECT_GT(r.p_value, level) << what << (coarse ? " (8 x 8 blocks)" : "") << ": chi2 = " << r.statistic
                                    << ", dof = " << r.dof;
        std::printf("[chi2] %-30s %-6s chi2 %9.1f dof %5d p %.4f (level %.2g)\n", what.c_str(),
                    coarse ? "coarse" : "fine", r.statistic, r.dof, r.p_value, level);
    }
}

// ---- Concentric disk: uniform on the unit disk ------------------------------------------------------------
// Polar cells of equal area (r^2 and phi uniform), so every cell expects SAMPLES / cells.
TEST(SamplingExtremes, ConcentricDiskChiSquare) {
    const int res_r = 64, res_phi = 128;
    std::vector<double> observed(res_r * res_phi, 0.0), expected(res_r * res_phi, double(SAMPLES) / (res_r * res_phi));
    Rng rng(11);
    for (int i = 0; i < SAMPLES; ++i) {
        const vec2 d = sample_concentric_disk(vec2(rng.uniform(), rng.uniform()));
        const double r2 = double(d.x) * d.x + double(d.y) * d.y;
        ASSERT_LE(r2, 1.0 + 1e-6);
        double phi = std::atan2(double(d.y), double(d.x));
        if (phi < 0.0) phi += 2.0 * M_PI;
        const int i_r = std::min(int(r2 * res_r), res_r - 1);
        const int i_phi = std::min(int(phi / (2.0 * M_PI) * res_phi), res_phi - 1);
        observed[i_r * res_phi + i_phi] += 1.0;
    }
    expect_pass(observed, expected, res_r, res_phi, "concentric disk");
}

// ---- GGX visible normals -----------------------------------------------------------------------------------
// h ~ D_wo (sample_ggx_vndf) binned by its stretched direction s = normalize(h.x / a, h.y / a, h.z) on a
// (cos theta, phi) grid; expected cell masses integrate D_wo(h(s)) dw_h/dw_s, written from the papers in
// double (stability_cpu.h), over each cell. The test therefore also checks the stretch invariance the sampler
// relies on, and the pdf the renderer uses (pdf_ggx_vndf_reflection, times the reflection Jacobian 4 wo.h)
// against D_wo at every sample.
struct VndfCase {
    float degrees;
    float alpha;
};

class VndfChiSquare : public ::testing::TestWithParam<VndfCase> {};

TEST_P(VndfChiSquare, VisibleNormalsFollowDwo) {
    const VndfCase c = GetParam();
    const vec3 wo = direction_at(c.degrees);
    const dvec3 wo_d(wo);
    const double a = c.alpha;
    fh::test::HemisphereGrid grid;
    std::vector<double> observed(grid.cells(), 0.0);
    Rng rng(uint32_t(1000 * c.degrees + 1e4 * c.alpha));
    long degenerate = 0, back_facing = 0;
    double worst_pdf = 0.0;  // largest relative error of the renderer's pdf against D_wo / (4 wo.h)
    for (int i = 0; i < SAMPLES; ++i) {
        const vec3 h = sample_ggx_vndf(wo, c.alpha, vec2(rng.uniform(), rng.uniform()));
        ASSERT_TRUE(finite(h));
        if (h == vec3(0.0f)) {
            ++degenerate;
            continue;
        }
        const dvec3 h_d = glm::normalize(dvec3(h));
        back_facing += glm::dot(wo_d, h_d) < 0.0 || h.z < 0.0f;
        const double reference = ggx::vndf(wo_d, h_d, a) / (4.0 * glm::dot(wo_d, h_d));
        const float pdf = pdf_ggx_vndf_reflection(wo, h, c.alpha);
        ASSERT_TRUE(std::isfinite(pdf) && pdf >= 0.0f);
        if (reference > 0.0) worst_pdf = std::max(worst_pdf, std::abs(pdf / reference - 1.0));
        const dvec3 s = ggx::stretched_from_normal(h_d, a);
        observed[grid.cell_of(s.x, s.y, s.z)] += 1.0;
    }
    EXPECT_EQ(degenerate, 0) << "sample_ggx_vndf returned 0";
    EXPECT_EQ(back_facing, 0) << "visible normals facing away from wo";
    EXPECT_LT(worst_pdf, 1e-4) << "pdf_ggx_vndf_reflection against D_wo / (4 wo.h)";
    const dvec3 wo_s = ggx::stretched_from_normal(wo_d, a);  // where D_wo(h(s)) dw_h/dw_s peaks
    std::vector<double> expected = grid.integrate(
        [&](double x, double y, double z) {
            const dvec3 s(x, y, z);
            return ggx::vndf(wo_d, ggx::normal_from_stretched(s, a), a) * ggx::normal_per_stretched_solid_angle(s, a);
        },
        wo_s.x, wo_s.y, wo_s.z, 1e-4, 1e-10);
    double total = 0.0;
    for (double& e : expected) total += e, e *= SAMPLES;
    EXPECT_NEAR(total, 1.0, 1e-4) << "D_wo integrates to 1 (reference and quadrature)";
    char what[64];
    std::snprintf(what, sizeof what, "vndf alpha %.3g at %.1f deg", c.alpha, c.degrees);
    expect_pass(observed, expected, grid.res_cos, grid.res_phi, what);
    std::printf("[vndf] alpha %.3g at %.1f deg: int D_wo %.7f, worst pdf relative error %.2e\n", c.alpha, c.degrees,
                total, worst_pdf);
}

std::vector<VndfCase> vndf_cases() {
    std::vector<VndfCase> cases;
    for (float degrees : {0.0f, 45.0f, 80.0f, 85.0f, 89.0f, 89.9f})
        for (float alpha : {1e-3f, 1e-2f, 0.1f, 0.5f, 1.0f}) cases.push_back({degrees, alpha});
    return cases;
}

INSTANTIATE_TEST_SUITE_P(Cases, VndfChiSquare, ::testing::ValuesIn(vndf_cases()),
                         [](const ::testing::TestParamInfo<VndfCase>& info) {
                             char name[32];  // deg899_alpha0001: 89.9 degrees, alpha 0.001
                             std::snprintf(name, sizeof name, "deg%d_alpha%04d", int(info.param.degrees * 10 + 0.5f),
                                           int(info.param.alpha * 1000 + 0.5f));
                             return std::string(name);
                         });

// ---- Finite at the edges of u -------------------------------------------------------------------------------
// Every warp, for u components at U_EDGES (0, 1 - 2^-24, ...): finite outputs in their domain, and pdfs
// finite and >= 0 (0 allowed: the caller rejects such samples). GGX over alpha and wo down to the horizon.
TEST(SamplingExtremes, EveryWarpIsFiniteAtTheEdgesOfU) {
    long checked = 0, failures = 0;
    auto check = [&](bool ok, const char* what, vec2 u) {
        ++checked;
        if (!ok && ++failures <= 10) ADD_FAILURE() << what << " at u = (" << u.x << ", " << u.y << ")";
    };
    const float cosines[] = {1.0f, 0.5f, 0.0174524f, 0.00174533f, 1e-4f, 1e-7f, 0.0f};  // 0..89.9 deg, horizon
    for (float a : U_EDGES)
        for (float b : U_EDGES) {
            const vec2 u(a, b);
            const vec2 d = sample_concentric_disk(u);
            check(finite(d) && dot(d, d) <= 1.0f + 1e-6f, "concentric disk", u);
            const vec3 w = sample_cosine_hemisphere(u);
            const float pdf_w = pdf_cosine_hemisphere(w.z);
            check(finite(w) && w.z >= 0.0f && std::abs(length(w) - 1.0f) < 1e-5f, "cosine hemisphere", u);
            check(std::isfinite(pdf_w) && pdf_w >= 0.0f, "cosine hemisphere pdf", u);
            const vec2 t = sample_uniform_triangle(u);
            check(finite(t) && t.x >= 0.0f && t.y >= 0.0f && t.x + t.y <= 1.0f, "uniform triangle", u);
            for (float radius : {1e-6f, 0.5f, 1.5f, 1e4f}) {
                const vec2 o = sample_gaussian_filter(u, radius);
                check(finite(o) && std::abs(o.x) <= radius && std::abs(o.y) <= radius, "gaussian filter", u);
            }
            for (float alpha : {1e-3f, 1e-2f, 0.5f, 1.0f})
                for (float cos_o : cosines) {
                    const float sin_o = std::sqrt(1.0f - cos_o * cos_o);
                    const vec3 wo(0.6f * sin_o, 0.8f * sin_o, cos_o);
                    const vec3 h = sample_ggx_vndf(wo, alpha, u);
                    check(finite(h) && (h == vec3(0.0f) || (std::abs(length(h) - 1.0f) < 1e-5f && h.z >= 0.0f)),
                          "ggx vndf", u);
                    const float pdf = pdf_ggx_vndf_reflection(wo, h, alpha);
                    check(std::isfinite(pdf) && pdf >= 0.0f && (cos_o > 0.0f || pdf == 0.0f), "ggx vndf pdf", u);
                    const float v_cos = ggx_v_cos(cos_o, std::max(h.z, 0.0f), alpha);
                    check(std::isfinite(v_cos) && v_cos >= 0.0f && v_cos <= 0.5f / alpha * 1.0001f, "ggx V cos", u);
                }
        }
    std::printf("[edges] %ld checks, %ld failures\n", checked, failures);
    EXPECT_EQ(failures, 0);
}

}  // namespace
