// The convergence metrics on synthetic images with known answers: error means, the progressive-film variance
// and bias estimators, log-log slopes and time-to-target interpolation.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "app/converge/converge_metrics.h"

namespace fh {
namespace {

Image constant_image(int w, int h, float v) { return {w, h, std::vector<float>(size_t(3) * w * h, v)}; }

// A progressive film of per-sample values mean + N(0, sigma^2): the running mean after each spp in `spps`.
std::vector<Image> progressive_film(int w, int h, double mean, double sigma, const std::vector<uint32_t>& spps,
                                    uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, sigma);
    std::vector<double> sums(size_t(3) * w * h, 0.0);
    std::vector<Image> images;
    uint32_t done = 0;
    for (uint32_t spp : spps) {
        for (; done < spp; ++done)
            for (double& s : sums) s += mean + noise(rng);
        Image img{w, h, {}};
        for (double s : sums) img.rgb.push_back(float(s / spp));
        images.push_back(img);
    }
    return images;
}

TEST(ConvergeMetrics, ErrorsOfAConstantOffset) {
    Image ref = constant_image(4, 4, 2.0f), x = constant_image(4, 4, 2.5f);
    ImageErrors e = measure_errors(x, ref);
    EXPECT_NEAR(e.mse, 0.25, 1e-12);
    EXPECT_NEAR(e.relmse, 0.25 / (4.0 + REL_EPS), 1e-12);
    EXPECT_NEAR(e.mape, 0.5 / (2.0 + REL_EPS), 1e-12);
    EXPECT_FALSE(e.has_variance);
}

TEST(ConvergeMetrics, NonFiniteValuesAreSkippedAndCounted) {
    Image ref = constant_image(2, 1, 1.0f), x = constant_image(2, 1, 2.0f);
    x.rgb[0] = std::nanf("");
    ImageErrors e = measure_errors(x, ref);
    EXPECT_EQ(e.nonfinite, 1u);
    EXPECT_NEAR(e.mse, 1.0, 1e-12);
}

TEST(ConvergeMetrics, VarianceAndBiasOfAProgressiveFilm) {
    // 64x64 pixels, sigma 1, 64 and 128 spp: Var(x_128) = 1/128. Unbiased: bias^2 ~ 0; offset 0.1: bias^2 ~ 0.01.
    for (double offset : {0.0, 0.1}) {
        std::vector<Image> film = progressive_film(64, 64, 1.0 + offset, 1.0, {64, 128}, 7);
        Image ref = constant_image(64, 64, 1.0f);
        ImageErrors e = measure_errors(film[1], ref, {&film[0], 64, 128});
        ASSERT_TRUE(e.has_variance);
        EXPECT_NEAR(e.variance, 1.0 / 128, 0.05 / 128);
        EXPECT_NEAR(e.bias2, offset * offset, 4 * e.bias2_stderr + 1e-9);
        EXPECT_EQ(offset > 0, e.bias2 > 3 * e.bias2_stderr) << "offset " << offset;
    }
}

TEST(ConvergeMetrics, VarianceFactorForAnUnevenLastStep) {
    // From 64 to 100 spp (a --max-spp that is not a power of two): Var(x_100) = 1/100.
    std::vector<Image> film = progressive_film(64, 64, 1.0, 1.0, {64, 100}, 3);
    EXPECT_NEAR(estimate_variance(film[1], {&film[0], 64, 100}), 0.01, 0.0008);
}

TEST(ConvergeMetrics, TwoSeedsEstimateTheVariance) {
    std::vector<Image> a = progressive_film(64, 64, 1.0, 1.0, {32}, 1), b = progressive_film(64, 64, 1.0, 1.0, {32}, 2);
    EXPECT_NEAR(measure_two_seed_errors(a[0], b[0]).mse, 1.0 / 32, 0.05 / 32);
}

TEST(ConvergeMetrics, LogLogSlope) {
    std::vector<double> x{1, 2, 4, 8}, y{3, 1.5, 0.75, 0.375};
    EXPECT_NEAR(fit_loglog_slope(x, y), -1.0, 1e-12);
    EXPECT_TRUE(std::isnan(fit_loglog_slope({1}, {1})));
}

ConvergeStep step(uint32_t spp, double seconds, double relmse) {
    ConvergeStep s{spp, seconds, {}};
    s.errors.relmse = relmse;
    return s;
}

TEST(ConvergeMetrics, TimeToReachInterpolatesExtrapolatesOrNever) {
    std::vector<ConvergeStep> steps{step(1, 1, 0.1), step(2, 2, 0.05), step(4, 4, 0.025)};
    TargetTime t = time_to_reach(steps, 0, false, 0.07);
    EXPECT_EQ(t.kind, TargetTime::reached);
    EXPECT_NEAR(t.seconds, 0.1 / 0.07, 1e-9);  // on the slope -1 line through the steps
    t = time_to_reach(steps, 0, false, 0.01);
    EXPECT_EQ(t.kind, TargetTime::extrapolated);
    EXPECT_NEAR(t.seconds, 10.0, 1e-9);
    EXPECT_EQ(time_to_reach(steps, 0.02, true, 0.01).kind, TargetTime::never);
    EXPECT_EQ(time_to_reach(steps, 0.02, false, 0.01).kind, TargetTime::extrapolated);  // floor within noise
}

}  // namespace
}  // namespace fh
