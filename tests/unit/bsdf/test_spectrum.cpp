// The spectral path's tables and functions (shaders/lib/spectral/spectrum.glsl, spectral_table.glsl from
// tests/unit/bsdf/make_spectral_table.py) and dispersion (KHR_materials_dispersion) through the glass BSDF: the
// RGB -> spectrum basis is a partition of unity in [0, 1] that the film maps back to the same RGB, the wavelength
// sampler matches its pdf, the hero wavelength's estimator is unbiased, and a prism deviates each wavelength as Snell's
// law says with the extension's Cauchy index.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "bsdf_test_setup.h"
namespace fh::glsl {
#include "lib/spectral/spectrum.glsl"
}  // namespace fh::glsl

namespace {
using namespace fh::glsl;

const double STEP = SPECTRAL_LAMBDA_STEP;
const int NODES = SPECTRAL_NODE_COUNT;

double basis_at(int n, int c) { return SPECTRAL_TABLE[8 * n + c]; }
double film_at(int n, int c) { return SPECTRAL_TABLE[8 * n + 4 + c]; }

// The exact integral of the product of two functions linear between the nodes.
template <typename F, typename G>
double integrate_product(F f, G g) {
    double sum = 0.0;
    for (int n = 0; n + 1 < NODES; ++n)
        sum += STEP / 6.0 * (2.0 * f(n) * g(n) + f(n) * g(n + 1) + f(n + 1) * g(n) + 2.0 * f(n + 1) * g(n + 1));
    return sum;
}

double pdf_at(double lambda) { return pdf_visible_wavelength(float(lambda)); }

// Midpoint rule on [a, b] with n steps.
template <typename F>
double integrate(F f, double a, double b, int n = 200000) {
    const double h = (b - a) / n;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) sum += f(a + (i + 0.5) * h);
    return sum * h;
}

TEST(SpectralTable, BasisIsAPartitionOfUnityInZeroOne) {
    for (int n = 0; n < NODES; ++n) {
        EXPECT_NEAR(basis_at(n, 0) + basis_at(n, 1) + basis_at(n, 2), 1.0, 1e-6) << "node " << n;
        for (int c = 0; c < 3; ++c) {
            EXPECT_GE(basis_at(n, c), -1e-7) << "node " << n;
            EXPECT_LE(basis_at(n, c), 1.0 + 1e-7) << "node " << n;
        }
    }
}

TEST(SpectralTable, FilmReturnsEachPrimaryAndWhite) {
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(integrate_product([&](int n) { return film_at(n, c); }, [](int) { return 1.0; }), 1.0, 1e-6);
        for (int i = 0; i < 3; ++i)
            EXPECT_NEAR(integrate_product([&](int n) { return film_at(n, c); }, [&](int n) { return basis_at(n, i); }),
                        c == i ? 1.0 : 0.0, 1e-5)
                << "film channel " << c << ", basis " << i;
    }
}

// The film's weights are CIE 1931 matching functions under D65 seen through Rec.709's primaries: each channel peaks
// where that primary's dominant wavelength lies, and their luminance where ybar x D65 does (555 to 560 nm).
TEST(SpectralTable, FilmWeightsPeakWhereTheirPrimariesLie) {
    auto peak = [&](auto weight) {
        int best = 0;
        for (int n = 0; n < NODES; ++n)
            if (weight(n) > weight(best)) best = n;
        return SPECTRAL_LAMBDA_MIN + STEP * best;
    };
    const double red = peak([](int n) { return film_at(n, 0); });
    const double green = peak([](int n) { return film_at(n, 1); });
    const double blue = peak([](int n) { return film_at(n, 2); });
    const double luminance = peak([](int n) { return 0.2126 * film_at(n, 0) + 0.7152 * film_at(n, 1) + 0.0722 * film_at(n, 2); });
    std::printf("film peaks: R %.0f nm, G %.0f nm, B %.0f nm, luminance %.0f nm\n", red, green, blue, luminance);
    EXPECT_GE(red, 595.0);
    EXPECT_LE(red, 615.0);
    EXPECT_GE(green, 530.0);
    EXPECT_LE(green, 550.0);
    EXPECT_GE(blue, 440.0);
    EXPECT_LE(blue, 460.0);
    EXPECT_GE(luminance, 550.0);
    EXPECT_LE(luminance, 565.0);
}

TEST(Wavelengths, SamplerMatchesItsPdf) {
    EXPECT_NEAR(integrate(pdf_at, VISIBLE_LAMBDA_MIN, VISIBLE_LAMBDA_MAX), 1.0, 1e-4);
    EXPECT_NEAR(sample_visible_wavelength(0.0f), VISIBLE_LAMBDA_MIN, 0.5);
    EXPECT_NEAR(sample_visible_wavelength(1.0f - 1e-7f), VISIBLE_LAMBDA_MAX, 0.5);
    for (double u = 0.05; u < 1.0; u += 0.1) {
        const double lambda = sample_visible_wavelength(float(u));
        EXPECT_NEAR(integrate(pdf_at, VISIBLE_LAMBDA_MIN, lambda), u, 1e-4) << "u " << u;
    }
}

TEST(Wavelengths, FourAreSpreadAQuarterApartInSampleSpace) {
    const vec4 lambda = sample_wavelengths(0.9f);
    EXPECT_NEAR(lambda.x, sample_visible_wavelength(0.9f), 1e-4);
    EXPECT_NEAR(lambda.y, sample_visible_wavelength(0.15f), 1e-3);
    EXPECT_NEAR(lambda.z, sample_visible_wavelength(0.4f), 1e-3);
    EXPECT_NEAR(lambda.w, sample_visible_wavelength(0.65f), 1e-3);
}

// The estimator the stages use: the mean over paths of integrate_film(upsample_rgb(c)) is c, with all four
// wavelengths and with the hero alone (after a dispersive refraction). Stratified u, so the tolerance is tight.
TEST(Wavelengths, FilmEstimateOfAnUpsampledColourIsTheColour) {
    const vec3 colours[] = {vec3(1.0f), vec3(0.8f, 0.2f, 0.1f), vec3(0.1f, 0.5f, 0.9f), vec3(0.0f, 0.0f, 1.0f),
                            vec3(0.0f, 1.0f, 0.0f), vec3(3.0f, 0.5f, 0.0f)};
    const int n = 1 << 16;
    for (const vec3& c : colours) {
        dvec3 all(0.0), hero(0.0);
        for (int i = 0; i < n; ++i) {
            const SpectralFrame f = make_spectral_frame((float(i) + 0.5f) / float(n));
            const vec4 s = upsample_rgb(f, c);
            all += dvec3(integrate_film(f, s));
            hero += dvec3(integrate_film(f, terminate_secondary_wavelengths(s)));
        }
        all /= double(n);
        hero /= double(n);
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(all[k], c[k], 2e-3 * std::max(1.0f, c[k])) << "colour " << c.x << "," << c.y << "," << c.z;
            EXPECT_NEAR(hero[k], c[k], 2e-3 * std::max(1.0f, c[k])) << "colour " << c.x << "," << c.y << "," << c.z;
        }
    }
}

TEST(Wavelengths, WhiteIsTheConstantSpectrumOne) {
    for (float u : {0.0f, 0.3f, 0.77f}) {
        const vec4 s = upsample_rgb(make_spectral_frame(u), vec3(1.0f));
        for (int k = 0; k < 4; ++k) EXPECT_NEAR(s[k], 1.0f, 1e-6f);
    }
}

// KHR_materials_dispersion: the index is the material's at 587.6 nm and its Abbe number is 20 / dispersion.
TEST(Dispersion, CauchyIndexHasTheAbbeNumber) {
    for (float dispersion : {0.2f, 1.0f, 2.0f})
        for (float ior : {1.33f, 1.5f, 2.4f}) {
            const double d = eval_dispersive_ior(ior, dispersion, 587.6f);
            const double f = eval_dispersive_ior(ior, dispersion, 486.1f);
            const double c = eval_dispersive_ior(ior, dispersion, 656.3f);
            EXPECT_NEAR(d, ior, 1e-5 * ior + 2e-5);
            EXPECT_NEAR((d - 1.0) / (f - c), 20.0 / dispersion, 0.002 * 20.0 / dispersion);
        }
    EXPECT_EQ(eval_dispersive_ior(1.5f, 0.0f, 400.0f), 1.5f);
    EXPECT_GE(eval_dispersive_ior(1.01f, 50.0f, 830.0f), 1.0f);  // clamped at 1, as the extension says
}

// The direction the glass BSDF (sample_bsdf, "smooth" volume glass: GGX of alpha 1e-3) refracts light into, arriving
// at `angle` from the side of eta (the stages pass ior entering, 1 / ior leaving): the sine of its angle to the
// normal, averaged over a grid of samples (the lobe is 0.1 degree wide and centred on the refracted direction).
double refracted_sine(float eta, double angle) {
    const BsdfParams p = with_transmission(make_bsdf_params(fh::test::make_material(vec3(1.0f), 0.0f, 0.0f)), 1.0f,
                                           eta, 0u);
    const vec3 wo(float(std::sin(angle)), 0.0f, float(std::cos(angle)));
    double sum = 0.0;
    int count = 0;
    const int n = 32;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) {
                const vec3 u((i + 0.5f) / n, (j + 0.5f) / n, (k + 0.5f) / n);
                const BsdfSample s = sample_bsdf(p, wo, u);
                if (s.valid == 0u || !(s.wi.z < 0.0f)) continue;
                EXPECT_LT(s.wi.x * wo.x, 0.0f);  // on through, not back
                sum += std::abs(double(s.wi.x));
                ++count;
            }
    EXPECT_GT(count, n * n * n / 2) << "eta " << eta;
    return count > 0 ? sum / count : 0.0;
}

// A 60-degree prism at the incidence of minimum deviation for the d line: the deviation of each wavelength through
// the renderer's refraction (entering with n(lambda), leaving with 1 / n(lambda)) against Snell's law.
TEST(Dispersion, PrismDeviatesEachWavelengthAsSnellSays) {
    const double apex = 60.0 * M_PI / 180.0, ior = 1.5, dispersion = 1.0;
    const double incidence = std::asin(ior * std::sin(apex / 2.0));  // minimum deviation at n_d
    std::printf("prism (60 deg, n_d 1.5, dispersion 1) at %.2f deg incidence:\n", incidence * 180.0 / M_PI);
    double previous = 1e9;
    for (double lambda : {656.3, 587.6, 550.0, 486.1, 420.0}) {
        const double n = eval_dispersive_ior(float(ior), float(dispersion), float(lambda));
        // Snell: in at incidence, across the glass to the second face, out.
        const double inside = std::asin(std::sin(incidence) / n);
        const double second = apex - inside;
        const double expected = incidence + std::asin(n * std::sin(second)) - apex;
        // The BSDF: the same two refractions.
        const double inside_bsdf = std::asin(refracted_sine(float(n), incidence));
        const double out_bsdf = std::asin(refracted_sine(float(1.0 / n), apex - inside_bsdf));
        const double deviation = incidence + out_bsdf - apex;
        std::printf("  %.1f nm: n %.5f, deviation %.4f deg (Snell %.4f)\n", lambda, n, deviation * 180.0 / M_PI,
                    expected * 180.0 / M_PI);
        EXPECT_NEAR(deviation, expected, 1e-4) << lambda << " nm";
        if (previous < 1e9) EXPECT_GT(deviation, previous) << lambda << " nm";  // shorter wavelengths bend more
        previous = deviation;
    }
}

}  // namespace
