// Unit tests of the render-test image checks (tests/render/image_compare.h) on synthetic images.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "image_compare.h"

namespace {

// A smooth 256 x 256 "render": gradients in R and B, constant G, and a black band (rows 0-15) so the
// relative floor for nearly black tiles is exercised too.
fh::Image make_reference() {
    fh::Image image{256, 256, std::vector<float>(256 * 256 * 3)};
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            float* p = &image.rgb[(std::size_t(y) * 256 + x) * 3];
            const float on = y < 16 ? 0.0f : 1.0f;
            p[0] = on * (0.2f + 0.6f * x / 255.0f);
            p[1] = on * 0.5f;
            p[2] = on * (0.1f + 0.3f * y / 255.0f);
        }
    return image;
}

// reference * scale + Gaussian noise with standard deviation `relative_sigma` * value (as Monte Carlo noise
// scales with the signal); black stays black.
fh::Image make_test(const fh::Image& reference, float scale, float relative_sigma, unsigned seed) {
    fh::Image test = reference;
    std::mt19937 random(seed);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    for (float& v : test.rgb) v = v * scale + v * relative_sigma * normal(random);
    return test;
}

void scale_tile(fh::Image& image, int x0, int y0, int size, float factor) {
    for (int y = y0; y < y0 + size; ++y)
        for (int x = x0; x < x0 + size; ++x)
            for (int c = 0; c < 3; ++c) image.rgb[(std::size_t(y) * image.width + x) * 3 + c] *= factor;
}

bool mentions(const fh::CheckResult& result, const std::string& word) {
    for (const auto& failure : result.failures)
        if (failure.find(word) != std::string::npos) return true;
    return false;
}

}  // namespace

TEST(NormalQuantile, KnownValues) {
    EXPECT_NEAR(fh::normal_upper_quantile(0.5), 0.0, 1e-12);
    EXPECT_NEAR(fh::normal_upper_quantile(0.025), 1.959963985, 1e-8);
    EXPECT_NEAR(fh::bonferroni_z_threshold(0.01, 1), 2.575829304, 1e-8);
    EXPECT_NEAR(fh::bonferroni_z_threshold(0.01, 768), 4.359755, 1e-5);  // 256 tiles x 3 channels
    EXPECT_NEAR(fh::normal_upper_quantile(1e-12), 7.0344838253, 1e-8);
}

TEST(CompareToReference, IdenticalImagesPass) {
    const fh::Image reference = make_reference();
    const fh::ReferenceResult result = fh::compare_to_reference(reference, reference);
    EXPECT_TRUE(result.passed()) << result.summary;
    EXPECT_EQ(result.over_rel + result.over_z + result.failing_blocks, 0);
    EXPECT_EQ(result.mean_rel[3], 0.0);
    EXPECT_EQ(result.tiles, 256);
    EXPECT_TRUE(fh::check_identical(reference, reference).passed());
}

TEST(CompareToReference, NoiseWithZeroMeanPasses) {
    // 30% per-pixel noise: a 16x16 tile mean scatters by ~1.9%, so a few tiles exceed 5% by chance alone;
    // the z-score knows they are noise.
    const fh::Image reference = make_reference();
    const fh::ReferenceResult result = fh::compare_to_reference(make_test(reference, 1.0f, 0.3f, 1), reference);
    EXPECT_TRUE(result.passed()) << result.summary;
    EXPECT_GT(result.over_rel, 0) << "relative size alone would have failed: " << result.summary;
    EXPECT_EQ(result.failing_blocks, 0);
}

TEST(CompareToReference, TenPercentBiasedTileFails) {
    const fh::Image reference = make_reference();
    fh::Image test = make_test(reference, 1.0f, 0.02f, 2);
    scale_tile(test, 64, 128, 16, 1.1f);
    const fh::ReferenceResult result = fh::compare_to_reference(test, reference);
    EXPECT_FALSE(result.passed());
    EXPECT_TRUE(mentions(result, "blocks")) << result.summary;
    EXPECT_FALSE(mentions(result, "mean")) << "a single tile barely moves the image mean";
    EXPECT_EQ(result.failing_blocks, 3);  // that tile, all three channels
    EXPECT_EQ(result.worst_rel.x, 64);
    EXPECT_EQ(result.worst_rel.y, 128);
    EXPECT_NEAR(result.worst_rel.rel, 0.1, 0.01);
    ASSERT_EQ(result.difference.rgb.size(), test.rgb.size());
    const std::size_t inside = (std::size_t(130) * 256 + 70) * 3 + 1;
    EXPECT_EQ(result.difference.rgb[inside], test.rgb[inside] - reference.rgb[inside]);
    ASSERT_EQ(result.z_image.rgb.size(), test.rgb.size());
    EXPECT_GT(result.z_image.rgb[inside], result.z_critical);
}

TEST(CompareToReference, OnePercentGlobalBiasFailsTheMeanTest) {
    const fh::Image reference = make_reference();
    const fh::ReferenceResult result = fh::compare_to_reference(make_test(reference, 1.01f, 0.02f, 3), reference);
    EXPECT_FALSE(result.passed());
    EXPECT_TRUE(mentions(result, "mean")) << result.summary;
    EXPECT_EQ(result.failing_blocks, 0) << "1% per tile is below max_block_rel";
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(result.mean_rel[c], 0.01, 0.002) << c;
}

TEST(CompareToReference, SmallNoiselessBiasIsSignificantButNotLargeSoPasses) {
    // Converged images that differ by 2% in one tile: |z| is infinite, but 2% < max_block_rel.
    const fh::Image reference = make_reference();
    fh::Image test = reference;
    scale_tile(test, 32, 32, 16, 1.02f);
    const fh::ReferenceResult result = fh::compare_to_reference(test, reference);
    EXPECT_TRUE(result.passed()) << result.summary;
    EXPECT_EQ(result.over_z, 3);
    EXPECT_EQ(result.over_rel, 0);
}

TEST(CompareToReference, BlackTilesUseTheFloor) {
    // A tiny absolute difference on black reference pixels is 1e-4 / (1e-2 * mean): small, not infinite.
    const fh::Image reference = make_reference();
    fh::Image test = reference;
    for (int x = 0; x < 16; ++x) test.rgb[(std::size_t(0) * 256 + x) * 3 + 1] = 1e-4f * 16;  // tile mean 1e-4
    const fh::ReferenceResult result = fh::compare_to_reference(test, reference);
    EXPECT_TRUE(result.passed()) << result.summary;
    EXPECT_GT(result.worst_rel.rel, 0.0);
    EXPECT_LT(result.worst_rel.rel, 0.05);
}

TEST(CompareToReference, SizeMismatchAndNonFiniteFail) {
    const fh::Image reference = make_reference();
    fh::Image small{16, 16, std::vector<float>(16 * 16 * 3, 0.5f)};
    const fh::ReferenceResult mismatch = fh::compare_to_reference(small, reference);
    EXPECT_FALSE(mismatch.passed());
    EXPECT_TRUE(mentions(mismatch, "size")) << mismatch.summary;
    EXPECT_FALSE(fh::check_identical(small, reference).passed());

    fh::Image test = reference;
    test.rgb[1000] = std::numeric_limits<float>::quiet_NaN();
    const fh::ReferenceResult nan = fh::compare_to_reference(test, reference);
    EXPECT_FALSE(nan.passed());
    EXPECT_TRUE(mentions(nan, "finite")) << nan.summary;
}

TEST(CheckConstant, FurnaceRules) {
    fh::Image image{32, 32, std::vector<float>(32 * 32 * 3, 0.8f)};
    EXPECT_TRUE(fh::check_constant(image, 0.8, 0.01).passed());

    fh::Image spot = image;
    spot.rgb[0] = 0.8f * 1.05f;  // corner pixel 5% off
    const fh::CheckResult spot_result = fh::check_constant(spot, 0.8, 0.01);
    EXPECT_FALSE(spot_result.passed());
    EXPECT_TRUE(mentions(spot_result, "pixels")) << spot_result.summary;
    EXPECT_TRUE(fh::check_constant(spot, 0.8, 0.01, 1).passed()) << "the border is ignored";

    fh::Image shifted = image;
    for (float& v : shifted.rgb) v *= 1.005f;  // every pixel within 1%, but the mean 0.5% off > 0.1%
    const fh::CheckResult shifted_result = fh::check_constant(shifted, 0.8, 0.01);
    EXPECT_FALSE(shifted_result.passed());
    EXPECT_TRUE(mentions(shifted_result, "mean")) << shifted_result.summary;
    EXPECT_FALSE(mentions(shifted_result, "pixels"));

    fh::Image black{4, 4, std::vector<float>(4 * 4 * 3, 0.0f)};
    EXPECT_TRUE(fh::check_constant(black, 0.0, 0.01).passed());
    black.rgb[5] = 0.02f;
    EXPECT_FALSE(fh::check_constant(black, 0.0, 0.01).passed());
    EXPECT_FALSE(fh::check_constant(black, 0.0, 0.01, 2).passed()) << "nothing left inside the border";
}

TEST(CheckIdentical, ReportsTheFirstDifferingPixel) {
    const fh::Image reference = make_reference();
    fh::Image other = reference;
    other.rgb[(std::size_t(7) * 256 + 3) * 3 + 2] = std::nextafter(other.rgb[(std::size_t(7) * 256 + 3) * 3 + 2], 1.0f);
    const fh::CheckResult result = fh::check_identical(other, reference);
    EXPECT_FALSE(result.passed());
    ASSERT_EQ(result.failures.size(), 1u);
    EXPECT_NE(result.failures[0].find("(3,7) B"), std::string::npos) << result.failures[0];
}

TEST(CheckFinite, FindsInfinity) {
    fh::Image image = make_reference();
    EXPECT_TRUE(fh::check_finite(image).passed());
    image.rgb[(std::size_t(9) * 256 + 4) * 3] = std::numeric_limits<float>::infinity();
    const fh::CheckResult result = fh::check_finite(image);
    EXPECT_FALSE(result.passed());
    EXPECT_NE(result.failures[0].find("(4,9) R"), std::string::npos) << result.failures[0];
    EXPECT_EQ(result.difference.rgb[(std::size_t(9) * 256 + 4) * 3], 1.0f);
}

// ---- compare_distributions: the per-pixel Welch t test of the stability suite ---------------------------

TEST(DistributionCompare, StudentTailMatchesKnownValues) {
    EXPECT_NEAR(fh::student_t_two_sided_p(2.228, 10.0), 0.05, 2e-4);   // t table: 97.5% quantile, 10 dof
    EXPECT_NEAR(fh::student_t_two_sided_p(12.706, 1.0), 0.05, 2e-4);   // 1 dof
    EXPECT_NEAR(fh::student_t_two_sided_p(0.0, 5.0), 1.0, 1e-12);
    EXPECT_NEAR(fh::student_t_two_sided_p(3.0, 1e6), std::erfc(3.0 / std::sqrt(2.0)), 1e-5);  // normal limit
}

namespace {
// K noisy batches of a 32x32 image whose every pixel has expected value `mean` (Gaussian noise, sd 0.1).
std::vector<fh::Image> make_batches(int k, double mean, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0.0f, 0.1f);
    std::vector<fh::Image> out;
    for (int b = 0; b < k; ++b) {
        fh::Image image{32, 32, std::vector<float>(32 * 32 * 3)};
        for (float& v : image.rgb) v = float(mean) + noise(rng);
        out.push_back(image);
    }
    return out;
}
}  // namespace

TEST(DistributionCompare, PassesSameMeansAndFailsAShiftedPixel) {
    const auto a = make_batches(8, 1.0, 1), b = make_batches(8, 1.0, 2);
    EXPECT_TRUE(fh::compare_distributions(a, b).passed());
    auto shifted = make_batches(8, 1.0, 3);
    for (fh::Image& image : shifted) image.rgb[3 * 100 + 1] += 0.5f;  // one pixel, green, 5 sigma of a batch
    const fh::DistributionResult r = fh::compare_distributions(shifted, b);
    EXPECT_FALSE(r.passed()) << r.summary;
    EXPECT_EQ(r.worst_index, size_t(3 * 100 + 1));
}
