// The statistics of `fredholm compare` (engine/app/compare/noise_test.h) on synthetic images: the quantiles against
// tabulated values, the false-alarm rate on pure noise of known variance, and the power on a shift of one tile.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "app/compare/noise_test.h"

namespace {

TEST(NoiseTest, QuantilesMatchTables) {
    EXPECT_NEAR(fh::normal_upper_quantile(0.025), 1.959964, 1e-5);
    EXPECT_NEAR(fh::normal_upper_quantile(1e-6), 4.753424, 1e-5);
    EXPECT_NEAR(fh::student_t_upper_quantile(0.025, 10), 2.228139, 1e-5);
    EXPECT_NEAR(fh::student_t_upper_quantile(0.005, 3), 5.840909, 1e-5);
    EXPECT_NEAR(fh::student_t_upper_quantile(0.05, 1), 6.313752, 1e-5);
    EXPECT_NEAR(fh::student_t_upper_tail(2.0, 5), 0.050970, 1e-6);
}

// Two images of Gaussian noise around the same mean, each with its exact variance and 5 degrees of freedom.
fh::NoisyImage noisy(std::mt19937_64& rng, int size, double mean, double sigma) {
    fh::NoisyImage n;
    n.image.width = n.image.height = size;
    n.image.rgb.resize(3 * size_t(size) * size);
    n.variance.assign(size_t(size) * size, float(sigma * sigma));
    n.degrees_of_freedom = 5;
    std::normal_distribution<double> normal(0, sigma);
    for (size_t p = 0; p < n.variance.size(); ++p) {
        const float v = float(mean + normal(rng));
        n.image.rgb[3 * p] = n.image.rgb[3 * p + 1] = n.image.rgb[3 * p + 2] = v;
    }
    return n;
}

TEST(NoiseTest, FalseAlarmsStayBelowAlpha) {
    std::mt19937_64 rng(11);
    int differs = 0;
    const int trials = 400;
    for (int i = 0; i < trials; ++i) differs += fh::compare_images(noisy(rng, 64, 0.5, 0.05), noisy(rng, 64, 0.5, 0.05),
                                                                   {0.05, 16, 0.02}).differs;
    std::printf("[noise test] %d of %d pairs of pure noise called different at alpha 0.05\n", differs, trials);
    EXPECT_LE(differs, 30);  // 20 expected at most; 31 or more has a chance below 1% at a rate of 0.05
}

TEST(NoiseTest, FindsAShiftOfOneTile) {
    std::mt19937_64 rng(14);
    fh::NoisyImage a = noisy(rng, 64, 0.5, 0.05), b = noisy(rng, 64, 0.5, 0.05);
    // 8% up in the tile at 16..31 x 32..47: 0.57 sigma of the difference per pixel, 9 sigma over the tile's 256.
    for (int y = 32; y < 48; ++y)
        for (int x = 16; x < 32; ++x)
            for (int c = 0; c < 3; ++c) b.image.rgb[3 * (size_t(y) * 64 + x) + c] += 0.04f;
    const fh::CompareResult r = fh::compare_images(a, b, {0.01, 16, 0.02});
    EXPECT_TRUE(r.differs);
    ASSERT_FALSE(r.worst.empty());
    EXPECT_EQ(r.worst[0].x0, 16);
    EXPECT_EQ(r.worst[0].y0, 32);
    EXPECT_GE(r.significant_tiles, 1u);
}

TEST(NoiseTest, RefusesImagesOfDifferentSizes) {
    std::mt19937_64 rng(13);
    EXPECT_THROW(fh::compare_images(noisy(rng, 8, 0.5, 0.1), noisy(rng, 16, 0.5, 0.1), {}), std::invalid_argument);
}

}  // namespace
