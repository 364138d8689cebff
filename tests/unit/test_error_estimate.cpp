// The error estimate's batches (engine/render/error_estimate.h): the batch size grows so a render keeps 3 to 6 complete
// batches, a render split into parts joins to the same sums bit for bit, and the variance of the mean it reports is
// right for independent samples.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "render/error_estimate.h"

namespace {

using fh::ErrorBatches;
using fh::ExactSum;

// A luminance value as the film's exact sum would hold it (radiance x 2^56 x 10^4).
ExactSum exact(double luminance) {
    return ExactSum(__int128(std::ldexp(luminance, fh::gpu::FILM_FRACTION_BITS))) * 10000;
}

// Sample i of pixel p: a made-up value, negative now and then (two's complement must join exactly too).
ExactSum sample_value(size_t p, uint32_t i) { return exact(std::sin(0.37 * i + 1.3 * p) * (1 + p) + 0.25); }

// Samples [first, end) added one at a time, as the render loop does: coarsened before a batch would not fit.
ErrorBatches render_samples(size_t pixels, uint32_t first, uint32_t end) {
    ErrorBatches b = fh::make_error_batches(pixels, first);
    for (uint32_t s = first; s < end; ++s) {
        const uint32_t size = fh::batch_size_for(b.first_sample, s + 1);
        if (size > b.batch_size) fh::coarsen(b, size);
        std::vector<ExactSum> added(pixels);
        for (size_t p = 0; p < pixels; ++p) added[p] = sample_value(p, s);
        fh::add_samples(b, s, s + 1, added);
    }
    return b;
}

TEST(ErrorEstimate, BatchSizeKeepsAtMostSixBatches) {
    EXPECT_EQ(fh::MAX_ERROR_BATCHES, 6u);
    EXPECT_EQ(fh::batch_size_for(0, 6), 1u);
    EXPECT_EQ(fh::batch_size_for(0, 7), 2u);
    EXPECT_EQ(fh::batch_size_for(0, 48), 8u);
    EXPECT_EQ(fh::batch_size_for(0, 49), 16u);
    EXPECT_EQ(fh::batch_size_for(5, 9), 1u);
    EXPECT_EQ(fh::batch_size_for(3, 12), 2u);  // batches 1..5 of 2
    for (uint32_t n = 6; n < 5000; n += 37) {
        const ErrorBatches b = render_samples(1, 0, n);
        EXPECT_LE(b.slot_count(), fh::MAX_ERROR_BATCHES) << n;
        EXPECT_GE(fh::complete_batch_count(b), 3u) << n;
    }
}

TEST(ErrorEstimate, PartsJoinToTheWholeRenderBitForBit) {
    const size_t pixels = 5;
    const ErrorBatches whole = render_samples(pixels, 0, 77);
    ErrorBatches joined = fh::make_joined_batches(pixels, 0, 77);
    std::vector<size_t> same(pixels);
    for (size_t p = 0; p < pixels; ++p) same[p] = p;
    for (auto [a, b] : {std::pair{30u, 31u}, {0u, 13u}, {31u, 77u}, {13u, 30u}}) fh::add_part(joined, render_samples(pixels, a, b), same);
    EXPECT_EQ(joined.batch_size, whole.batch_size);
    EXPECT_EQ(joined.first_batch, whole.first_batch);
    EXPECT_EQ(joined.slot_count(), whole.slot_count());
    EXPECT_TRUE(joined.sums == whole.sums);
    const std::vector<float> vw = fh::pixel_variance(whole), vj = fh::pixel_variance(joined);
    EXPECT_EQ(std::memcmp(vw.data(), vj.data(), vw.size() * sizeof(float)), 0);
    // A part left out changes the sums.
    ErrorBatches missing = fh::make_joined_batches(pixels, 0, 77);
    for (auto [a, b] : {std::pair{0u, 13u}, {31u, 77u}, {13u, 30u}}) fh::add_part(missing, render_samples(pixels, a, b), same);
    EXPECT_FALSE(missing.sums == whole.sums);
}

TEST(ErrorEstimate, RefusesSamplesThatDoNotContinueTheBatches) {
    ErrorBatches b = fh::make_error_batches(2, 0);
    const std::vector<ExactSum> added(2, exact(1.0));
    EXPECT_THROW(fh::add_samples(b, 1, 2, added), std::logic_error);  // a gap
    EXPECT_THROW(fh::add_samples(b, 0, 2, added), std::logic_error);  // two batches of size 1 at once
    EXPECT_THROW(fh::coarsen(b, 3), std::logic_error);
}

// Independent samples of known variance: the reported variance of each pixel's mean averages to sigma^2 / N.
TEST(ErrorEstimate, VarianceOfTheMeanOfIndependentSamples) {
    const size_t pixels = 20000;
    const uint32_t samples = 104;  // batches of 32: 3 complete, one partial
    std::mt19937_64 rng(7);
    std::normal_distribution<double> normal(2.0, 0.5);
    ErrorBatches b = fh::make_error_batches(pixels, 0);
    for (uint32_t s = 0; s < samples; ++s) {
        const uint32_t size = fh::batch_size_for(0, s + 1);
        if (size > b.batch_size) fh::coarsen(b, size);
        std::vector<ExactSum> added(pixels);
        for (ExactSum& a : added) a = exact(normal(rng));
        fh::add_samples(b, s, s + 1, added);
    }
    EXPECT_EQ(fh::complete_batch_count(b), 3u);
    const std::vector<float> variance = fh::pixel_variance(b);
    double mean = 0;
    for (float v : variance) mean += v / double(pixels);
    const double expected = 0.25 / samples;
    std::printf("[error estimate] mean variance of the mean %.4e, expected %.4e\n", mean, expected);
    EXPECT_NEAR(mean, expected, 0.03 * expected);  // 20000 pixels x 2 degrees of freedom: about 0.7% noise
    // The image's relative error of pixels that all read 2 (luminance): sqrt(var / (4 + 0.01)).
    fh::Image image;
    image.width = int(pixels), image.height = 1;
    image.rgb.assign(3 * pixels, 2.0f);
    EXPECT_NEAR(fh::relative_error(image, variance), std::sqrt(expected / 4.01), 0.02 * std::sqrt(expected / 4.01));
}

TEST(ErrorEstimate, UnknownBelowTwoCompleteBatches) {
    const ErrorBatches one = render_samples(3, 0, 1);
    EXPECT_TRUE(std::isnan(fh::pixel_variance(one)[0]));
    const ErrorBatches two = render_samples(3, 0, 2);
    EXPECT_FALSE(std::isnan(fh::pixel_variance(two)[0]));
}

}  // namespace
