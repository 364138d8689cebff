// The BSDF of shaders/lib/bsdf/bsdf.glsl at its extremes: roughness 0, 1e-4, 1e-2, 0.1, 0.5 and 1, white GGX
// conductor (metallic 1, F = 1) and white dielectric (metallic 0, specular 1, ior 1.5), outgoing directions
// from the normal to 89.9 degrees. (a) every sample finite, down to u = 0 and u = 1 - 2^-24; (b) white
// furnace: the mean sample weight never exceeds 1 beyond 4 standard errors; (c) the GGX lobe's directional
// albedo E(mu, alpha) from the renderer's sampling, from eval / pdf, by quadrature of eval_bsdf over the
// hemisphere, and from the double-precision reference of the albedo table, all agree.
//
// Roughness is perceptual: make_bsdf_params uses alpha = max(roughness^2, BSDF_MIN_ALPHA = 1e-3), so
// roughness 0, 1e-4 and 1e-2 (alpha 0, 1e-8, 1e-4) all give the shader alpha 1e-3: a sharp lobe, never a
// delta. The tests use p.alpha, the value the shader uses, everywhere.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

// The single-scattering lobes these extremes are modelled on (the reference albedos, the double-precision pdf): the
// metal's multiple-scattering lobe has its own tests (tests/unit/bsdf/test_bsdf_ggx_multiscatter.cpp).
#define BSDF_HAS_GGX_MULTISCATTER false
#include "bsdf_test_setup.h"
#include "stability_cpu.h"

namespace {
using namespace fh::test;
using glm::dvec3;
namespace st = fh::test::stability;
namespace ggx = fh::test::stability::ggx;

const float ROUGHNESSES[] = {0.0f, 1e-4f, 1e-2f, 0.1f, 0.5f, 1.0f};
const float DEGREES[] = {0.0f, 30.0f, 60.0f, 80.0f, 85.0f, 89.0f, 89.9f};

BsdfParams white_metal(float roughness) { return make_bsdf_params(make_material(vec3(1.0f), 1.0f, roughness)); }
BsdfParams white_dielectric(float roughness) { return make_bsdf_params(make_material(vec3(1.0f), 0.0f, roughness)); }

TEST(MicrofacetExtremes, AlphaIsRoughnessSquaredClampedTo1e3) {
    EXPECT_EQ(BSDF_MIN_ALPHA, 1e-3f);
    for (float r : ROUGHNESSES) {
        const float expected = std::max(r * r, 1e-3f);
        EXPECT_EQ(white_metal(r).alpha, expected) << "roughness " << r;
        EXPECT_EQ(white_dielectric(r).alpha, expected) << "roughness " << r;
        std::printf("[alpha] roughness %-6g -> alpha %.6g%s\n", r, white_metal(r).alpha,
                    r * r < 1e-3f ? " (clamped)" : "");
    }
}

// ---- (a) Finite at the edges of u ---------------------------------------------------------------------------
TEST(MicrofacetExtremes, EverySampleIsFiniteAtTheEdgesOfU) {
    long checked = 0, valid = 0, failures = 0;
    double largest_weight = 0.0;
    auto fail = [&](bool bad, const char* what, float r, float degrees, vec3 u) {
        if (bad && ++failures <= 10)
            ADD_FAILURE() << what << ": roughness " << r << " at " << degrees << " deg, u = (" << u.x << ", " << u.y
                          << ", " << u.z << ")";
        return bad;
    };
    st::Rng rng(1);
    for (int metal = 0; metal < 2; ++metal)
        for (float r : ROUGHNESSES)
            for (float degrees : DEGREES) {
                const BsdfParams p = metal ? white_metal(r) : white_dielectric(r);
                const vec3 wo = st::direction_at(degrees);
                std::vector<vec3> us;
                for (float a : st::U_EDGES)
                    for (float b : st::U_EDGES)
                        for (float c : st::U_EDGES) us.push_back(vec3(a, b, c));
                for (int i = 0; i < 2000; ++i) us.push_back(vec3(rng.uniform(), rng.uniform(), rng.uniform()));
                for (vec3 u : us) {
                    const BsdfSample s = sample_bsdf(p, wo, u);
                    ++checked;
                    if (fail(!(st::finite(s.weight) && std::isfinite(s.pdf) && st::finite(s.wi) && s.pdf >= 0.0f),
                             "non-finite sample", r, degrees, u) ||
                        s.valid == 0u)
                        continue;
                    ++valid;
                    fail(!(s.pdf > 0.0f && s.wi.z > 0.0f && std::abs(length(s.wi) - 1.0f) < 1e-5f), "bad direction",
                         r, degrees, u);
                    fail(!(s.weight.x >= 0.0f && s.weight.y >= 0.0f && s.weight.z >= 0.0f), "negative weight", r,
                         degrees, u);
                    const float pdf = pdf_bsdf(p, wo, s.wi);
                    const vec3 f = eval_bsdf(p, wo, s.wi);
                    fail(!(std::isfinite(pdf) && st::finite(f) && std::abs(pdf - s.pdf) <= 1e-3f * s.pdf),
                         "pdf/eval", r, degrees, u);
                    largest_weight = std::max(largest_weight, double(s.weight.x));
                }
            }
    std::printf("[finite] %ld samples (%ld valid), %ld failures, largest weight %.4f\n", checked, valid, failures,
                largest_weight);
    EXPECT_EQ(failures, 0);
}

// ---- (b) White furnace -------------------------------------------------------------------------------------
struct Estimate {
    double mean = 0.0, std_error = 0.0, ratio_mean = 0.0, ratio_std_error = 0.0, invalid = 0.0;
};

// Mean of sample_bsdf's weight (invalid samples weigh 0), and of eval_bsdf / pdf_bsdf recomputed through
// the public functions at the sampled wi, with their standard errors. White materials: channel x suffices.
Estimate estimate_albedo(const BsdfParams& p, vec3 wo, int n, uint32_t seed) {
    st::Rng rng(seed);
    double sum = 0.0, sum2 = 0.0, ratio = 0.0, ratio2 = 0.0;
    long invalid = 0;
    for (int i = 0; i < n; ++i) {
        const BsdfSample s = sample_bsdf(p, wo, vec3(rng.uniform(), rng.uniform(), rng.uniform()));
        if (s.valid == 0u) {
            ++invalid;
            continue;
        }
        const double w = s.weight.x, q = double(eval_bsdf(p, wo, s.wi).x) / double(pdf_bsdf(p, wo, s.wi));
        sum += w;
        sum2 += w * w;
        ratio += q;
        ratio2 += q * q;
    }
    Estimate e;
    e.mean = sum / n;
    e.std_error = std::sqrt(std::max(sum2 / n - e.mean * e.mean, 0.0) / n);
    e.ratio_mean = ratio / n;
    e.ratio_std_error = std::sqrt(std::max(ratio2 / n - e.ratio_mean * e.ratio_mean, 0.0) / n);
    e.invalid = double(invalid) / n;
    return e;
}

constexpr int FURNACE_SAMPLES = 200000;

TEST(MicrofacetExtremes, WhiteFurnaceNeverGainsEnergy) {
    double worst_excess = -1.0;  // largest (mean - 1) / standard error
    for (int metal = 0; metal < 2; ++metal)
        for (float r : ROUGHNESSES)
            for (float degrees : DEGREES) {
                const BsdfParams p = metal ? white_metal(r) : white_dielectric(r);
                const Estimate e = estimate_albedo(p, st::direction_at(degrees), FURNACE_SAMPLES,
                                                   uint32_t(100 + 10 * metal + 1000 * degrees + 1e5 * r));
                EXPECT_LE(e.mean, 1.0 + 4.0 * e.std_error)
                    << (metal ? "metal" : "dielectric") << " roughness " << r << " at " << degrees << " deg";
                if (e.std_error > 0.0) worst_excess = std::max(worst_excess, (e.mean - 1.0) / e.std_error);
                std::printf("[furnace] %-10s roughness %-6g (alpha %.4g) at %4.1f deg: albedo %.5f +- %.5f "
                            "(invalid %.5f)\n",
                            metal ? "metal" : "dielectric", r, p.alpha, degrees, e.mean, e.std_error, e.invalid);
            }
    std::printf("[furnace] largest (albedo - 1) / standard error: %.2f (limit 4)\n", worst_excess);
}

// ---- (c) The GGX lobe's albedo by sampling, eval / pdf and quadrature --------------------------------------
// E by quadrature of eval_bsdf (the shader's f cos, F = 1) over the hemisphere in double, written over the
// stretched half vector s (stability_cpu.h): wi = reflect(wo, h(s)), dw_i = 4 (wo.h) (dw_h / dw_s) dw_s. In s
// the lobe of alpha 1e-3 is as smooth as that of alpha 1 (D(h) dw_h/dw_s = |M s| / pi), so the quadrature
// resolves it and no small-alpha limit has to stand in for it; f cos goes to 0 continuously at the horizon.
double albedo_by_quadrature(const BsdfParams& p, vec3 wo) {
    const dvec3 wo_d(wo);
    const double a = p.alpha;
    HemisphereGrid grid;
    grid.res_cos = 16;
    grid.res_phi = 32;
    const std::vector<double> cells = st::integrate_cut_cells(
        grid,
        [&](double cos_theta, double phi, bool& valid) {
            const dvec3 s = st::grid_direction(cos_theta, phi), h = ggx::normal_from_stretched(s, a);
            const dvec3 wi = ggx::reflect(wo_d, h);
            valid = wi.z > 0.0 && glm::dot(wo_d, h) > 0.0;
            if (!valid) return 0.0;
            const float f_cos = eval_bsdf(p, wo, vec3(float(wi.x), float(wi.y), float(wi.z))).x;
            return double(f_cos) * 4.0 * glm::dot(wo_d, h) * ggx::normal_per_stretched_solid_angle(s, a);
        },
        1e-10, 6);  // f cos is a float: Simpson is not asked to resolve its rounding noise
    return sum(cells);
}

TEST(MicrofacetExtremes, GgxAlbedoMatchesQuadrature) {
    const int n = 400000;
    double worst = 0.0;  // largest |sampled - quadrature| as a fraction of its tolerance
    std::printf("[albedo] roughness alpha   deg   E quadrature  E reference  E sampled +- SE        E eval/pdf  "
                "|sampled - quad| / tolerance\n");
    for (float r : ROUGHNESSES)
        for (float degrees : DEGREES) {
            const BsdfParams p = white_metal(r);
            const vec3 wo = st::direction_at(degrees);
            const double e_quad = albedo_by_quadrature(p, wo);
            const ggx_albedo::Albedo ref = ggx_albedo::albedo(double(wo.z), double(p.alpha));
            const double e_ref = ref.a + ref.b;  // F = 1: A + B
            const Estimate e = estimate_albedo(p, wo, n, uint32_t(7 + 1000 * degrees + 1e5 * r));
            // Quadrature uncertainty: the two independent quadratures' disagreement plus the reference's own
            // accuracy (3e-5, ggx_albedo_reference.h); float f cos at grazing is in the former.
            const double quad_error = std::abs(e_quad - e_ref) + 3e-5;
            const double tolerance = 4.0 * e.std_error + quad_error;
            EXPECT_LT(std::abs(e_quad - e_ref), 2e-4) << "quadratures disagree, roughness " << r << " at " << degrees;
            EXPECT_NEAR(e.mean, e_quad, tolerance) << "sampled, roughness " << r << " at " << degrees;
            EXPECT_NEAR(e.ratio_mean, e_quad, 4.0 * e.ratio_std_error + quad_error)
                << "eval/pdf, roughness " << r << " at " << degrees;
            if (p.alpha <= 1e-3f && degrees <= 85.0f) {
                // Smooth-mirror limit: E -> 1 as alpha tan(theta) -> 0 (F = 1); here 1 - E = O((alpha tan)^2) < 2e-4.
                EXPECT_GT(e_quad, 1.0 - 1e-3) << "mirror limit, roughness " << r << " at " << degrees;
                EXPECT_GT(e.mean, 1.0 - 1e-3 - 4.0 * e.std_error)
                    << "mirror limit, roughness " << r << " at " << degrees;
            }
            worst = std::max(worst, std::abs(e.mean - e_quad) / tolerance);
            std::printf("[albedo] %-8g %-7.4g %4.1f  %.6f      %.6f     %.6f +- %.6f  %.6f    %.2f\n", r, p.alpha,
                        degrees,
                        e_quad, e_ref, e.mean, e.std_error, e.ratio_mean, std::abs(e.mean - e_quad) / tolerance);
        }
    std::printf("[albedo] largest |sampled - quadrature| / tolerance: %.2f (tolerance 4 SE + quadrature error)\n",
                worst);
}

}  // namespace
