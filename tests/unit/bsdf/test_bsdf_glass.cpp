// The glass lobe (shaders/lib/bsdf/dielectric.glsl) inside the full BSDF (bsdf.glsl), on the CPU: Fresnel and total
// internal reflection, smooth-glass limits (1 - F through an interface, 1 - F through a thin wall), reciprocity
// (with the radiance scaling 1 / eta^2), the white furnace over the whole sphere, and chi-square tests of
// sample_bsdf against pdf_bsdf on both hemispheres.
#include <gtest/gtest.h>

#include <random>

#include "bsdf_test_setup.h"

namespace {
using namespace fh::test;

const float IOR = 1.5f;
const float F_NORMAL = 0.04f;  // ((1.5 - 1) / (1.5 + 1))^2

// A glass material: all transmission (or `transmission`), white unless `tint`.
BsdfParams make_glass(float roughness, float eta, bool thin, float transmission = 1.0f, float metallic = 0.0f,
                      vec3 tint = vec3(1.0f)) {
    return with_transmission(make_bsdf_params(make_material(tint, metallic, roughness, 1.0f, vec3(1.0f), IOR)),
                             transmission, eta, thin ? 1u : 0u);
}

vec3 uniform_sphere(float u1, float u2) {
    const float z = 1.0f - 2.0f * u1, r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 6.2831853f * u2;
    return vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// The kinds of glass the furnace and chi-square tests try: glass seen from outside, from inside, thin-walled,
// and half glass mixed with metal and Lambert.
const char* const GLASS_KIND_NAMES[] = {"outside", "inside", "thin", "mixed"};


TEST(Glass, FresnelMatchesTheTextbook) {
    EXPECT_NEAR(fresnel_dielectric(1.0f, IOR), F_NORMAL, 1e-6f);
    EXPECT_NEAR(fresnel_dielectric(1.0f, 1.0f / IOR), F_NORMAL, 1e-6f);  // the same from inside
    EXPECT_FLOAT_EQ(fresnel_dielectric(0.0f, IOR), 1.0f);                // grazing
    // Brewster's angle: the parallel polarisation vanishes, F = r_perp^2 / 2.
    const float brewster = std::atan(IOR);
    const float cos_t = std::cos(std::asin(std::sin(brewster) / IOR));
    const float r_perp = (std::cos(brewster) - IOR * cos_t) / (std::cos(brewster) + IOR * cos_t);
    EXPECT_NEAR(fresnel_dielectric(std::cos(brewster), IOR), 0.5f * r_perp * r_perp, 1e-6f);
    // Reciprocal: F seen from either side of the same pair of directions.
    for (float deg : {10.0f, 30.0f, 40.0f}) {
        const float ci = std::cos(glm::radians(deg));
        const float ct = std::sqrt(1.0f - (1.0f - ci * ci) / (IOR * IOR));
        EXPECT_NEAR(fresnel_dielectric(ci, IOR), fresnel_dielectric(ct, 1.0f / IOR), 1e-6f) << deg;
    }
}

TEST(Glass, TotalInternalReflectionPastTheCriticalAngle) {
    const float critical = std::asin(1.0f / IOR);  // 41.8 degrees
    EXPECT_FLOAT_EQ(fresnel_dielectric(std::cos(critical + 0.01f), 1.0f / IOR), 1.0f);
    EXPECT_LT(fresnel_dielectric(std::cos(critical - 0.01f), 1.0f / IOR), 1.0f);
    // Smooth glass seen from inside at 60 degrees: every sample reflects, and keeps all the energy.
    const BsdfParams p = make_glass(0.0f, 1.0f / IOR, false);
    const Albedo a = estimate_albedo(p, outgoing(60.0f), 100000, 1);
    EXPECT_EQ(a.transmitted, 0.0);
    EXPECT_NEAR(a.mean, 1.0, 2e-3);
    // Below the critical angle (30 degrees) light leaves: 1 - F of it.
    const Albedo b = estimate_albedo(p, outgoing(30.0f), 200000, 2);
    const float cos_i = std::cos(glm::radians(30.0f));
    EXPECT_NEAR(b.transmitted, 1.0 - fresnel_dielectric(cos_i, 1.0f / IOR), 5e-3);
}

TEST(Glass, SmoothInterfacePassesOneMinusFresnel) {
    // Normal incidence from outside: 1 - F = 0.96 goes through, carrying radiance x 1 / eta^2.
    const BsdfParams p = make_glass(0.0f, IOR, false);
    const vec3 wo(0.0f, 0.0f, 1.0f);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    const int n = 200000;
    double through = 0.0, weight_through = 0.0, bent = 0.0;
    for (int i = 0; i < n; ++i) {
        const BsdfSample s = sample_bsdf(p, wo, vec3(uniform(rng), uniform(rng), uniform(rng)));
        if (s.valid == 0u || s.wi.z >= 0.0f) continue;
        through += 1.0;
        weight_through += s.weight.y;
        bent += std::abs(s.wi.x) + std::abs(s.wi.y) > 1e-2f;  // GGX's tail at alpha = 1e-3
    }
    EXPECT_LT(bent / through, 0.02) << "smooth glass bends a normal ray";
    EXPECT_NEAR(through / n, 1.0 - F_NORMAL, 3.0 * std::sqrt(F_NORMAL * (1 - F_NORMAL) / n) + 1e-4);
    EXPECT_NEAR(weight_through / through, 1.0 / (IOR * IOR), 2e-3) << "radiance scaling 1 / eta^2";
}

TEST(Glass, ThinWallPassesOneMinusFresnelUnbent) {
    const BsdfParams p = make_glass(0.0f, IOR, true);
    for (float deg : {0.0f, 45.0f}) {
        const vec3 wo = outgoing(deg);
        const Albedo a = estimate_albedo(p, wo, 200000, 4);
        const double f = fresnel_dielectric(std::cos(glm::radians(deg)), IOR);
        EXPECT_NEAR(a.transmitted, 1.0 - f, 4e-3) << deg;
        EXPECT_NEAR(a.mean, 1.0, 3e-3) << deg;  // white: what is not reflected passes
        const BsdfSample s = sample_bsdf(p, wo, vec3(0.99f, 0.3f, 0.6f));  // u.x > F: transmits
        ASSERT_EQ(s.valid, 1u);
        EXPECT_NEAR(s.wi.x, -wo.x, 1e-2f);  // straight through
        EXPECT_NEAR(s.wi.z, -wo.z, 1e-2f);
    }
}

TEST(Glass, TintAndTransmissionFactorScaleWhatPasses) {
    const vec3 wo(0.0f, 0.0f, 1.0f);
    const BsdfParams tinted = make_glass(0.0f, IOR, true, 1.0f, 0.0f, vec3(0.5f, 0.25f, 1.0f));
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (int i = 0; i < 1000; ++i) {
        const BsdfSample s = sample_bsdf(tinted, wo, vec3(uniform(rng), uniform(rng), uniform(rng)));
        if (s.valid == 0u || s.wi.z >= 0.0f) continue;
        EXPECT_NEAR(s.weight.x / s.weight.z, 0.5f, 1e-4f);
        EXPECT_NEAR(s.weight.y / s.weight.z, 0.25f, 1e-4f);
    }
    // transmission 0.3 over a white Lambert base: 0.3 (1 - F) of the energy passes.
    const BsdfParams part = make_glass(0.3f, IOR, true, 0.3f);
    const Albedo a = estimate_albedo(part, wo, 400000, 6);
    const double transmitted_energy = 0.3 * (1.0 - fresnel_dielectric(1.0f, IOR));
    double through_energy = 0.0;
    std::mt19937 rng2(7);
    const int n = 400000;
    for (int i = 0; i < n; ++i) {
        const BsdfSample s = sample_bsdf(part, wo, vec3(uniform(rng2), uniform(rng2), uniform(rng2)));
        if (s.valid != 0u && s.wi.z < 0.0f) through_energy += s.weight.y;
    }
    // Rough (0.3) glass loses a little to single scattering; never more than it should pass.
    EXPECT_LT(through_energy / n, transmitted_energy + 3e-3);
    EXPECT_GT(through_energy / n, 0.95 * transmitted_energy);
    EXPECT_LT(a.mean, 1.0 + 4.0 * a.standard_error);
}

// Generalised reciprocity of the radiance BTDF (Veach 1997 sec. 5.2): f(wo, wi) / n_o^2 = f(wi, wo) / n_i^2,
// n the refractive index on each direction's side; reflection and thin walls are plainly symmetric.
TEST(Glass, IsReciprocal) {
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (float roughness : {0.2f, 0.5f, 1.0f})
        for (bool thin : {false, true})
            for (int i = 0; i < 2000; ++i) {
                const vec3 wo = uniform_sphere(uniform(rng), uniform(rng));
                const vec3 wi = uniform_sphere(uniform(rng), uniform(rng));
                if (std::abs(wo.z) < 0.05f || std::abs(wi.z) < 0.05f) continue;
                // Local frames put the viewer at +z: flip both directions when wo is below.
                const vec3 a_wo = wo.z > 0.0f ? wo : -wo, a_wi = wo.z > 0.0f ? wi : -wi;
                const vec3 b_wo = wi.z > 0.0f ? wi : -wi, b_wi = wi.z > 0.0f ? wo : -wo;
                // Outside is +z of the original frame: eta = 1.5 looking from outside, 1 / 1.5 from inside.
                // (A thin wall has the same ior from both sides, as shade.comp passes it.)
                const float eta_a = wo.z > 0.0f || thin ? IOR : 1.0f / IOR, eta_b = wi.z > 0.0f || thin ? IOR : 1.0f / IOR;
                const BsdfParams pa = make_glass(roughness, eta_a, thin, 1.0f, 0.0f, vec3(0.8f, 0.6f, 0.4f));
                const BsdfParams pb = make_glass(roughness, eta_b, thin, 1.0f, 0.0f, vec3(0.8f, 0.6f, 0.4f));
                const vec3 fa = eval_bsdf(pa, a_wo, a_wi) / std::abs(a_wi.z);
                const vec3 fb = eval_bsdf(pb, b_wo, b_wi) / std::abs(b_wi.z);
                // f(wo, wi) / n_o^2 is symmetric, n_o the index on the viewer's side: 1.5 inside, 1 outside.
                const bool through = (a_wi.z < 0.0f);
                const float sa = through && !thin && wo.z < 0.0f ? 1.0f / (IOR * IOR) : 1.0f;
                const float sb = through && !thin && wi.z < 0.0f ? 1.0f / (IOR * IOR) : 1.0f;
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(fa[c] * sa, fb[c] * sb, 2e-3f * std::max(fa[c] * sa, 1.0f))
                        << "roughness " << roughness << " thin " << thin << " wo " << wo.x << "," << wo.y << ","
                        << wo.z << " wi " << wi.x << "," << wi.y << "," << wi.z;
            }
}

// White furnace over the whole sphere: no glass (in or out, thin or not, any roughness, down to grazing, mixed
// with metal and Lambert) returns more energy than it receives; glass alone, smooth or rough, keeps nearly all of it
// (the multiple-scattering lobe gives back what single scattering loses: up to 59% from inside at roughness 1).
TEST(Glass, WhiteFurnaceConservesEnergy) {
    uint32_t seed = 100;
    for (float roughness : {0.0f, 0.2f, 0.5f, 1.0f})
        for (float deg : INCIDENCES)
            for (int kind = 0; kind < 4; ++kind) {
                const BsdfParams p = kind == 0   ? make_glass(roughness, IOR, false)
                                     : kind == 1 ? make_glass(roughness, 1.0f / IOR, false)
                                     : kind == 2 ? make_glass(roughness, IOR, true)
                                                 : make_glass(roughness, IOR, false, 0.5f, 0.3f);
                const Albedo a = estimate_albedo(p, outgoing(deg), 50000, seed++);
                std::printf("[furnace] %-7s roughness %.1f at %2.0f deg keeps %.4f (+- %.4f)\n",
                            GLASS_KIND_NAMES[kind], roughness, deg, a.mean, a.standard_error);
                EXPECT_LT(a.mean, 1.0 + 4.0 * a.standard_error + 1e-3)
                    << "kind " << kind << " roughness " << roughness << " at " << deg << " deg";
                if (roughness == 0.0f && kind < 3 && deg < 80.0f)
                    EXPECT_GT(a.mean, 0.985) << "smooth glass loses energy: kind " << kind << " at " << deg;
                if (kind < 3)  // the mixed kind's metal is the spec's single-scattering GGX, which loses energy
                    EXPECT_GT(a.mean, 0.985 - 4.0 * a.standard_error)
                        << "glass loses energy: kind " << kind << " roughness " << roughness << " at " << deg;
            }
}

// The multiple-scattering lobe is sized for white glass; with KHR_materials_specular's factor and colour below 1
// (more light refracted, less reflected) and a white base, a white-green glass still never gains energy, at any
// roughness, from either side or thin-walled, and at high indices (2.4, diamond) too (dielectric.glsl,
// glass_multiscatter_tint, says why).
TEST(Glass, SpecularTintedGlassNeverGainsEnergy) {
    uint32_t seed = 900;
    for (float ior : {1.5f, 2.4f})
        for (float specular : {0.0f, 0.5f, 1.0f, 3.0f})  // 3: a specular colour brighter than white
            for (float roughness : {0.3f, 1.0f})
                for (float deg : {0.0f, 60.0f, 85.0f})
                    for (int kind = 0; kind < 3; ++kind) {
                        const fh::gpu::Material m = make_material(vec3(1.0f), 0.0f, roughness, std::min(specular, 1.0f),
                                                                  vec3(0.2f, std::max(specular, 1.0f), 0.5f), ior);
                        const float eta = kind == 1 ? 1.0f / ior : ior;
                        const BsdfParams p = with_transmission(make_bsdf_params(m), 1.0f, eta, kind == 2 ? 1u : 0u);
                        const Albedo a = estimate_albedo(p, outgoing(deg), 40000, seed++);
                        EXPECT_LT(a.mean, 1.0 + 4.0 * a.standard_error + 1e-3)
                            << GLASS_KIND_NAMES[kind] << " ior " << ior << " specular " << specular << " roughness "
                            << roughness << " at " << deg << " deg";
                    }
}

// ---- Chi-square over both hemispheres ------------------------------------------------------------------
struct GlassCase {
    int kind;  // 0 glass from outside, 1 from inside, 2 thin-walled, 3 half glass over metal and Lambert
    float roughness;
    float degrees;
};

BsdfParams make_glass_case(const GlassCase& c) {
    switch (c.kind) {
        case 0: return make_glass(c.roughness, IOR, false);
        case 1: return make_glass(c.roughness, 1.0f / IOR, false);
        case 2: return make_glass(c.roughness, IOR, true);
        default: return make_glass(c.roughness, IOR, false, 0.5f, 0.25f, vec3(0.7f, 0.5f, 0.3f));
    }
}

class GlassChiSquare : public ::testing::TestWithParam<GlassCase> {};

TEST_P(GlassChiSquare, SamplesFollowPdf) {
    const GlassCase c = GetParam();
    const BsdfParams p = make_glass_case(c);
    const vec3 wo = outgoing(c.degrees);
    // Peak below: the refracted direction (or, thin-walled, the straight-through one).
    vec3 peak(-wo.x, -wo.y, wo.z);
    if (p.glass.thin_walled == 0u) {
        const float sin2_t = (1.0f - wo.z * wo.z) / (p.glass.eta * p.glass.eta);
        if (sin2_t < 1.0f) peak = vec3(-wo.x / p.glass.eta, -wo.y / p.glass.eta, std::sqrt(1.0f - sin2_t));
    }
    const TwoSidedChiSquare r = check_sampling_both_hemispheres(
        p, wo, peak, 500000, 77 + 1000 * c.kind + int(c.degrees) + int(100 * c.roughness));
    std::printf("[chi2] glass %-7s roughness %.2f at %2.0f deg: chi2 %8.1f dof %5d p %.4f, int pdf %.6f\n",
                GLASS_KIND_NAMES[c.kind], c.roughness, c.degrees, r.result.statistic, r.result.dof, r.result.p_value,
                r.pdf_integral);
}

std::vector<GlassCase> glass_cases() {
    std::vector<GlassCase> cases;
    for (int k = 0; k < 4; ++k)
        for (float r : {0.1f, 0.4f, 1.0f})
            for (float d : {0.0f, 50.0f, 80.0f}) cases.push_back({k, r, d});
    return cases;
}

INSTANTIATE_TEST_SUITE_P(Cases, GlassChiSquare, ::testing::ValuesIn(glass_cases()),
                         [](const ::testing::TestParamInfo<GlassCase>& info) {
                             return std::string(GLASS_KIND_NAMES[info.param.kind]) + "_r" +
                                    std::to_string(int(info.param.roughness * 100)) + "_deg" +
                                    std::to_string(int(info.param.degrees));
                         });

}  // namespace
