// The BSDF test executables' shared setup: shaders/lib/bsdf/bsdf.glsl compiled as C++ (in fh::glsl) and the
// materials, directions and quadrature the tests share. Include once per executable (the .glsl functions
// are not inline).
#pragma once
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "chi_square.h"
#include "shared/layout.h"
#include "lib/core/cpp_compat.h"
namespace fh::glsl {
#include "lib/bsdf/bsdf.glsl"
}  // namespace fh::glsl

namespace fh::test {
using namespace fh::glsl;

inline const float ONE_MINUS_EPS = 1.0f - 1.0f / 16777216.0f;  // largest float the RNG returns
inline const float ROUGHNESSES[] = {0.05f, 0.2f, 0.5f, 1.0f};
inline const float INCIDENCES[] = {0.0f, 30.0f, 60.0f, 80.0f, 89.0f};  // degrees
enum Kind { DIELECTRIC, METAL, HALF_METAL, KIND_COUNT };
inline const char* const KIND_NAMES[] = {"dielectric", "metal", "halfmetal"};

inline fh::gpu::Material make_material(vec3 base, float metallic, float roughness, float specular = 1.0f,
                                       vec3 specular_color = vec3(1.0f), float ior = 1.5f) {
    fh::gpu::Material m{};
    m.base_color = vec4(base, 1.0f);
    m.specular_color = vec4(specular_color, specular);
    m.metallic = metallic;
    m.roughness = roughness;
    m.ior = ior;
    m.base_color_texture = m.metallic_roughness_texture = m.normal_texture = m.emissive_texture = 0xffffffffu;
    m.specular_texture = m.specular_color_texture = 0xffffffffu;
    return m;
}

inline BsdfParams make_case(Kind kind, float roughness) {
    switch (kind) {
        case DIELECTRIC: return make_bsdf_params(make_material(vec3(0.7f, 0.5f, 0.3f), 0.0f, roughness));
        case METAL: return make_bsdf_params(make_material(vec3(0.9f, 0.6f, 0.4f), 1.0f, roughness));
        default: return make_bsdf_params(make_material(vec3(0.5f, 0.8f, 0.6f), 0.5f, roughness));
    }
}

// The bases the layer tests (anisotropy, iridescence) put their layer on, roughness given.
enum LayerBase { DIELECTRIC_BASE, METAL_BASE, THIN_GLASS_BASE, VOLUME_GLASS_BASE, COATED_BASE, HALF_METAL_BASE };
inline const char* const LAYER_BASE_NAMES[] = {"dielectric", "metal", "thinglass", "volumeglass", "coated", "halfmetal"};

inline BsdfParams make_layer_base(LayerBase base, float roughness) {
    switch (base) {
        case DIELECTRIC_BASE: return make_bsdf_params(make_material(vec3(0.7f, 0.5f, 0.3f), 0.0f, roughness));
        case METAL_BASE: return make_bsdf_params(make_material(vec3(0.9f, 0.6f, 0.4f), 1.0f, roughness));
        case THIN_GLASS_BASE:
            return with_transmission(make_bsdf_params(make_material(vec3(0.9f), 0.0f, roughness)), 0.8f, 1.5f, 1u);
        case VOLUME_GLASS_BASE:
            return with_transmission(make_bsdf_params(make_material(vec3(0.9f), 0.0f, roughness)), 1.0f, 1.5f, 0u);
        case COATED_BASE:
            return with_clearcoat(make_bsdf_params(make_material(vec3(0.8f, 0.6f, 0.4f), 0.3f, roughness)), 0.6f, 0.1f,
                                  vec3(0.0f, 0.0f, 1.0f));
        default: return make_bsdf_params(make_material(vec3(0.5f, 0.8f, 0.6f), 0.5f, roughness));
    }
}

// `w` turned by `angle` radians about the normal (z).
inline vec3 turn_about_normal(vec3 w, float angle) {
    return vec3(w.x * std::cos(angle) - w.y * std::sin(angle), w.x * std::sin(angle) + w.y * std::cos(angle), w.z);
}

// Outgoing direction at `degrees` from the normal, at an azimuth off the histogram's cell boundaries.
inline vec3 outgoing(float degrees) {
    const float t = glm::radians(degrees), phi = 0.7f;
    return vec3(std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t));
}

inline bool finite(vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Integrals of a density over the grid cells, split at the mirror direction where the GGX lobe peaks.
template <class D>
std::vector<double> integrate_cells(const HemisphereGrid& grid, vec3 wo, const D& density) {
    return grid.integrate(
        [&](double x, double y, double z) { return density(vec3(float(x), float(y), float(z))); }, -wo.x, -wo.y,
        wo.z, 1e-5, 1e-11);
}

inline double sum(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

// Quadrature of a directional function over the hemisphere (32 x 64 cells, split at the mirror direction).
template <class D>
double integrate_hemisphere(vec3 wo, const D& density) {
    HemisphereGrid grid;
    grid.res_cos = 32;
    grid.res_phi = 64;
    return sum(integrate_cells(grid, wo, density));
}

// sample_bsdf and eval_bsdf give the same bits for `a` and `b` (a layer of weight 0 is no layer at all), over n
// random outgoing directions up to `max_degrees` and random numbers from `seed`.
inline void expect_identical_bsdfs(const BsdfParams& a, const BsdfParams& b, uint32_t seed, float max_degrees, int n = 1000) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (int i = 0; i < n; ++i) {
        const vec3 wo = outgoing(max_degrees * uniform(rng));
        const vec3 u(uniform(rng), uniform(rng), uniform(rng));
        const BsdfSample x = sample_bsdf(a, wo, u), y = sample_bsdf(b, wo, u);
        ASSERT_EQ(x.valid, y.valid);
        ASSERT_EQ(x.wi, y.wi);
        ASSERT_EQ(x.pdf, y.pdf);
        ASSERT_EQ(x.weight, y.weight);
        ASSERT_EQ(eval_bsdf(a, wo, x.wi), eval_bsdf(b, wo, x.wi));
    }
}

// The fraction of the energy from wo that `p` keeps: reflected + eta^2 x transmitted (the BTDF carries radiance's 1 / eta^2,
// so eta^2 undoes it; thin walls do not bend light and are not scaled). Monte Carlo with n samples.
struct Albedo {
    double mean = 0.0;
    double standard_error = 0.0;
    double transmitted = 0.0;  // fraction of samples that went through
};

inline Albedo estimate_albedo(const BsdfParams& p, vec3 wo, int n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    double sum = 0.0, sum2 = 0.0, through = 0.0;
    const float scale = p.glass.thin_walled != 0u ? 1.0f : p.glass.eta * p.glass.eta;
    for (int i = 0; i < n; ++i) {
        const BsdfSample s = sample_bsdf(p, wo, vec3(uniform(rng), uniform(rng), uniform(rng)));
        if (s.valid == 0u) continue;
        EXPECT_TRUE(finite(s.weight) && std::isfinite(s.pdf));
        const double w = s.weight.y * (s.wi.z < 0.0f ? scale : 1.0f);
        sum += w;
        sum2 += w * w;
        through += s.wi.z < 0.0f;
    }
    Albedo a;
    a.mean = sum / n;
    a.standard_error = std::sqrt(std::max(sum2 / n - a.mean * a.mean, 0.0) / n);
    a.transmitted = through / n;
    return a;
}

// f(wo, wi) = f(wi, wo) (f = eval_bsdf / cos theta_i) for n random pairs of directions above the surface, from `seed`.
inline void expect_reciprocal_reflection(const BsdfParams& p, uint32_t seed, int n, const char* what) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (int i = 0; i < n; ++i) {
        const vec3 wo = outgoing(89.0f * uniform(rng));
        const vec3 up = outgoing(89.0f * uniform(rng));
        const vec3 wi = turn_about_normal(up, 6.2831853f * uniform(rng));
        const vec3 a = eval_bsdf(p, wo, wi) / wi.z;
        const vec3 b = eval_bsdf(p, wi, wo) / wo.z;
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(a[c], b[c], 1e-4f * std::max(a[c], 1.0f)) << what;
    }
}

// Chi-square of sample_bsdf against pdf_bsdf over both hemispheres (a 32 x 64 grid each; n samples from `seed`),
// with the checks every such test makes: each sample's pdf equals pdf_bsdf, the pdf integrates to at most 1 and
// the invalid samples make up the rest. The quadrature splits cells at the mirror direction above and at
// `peak_below` (|z|) below. Returns the test's result and the pdf's integral, to print.
struct TwoSidedChiSquare {
    ChiSquareResult result;
    double pdf_integral = 0.0;
};

inline TwoSidedChiSquare check_sampling_both_hemispheres(const BsdfParams& p, vec3 wo, vec3 peak_below, int n,
                                                         uint32_t seed) {
    HemisphereGrid grid;
    grid.res_cos = 32;
    grid.res_phi = 64;
    std::vector<double> observed(2 * grid.cells(), 0.0);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    int pdf_mismatches = 0;
    double invalid = 0.0;
    for (int i = 0; i < n; ++i) {
        const BsdfSample s = sample_bsdf(p, wo, vec3(uniform(rng), uniform(rng), uniform(rng)));
        if (s.valid == 0u) {
            invalid += 1.0;
            continue;
        }
        EXPECT_TRUE(finite(s.weight) && std::isfinite(s.pdf) && s.pdf > 0.0f);
        const float pdf = pdf_bsdf(p, wo, s.wi);
        pdf_mismatches += std::abs(pdf - s.pdf) > 1e-3f * pdf;
        observed[(s.wi.z < 0.0f ? grid.cells() : 0) + grid.cell_of(s.wi.x, s.wi.y, std::abs(s.wi.z))] += 1.0;
    }
    EXPECT_EQ(pdf_mismatches, 0) << "sample.pdf != pdf_bsdf(wi)";
    std::vector<double> expected = integrate_cells(grid, wo, [&](vec3 wi) { return pdf_bsdf(p, wo, wi); });
    const std::vector<double> below = grid.integrate(
        [&](double x, double y, double z) { return pdf_bsdf(p, wo, vec3(float(x), float(y), -float(z))); },
        peak_below.x, peak_below.y, peak_below.z, 1e-5, 1e-11);
    expected.insert(expected.end(), below.begin(), below.end());
    TwoSidedChiSquare out;
    out.pdf_integral = sum(expected);
    EXPECT_LT(out.pdf_integral, 1.0 + 1e-3) << "pdf_bsdf integrates to more than 1";
    EXPECT_NEAR(invalid / n, 1.0 - out.pdf_integral,
                5.0 * std::sqrt(std::max(1.0 - out.pdf_integral, 1.0 / n) / n) + 2e-3);
    for (double& e : expected) e *= n;
    out.result = chi_square_test(observed, expected);
    EXPECT_TRUE(out.result.error.empty()) << out.result.error;
    EXPECT_GT(out.result.p_value, corrected_significance(UNIT_CHI_SQUARE_TESTS))
        << "chi2 = " << out.result.statistic << ", dof = " << out.result.dof;
    return out;
}

}  // namespace fh::test
